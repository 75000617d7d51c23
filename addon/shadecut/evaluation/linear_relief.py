"""A linear reading of a material's relief (issue 46): Pentland's linear shape from shading beside the
graph cut's reading, on the photograph and on the true shading.

A relief is nearly flat, so its Lambertian shading is nearly linear in the depth's gradient: with
p = dz/dx and q = dz/dy (x to the right, y up, ``normals_from_depth``'s convention) and the unit light
S, the brightness over the albedo is I = (S_z - p S_x - q S_y) / sqrt(1 + p^2 + q^2), so the slope
along the light's image direction is known at every pixel:

    p S_x + q S_y = S_z - I sqrt(1 + p^2 + q^2).

Pentland (1990) solves the first-order form of it (the square root taken as 1) in the Fourier domain.
Here it is solved in the least-squares sense with ``smoothness`` times |grad z|^2, by one FFT of the
frame padded with flat ground (the slope 0), and the square root is then taken from the previous
solution ``iterations`` times. Slopes across the light's direction are what one image leaves open:
the smoothness keeps them at the least that explains it.

The smoothness is chosen by the one documented procedure of the materials evaluation: the value of
least mean error over the training half's renders, each input (the photograph, the true shading) its
own, applied to the test half.
"""

from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from .. import angular_error, normals_from_depth
from ..imaging import luminance
from ..materials import TEST, TRAINING
from .materials import default_lights, flat_normals, load_half, renders, true_shading

# |grad z|^2 weights tried, against the slope along the light's direction (a ratio of two squared
# slopes, so the same at every resolution).
SMOOTHNESSES = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0)
ITERATIONS = 3
INPUTS = ("photograph", "true shading")


def _central_difference_symbols(rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    """The Fourier symbols of d/dx and d/dy (y up) by central differences on a rows x cols grid."""
    across = 2.0 * np.pi * np.fft.fftfreq(cols)[None, :]
    down = 2.0 * np.pi * np.fft.fftfreq(rows)[:, None]
    return 1j * np.sin(across), -1j * np.sin(down)


def _solve_slope_along_light(slope: np.ndarray, light_xy: np.ndarray, smoothness: float, pad: int) -> np.ndarray:
    """The depth z of least |S_xy . grad z - slope|^2 + smoothness |grad z|^2 over the frame padded by
    ``pad`` pixels of slope 0; the slope's mean (a tilt of the whole frame) is left out."""
    rows, cols = slope.shape
    padded = np.pad(slope - slope.mean(), pad)
    d_dx, d_dy = _central_difference_symbols(*padded.shape)
    along = light_xy[0] * d_dx + light_xy[1] * d_dy
    gradient_power = np.abs(d_dx) ** 2 + np.abs(d_dy) ** 2
    denominator = np.abs(along) ** 2 + smoothness * gradient_power
    denominator[0, 0] = 1.0  # the mean depth: no slope fixes it
    spectrum = np.fft.fft2(padded) * np.conj(along) / denominator
    return np.real(np.fft.ifft2(spectrum))[pad:pad + rows, pad:pad + cols]


def linear_shape_from_shading(shading: np.ndarray, light: Sequence[float], smoothness: float,
                              iterations: int = ITERATIONS) -> np.ndarray:
    """(H, W) depth in pixel units (larger = closer, mean 0) of a relief from its shading.

    Args:
        shading: (H, W) brightness over the albedo, finite; a relief's mean shading is about S_z.
        light: the direction toward the light (any length), S_z > 0.
        smoothness: > 0, the weight of |grad z|^2 (see the module).
        iterations: >= 0 times the square root sqrt(1 + p^2 + q^2) is taken from the last solution.
    """
    shading = np.asarray(shading, dtype=np.float64)
    light = np.asarray(light, dtype=np.float64) / np.linalg.norm(light)
    if shading.ndim != 2 or not np.all(np.isfinite(shading)):
        raise ValueError("shadecut: the shading must be a finite (H, W) array")
    if not light[2] > 0 or not smoothness > 0 or iterations < 0:
        raise ValueError("shadecut: the light must face the viewer, the smoothness be > 0 and iterations >= 0")
    pad = max(shading.shape) // 8
    depth = _solve_slope_along_light(light[2] - shading, light[:2], smoothness, pad)
    for _ in range(iterations):
        p = np.gradient(depth, axis=1)
        q = -np.gradient(depth, axis=0)
        depth = _solve_slope_along_light(light[2] - shading * np.sqrt(1.0 + p * p + q * q), light[:2], smoothness, pad)
    return depth - depth.mean()


def photograph_shading(photograph: np.ndarray, light: Sequence[float]) -> np.ndarray:
    """The photograph read as the shading of one albedo: its luminance scaled so that its median pixel
    has the flat ground's shading S_z (a relief is flat on the whole)."""
    grey = luminance(photograph)
    light = np.asarray(light, dtype=np.float64) / np.linalg.norm(light)
    return grey * (light[2] / max(float(np.median(grey)), 1e-12))


def linear_errors(photograph: np.ndarray, shading: np.ndarray, light: np.ndarray, truth: np.ndarray) -> dict:
    """Per input of :data:`INPUTS`, the mean angular error (degrees) at each of :data:`SMOOTHNESSES`."""
    mask = np.ones(truth.shape[:2], bool)
    readings = {"photograph": photograph_shading(photograph, light), "true shading": shading}
    return {name: np.array([angular_error(normals_from_depth(linear_shape_from_shading(image, light, w).astype(np.float32),
                                                             mask), truth) for w in SMOOTHNESSES])
            for name, image in readings.items()}


def half_errors(folder: os.PathLike | str, names: Sequence[str], lights: np.ndarray) -> dict:
    """Per input, a (renders, len(SMOOTHNESSES)) array of errors, and "flat": (renders,)."""
    per_input: dict = {name: [] for name in INPUTS}
    flat = []
    for material in load_half(folder, names):
        for light, photograph in renders(material, lights):
            for name, errors in linear_errors(photograph, true_shading(material, photograph), light, material.normals).items():
                per_input[name].append(errors)
            flat.append(angular_error(flat_normals(photograph.shape), material.normals))
    return {**{name: np.array(rows) for name, rows in per_input.items()}, "flat": np.array(flat)}


def evaluate_linear_relief(folder: os.PathLike | str) -> dict:
    """The training curves, the smoothness each input's curve chooses, and the test half's errors at it
    (mean, per render, renders below flat), under the materials evaluation's four lights."""
    lights = default_lights()
    training = half_errors(folder, TRAINING, lights)
    test = half_errors(folder, TEST, lights)
    result = {"flat": float(test["flat"].mean()), "renders": len(test["flat"]), "inputs": {}}
    for name in INPUTS:
        curve = training[name].mean(axis=0)
        chosen = int(np.argmin(curve))
        errors = test[name][:, chosen]
        result["inputs"][name] = {"training_curve": curve.tolist(), "smoothness": SMOOTHNESSES[chosen],
                                  "mean_deg": float(errors.mean()), "per_render": errors.tolist(),
                                  "below_flat": int(np.sum(errors < test["flat"]))}
    return result
