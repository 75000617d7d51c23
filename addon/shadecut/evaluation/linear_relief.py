"""A linear reading of a material's relief (issue 46): ShadeCut's ``method="pentland"`` (Pentland's
linear shape from shading, made a least-squares fit: docs/comparison_methods.md) on the scanned
materials, on the photograph and, as an oracle, on the true shading (the photograph over the true
albedo), beside flat.

Each reading is ``shadecut.reconstruct(image, light, scene="relief", method="pentland",
smoothness=w)`` with the true light (and, for the photograph, also with the light estimated:
``light=None``), ``albedo=1`` for the true shading, every other option default. Each
input's smoothness w is chosen by the one documented procedure of the materials evaluation: the value
of :data:`SMOOTHNESSES` of least mean error over the training half's renders, applied to the test half.
"""

from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from .. import angular_error, reconstruct
from ..materials import TEST, TRAINING
from .materials import default_lights, flat_normals, load_half, renders, true_shading

# The weights of |grad z|^2 tried, against the slope along the light's direction (a ratio of two
# squared slopes, the same at every resolution).
SMOOTHNESSES = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0)
INPUTS = ("photograph", "photograph, light estimated", "true shading")


def linear_errors(photograph: np.ndarray, shading: np.ndarray, light: np.ndarray, truth: np.ndarray) -> dict:
    """Per input of :data:`INPUTS`, the mean angular error (degrees) at each of :data:`SMOOTHNESSES`."""
    readings = {"photograph": (photograph, light, {}), "photograph, light estimated": (photograph, None, {}),
                "true shading": (shading, light, {"albedo": 1.0})}
    return {name: np.array([angular_error(reconstruct(image, given, scene="relief", method="pentland", smoothness=w,
                                                      **albedo).normals, truth) for w in SMOOTHNESSES])
            for name, (image, given, albedo) in readings.items()}


def half_errors(folder: os.PathLike | str, names: Sequence[str], lights: np.ndarray, cast_shadows: bool = False) -> dict:
    """Per input, a (renders, len(SMOOTHNESSES)) array of errors, and "flat": (renders,); the renders
    as ``materials.renders`` makes them."""
    per_input: dict = {name: [] for name in INPUTS}
    flat = []
    for material in load_half(folder, names):
        for light, photograph in renders(material, lights, cast_shadows):
            for name, errors in linear_errors(photograph, true_shading(material, photograph), light, material.normals).items():
                per_input[name].append(errors)
            flat.append(angular_error(flat_normals(photograph.shape), material.normals))
    return {**{name: np.array(rows) for name, rows in per_input.items()}, "flat": np.array(flat)}


def evaluate_linear_relief(folder: os.PathLike | str, cast_shadows: bool = False) -> dict:
    """The training curves, the smoothness each input's curve chooses, and the test half's errors at it
    (mean, per render, renders below flat), under the materials evaluation's four lights; both halves
    rendered with ``cast_shadows`` or without."""
    lights = default_lights()
    training = half_errors(folder, TRAINING, lights, cast_shadows)
    test = half_errors(folder, TEST, lights, cast_shadows)
    result = {"flat": float(test["flat"].mean()), "renders": len(test["flat"]), "inputs": {}}
    for name in INPUTS:
        curve = training[name].mean(axis=0)
        chosen = int(np.argmin(curve))
        errors = test[name][:, chosen]
        result["inputs"][name] = {"training_curve": curve.tolist(), "smoothness": SMOOTHNESSES[chosen],
                                  "mean_deg": float(errors.mean()), "per_render": errors.tolist(),
                                  "below_flat": int(np.sum(errors < test["flat"]))}
    return result
