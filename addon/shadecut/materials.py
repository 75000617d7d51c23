"""Scanned material sets (a surface's colour, measured normal map and height, as ambientCG publishes
them; ../shared/data/materials) read in ShadeCut's camera frame, and the one split of them into a
training half, for choosing parameters, and a test half, for acceptance (docs/datasets_and_evaluation.md,
"Scanned materials")."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence, Union

import numpy as np

from . import dataset_files
from .api import integrate
from .imaging import srgb_to_linear
from .synthetic_reliefs import cast_shadows as shadow_mask

TRAINING = ("Bark014", "Ground059", "Metal007", "PavingStones134", "WoodSiding005")
TEST = ("Bricks061", "Fabric048", "Leather037", "PaintedPlaster009", "Rock029")


@dataclass
class Material:
    """One scanned patch of surface, seen from straight above."""

    name: str
    albedo: np.ndarray  # (H, W, 3) float32 linear RGB, the de-lit base colour
    normals: np.ndarray  # (H, W, 3) float32 unit vectors, camera frame (x right, y up, z toward the viewer)
    height: np.ndarray  # (H, W) float32 in [0, 1], brighter = higher, at the source's own arbitrary scale


def _decoded_normals(codes: np.ndarray, path: Path) -> np.ndarray:
    """OpenGL normal-map codes in [0, 1] as unit vectors; ValueError for a map that holds no direction."""
    normals = codes[..., :3].astype(np.float64) * 2.0 - 1.0
    length = np.linalg.norm(normals, axis=-1, keepdims=True)
    if not (length > 0.5).all():
        raise ValueError(f"shadecut: {path} holds pixels that are no normal (length {length.min():.2f} after "
                         "decoding); a normal map in the OpenGL convention was expected")
    return (normals / length).astype(np.float32)


def load_material(folder: Union[os.PathLike, str]) -> Material:
    """The material in ``folder`` (color.png, normal_gl.png, displacement.png of one size); ValueError
    naming the file that is missing or of another size."""
    folder = Path(folder)
    maps = {}
    for name in ("color.png", "normal_gl.png", "displacement.png"):
        if not (folder / name).is_file():
            raise ValueError(f"shadecut: {folder} has no {name}; a material folder holds color.png, "
                             "normal_gl.png and displacement.png")
        maps[name] = dataset_files.read_image_channels(folder / name)[0]
    shape = maps["color.png"].shape[:2]
    for name, pixels in maps.items():
        if pixels.shape[:2] != shape:
            raise ValueError(f"shadecut: {folder / name} is {pixels.shape[1]} x {pixels.shape[0]} pixels but "
                             f"color.png is {shape[1]} x {shape[0]}")
    colour = maps["color.png"]
    colour = colour[..., :3] if colour.shape[-1] >= 3 else np.repeat(colour[..., :1], 3, axis=-1)
    return Material(name=folder.name, albedo=srgb_to_linear(colour).astype(np.float32),
                    normals=_decoded_normals(maps["normal_gl.png"], folder / "normal_gl.png"),
                    height=maps["displacement.png"][..., 0].astype(np.float32))


def lights_around(count: int, slant_degrees: float) -> np.ndarray:
    """(count, 3) unit directions at one slant from the viewer, evenly around it, the first from the
    top and the next counter-clockwise (from the left): a multi-angle capture's lights."""
    slant = np.radians(slant_degrees)
    azimuth = np.radians(90.0 + 360.0 * np.arange(count) / count)
    return np.stack([np.sin(slant) * np.cos(azimuth), np.sin(slant) * np.sin(azimuth),
                     np.full(count, np.cos(slant))], axis=1)


def at_one_slant(lights: np.ndarray, slant_degrees: float) -> np.ndarray:
    """(K, 3) unit directions with the azimuths of ``lights`` (K x 3, camera frame) around the viewer,
    every one at ``slant_degrees`` from it: what lights at one slant, the estimator's hint, can be."""
    azimuth, slant = np.arctan2(lights[:, 1], lights[:, 0]), np.radians(slant_degrees)
    return np.stack([np.sin(slant) * np.cos(azimuth), np.sin(slant) * np.sin(azimuth),
                     np.full(len(lights), np.cos(slant))], axis=1)


def lambertian_photographs(material: Material, lights: Sequence[Sequence[float]],
                           cast_shadows: bool = False) -> list[np.ndarray]:
    """(H, W, 3) float32 linear photographs of ``material`` under each distant light (K x 3, camera
    frame, any length): albedo x max(n . l, 0), no bounce. With ``cast_shadows``, black where the
    surface shades itself: the surface is the normal map integrated (pixel units, so its slopes are
    the measured ones), and a pixel is dark where its ray toward the light passes below it."""
    depth = integrate(material.normals) if cast_shadows else None
    photographs = []
    for light in np.asarray(lights, dtype=np.float64):
        shading = np.clip(material.normals @ (light / np.linalg.norm(light)), 0.0, None)
        if depth is not None:
            shading[shadow_mask(depth, light)] = 0.0
        photographs.append((material.albedo * shading[..., None]).astype(np.float32))
    return photographs
