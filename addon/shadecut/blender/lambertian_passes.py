"""Cycles' passes of a Lambertian render (see :mod:`.lambertian`) assembled into the image and its
ground truth in the project's conventions: :class:`LambertianRender`."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import bpy
import numpy as np
from mathutils import Matrix

from ..api import LUMINANCE_WEIGHTS
from .lambertian_scene import RenderError

# Blender's scene-linear primaries are Rec. 709's: a render's grey is what reconstruct() reads from it.
LUMINANCE = np.array(LUMINANCE_WEIGHTS)
SHADOW_RATIO = 0.5  # a lit-facing pixel is in cast shadow when its direct light is below this share
MIN_SHADOW_COSINE = 0.02  # below this S . N the pixel is (nearly) in attached shadow, not cast


@dataclass
class LambertianRender:
    """One render and its ground truth, arrays in the project's conventions (row 0 at the top)."""

    image: np.ndarray  # (H, W) float32 linear, after the optional noise and quantization
    clean_image: np.ndarray  # (H, W) float32 linear, Cycles' render before noise and quantization
    normals: np.ndarray  # (H, W, 3) float32 camera frame, unit, 0 outside the mask
    depth: np.ndarray  # (H, W) float32 camera-frame z in scene units (larger = closer), 0 outside the mask
    mask: np.ndarray  # (H, W) bool
    light: np.ndarray  # (3,) unit vector toward the light, camera frame
    albedo: float  # the uniform albedo, or the mean of albedo_map over the mask
    meta: dict = field(default_factory=dict)
    shadow_mask: Optional[np.ndarray] = None  # (H, W) bool, with cast shadows on
    albedo_map: Optional[np.ndarray] = None  # (H, W) float32, with the objects' own colours

    @property
    def depth_pixels(self) -> np.ndarray:
        """Depth in pixel units (z / pixel_size), 0 outside the mask."""
        return np.where(self.mask, self.depth / np.float32(self.meta["pixel_size"]), 0).astype(np.float32)

    def write(self, folder) -> None:
        """Writes the sample folder (image.exr/.png, normals.exr, depth.exr, mask.png, meta.json)."""
        _dataset().write_sample(folder, image=self.image, normals=self.normals, depth=self.depth, mask=self.mask,
                                light=self.light, albedo=self.albedo, meta=self.meta, shadow_mask=self.shadow_mask,
                                albedo_map=self.albedo_map)


@functools.cache  # asked at every redraw of the panel
def files_unavailable() -> Optional[str]:
    """Why test images cannot be rendered here, or None. Their files go through OpenImageIO (its
    Python module and shadecut._imageio): there in Debian's Blender with a source build, not in the
    add-on's zip (docs/portable_addon.md)."""
    try:
        from .. import _imageio, dataset  # noqa: F401  (that they import is what is asked)
    except ImportError as error:
        return f"Rendering test images needs OpenImageIO, which this installation lacks ({error})"
    return None


def _dataset():
    """shadecut.dataset, or RenderError saying why it cannot be used here."""
    reason = files_unavailable()
    if reason:
        raise RenderError(reason)
    from .. import dataset

    return dataset


def read_passes(path: Path) -> dict:
    """The multilayer EXR Cycles wrote, as {"Combined.R": (H, W) array, ...}, row 0 at the top."""
    dataset = _dataset()
    try:
        pixels, names = dataset.read_image_channels(path)
    except OSError as error:
        raise RenderError(f"Cycles wrote no readable image: {error}") from error
    # Channels are named "<view layer>.<pass>.<channel>"; drop the view layer.
    return {name.split(".", 1)[1]: pixels[..., i] for i, name in enumerate(names)}


def _quantize(image: np.ndarray, bits: int) -> np.ndarray:
    """Rounds to ``bits``-bit sRGB codes (as an 8/16-bit PNG stores them) and back to linear."""
    levels = 2**bits - 1
    value = np.clip(image, 0.0, 1.0)
    encoded = np.where(value <= 0.0031308, 12.92 * value, 1.055 * value ** (1 / 2.4) - 0.055)
    encoded = np.round(encoded * levels) / levels
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def assemble(passes, light_vector, camera_matrix, lens, resolution, albedo, shadows, indirect, noise, bits, seed,
              samples, frame, object_names) -> LambertianRender:
    """Turns Cycles' passes into the arrays and meta of a :class:`LambertianRender`."""
    width, height = resolution
    mask, clean, normals, depth = _camera_frame_truth(passes, camera_matrix)
    albedo_map, albedo_value = _albedo(passes, mask, albedo)
    shadow_mask = _cast_shadows(passes, mask, normals, light_vector) if shadows else None
    image = _degrade(clean, noise, bits, seed)
    camera = dict(lens, matrix_world=[list(row) for row in camera_matrix])
    pixel_size = _pixel_size(camera, depth, mask)
    meta = {
        "source": "blender_cycles",
        "blender_version": bpy.app.version_string,
        "objects": object_names,
        "frame": frame,
        "light": light_vector.tolist(),
        "light_slant_deg": math.degrees(math.acos(min(1.0, light_vector[2]))),
        "light_tilt_deg": math.degrees(math.atan2(light_vector[1], light_vector[0])) % 360,
        "albedo": albedo_value,
        "albedo_mode": "uniform" if albedo is not None else "own_colours",
        "resolution": [width, height],
        "camera": camera,
        "pixel_size": pixel_size,
        "shadows": shadows,
        "indirect": indirect,
        "noise_sigma": noise,
        "quantization_bits": bits,
        "seed": seed,
        "samples": samples,
        "pixel_filter": "box 0.01 px (samples at pixel centres)",
    }
    if camera["type"] == "perspective":
        meta["pixel_size_note"] = "perspective camera: pixel size at the objects' median distance"
    return LambertianRender(image=image, clean_image=clean, normals=normals, depth=depth,
                            mask=mask, light=light_vector, albedo=albedo_value, meta=meta, shadow_mask=shadow_mask,
                            albedo_map=albedo_map)


# The names Cycles gives a pass in the EXR, by Blender version: short before 5.0, spelt out since.
PASS_NAMES = {"DiffCol": ("DiffCol", "Diffuse Color"), "DiffDir": ("DiffDir", "Diffuse Direct")}


def _channels(passes: dict, name: str, channels: str) -> np.ndarray:
    """One pass as an (H, W, len(channels)) array, e.g. ``_channels(passes, "Normal", "XYZ")``."""
    for spelling in PASS_NAMES.get(name, (name,)):
        if f"{spelling}.{channels[0]}" in passes:
            return np.dstack([passes[f"{spelling}.{c}"] for c in channels])
    raise RenderError(f"Cycles wrote no {' or '.join(PASS_NAMES.get(name, (name,)))} pass "
                      f"(the file has {sorted({key.rsplit('.', 1)[0] for key in passes})})")


def _camera_frame_truth(passes: dict, camera_matrix: Matrix) -> tuple[np.ndarray, ...]:
    """The mask, the clean image, and the normals and depth in the camera frame, 0 outside the mask."""
    rotation = np.array(camera_matrix.to_3x3().normalized())
    origin = np.array(camera_matrix.translation)
    mask = passes["Combined.A"] > 0.5
    clean = (_channels(passes, "Combined", "RGB") @ LUMINANCE).astype(np.float32)

    # World to camera frame: v_cam = R^T (v - origin), written for row vectors.
    normals = _channels(passes, "Normal", "XYZ") @ rotation
    length = np.linalg.norm(normals, axis=2, keepdims=True)
    normals = np.where(mask[..., None] & (length > 0), normals / np.maximum(length, 1e-12), 0).astype(np.float32)
    points = (_channels(passes, "Position", "XYZ") - origin) @ rotation
    depth = np.where(mask, points[..., 2], 0).astype(np.float32)
    return mask, clean, normals, depth


def _albedo(passes: dict, mask: np.ndarray, albedo: Optional[float]) -> tuple[Optional[np.ndarray], float]:
    """(albedo map, albedo): (None, the uniform albedo), or the own colours' map and its mean on the mask."""
    if albedo is not None:
        return None, float(albedo)
    albedo_map = np.where(mask, _channels(passes, "DiffCol", "RGB") @ LUMINANCE, 0).astype(np.float32)
    return albedo_map, float(albedo_map[mask].mean()) if mask.any() else 0.0


def _cast_shadows(passes: dict, mask: np.ndarray, normals: np.ndarray, light_vector: np.ndarray) -> np.ndarray:
    """The pixels in cast shadow.

    Diffuse Direct is the light arriving at the surface (sun strength pi: cos where it is lit); a
    pixel facing the light that gets clearly less than its cosine lies in a cast shadow.
    """
    direct = _channels(passes, "DiffDir", "RGB") @ LUMINANCE
    cosine = normals @ light_vector
    return mask & (cosine > MIN_SHADOW_COSINE) & (direct < SHADOW_RATIO * cosine)


def _degrade(clean: np.ndarray, noise: float, bits: Optional[int], seed: int) -> np.ndarray:
    """The clean image with the Gaussian noise (seeded) and the quantization asked for, float32."""
    image = clean.astype(np.float64)
    if noise > 0:
        image = np.maximum(image + np.random.default_rng(seed).normal(0.0, noise, image.shape), 0.0)
    if bits is not None:
        image = _quantize(image, bits)
    return image.astype(np.float32)


def _pixel_size(camera: dict, depth: np.ndarray, mask: np.ndarray) -> float:
    """The size of a pixel in scene units (for a perspective camera, at the objects' median distance)."""
    if camera["type"] == "orthographic":
        return camera["ortho_scale"] / camera["side_px"]
    # A perspective pixel grows with distance; this is its size at the objects' median distance.
    distance = float(-np.median(depth[mask])) if mask.any() else 1.0
    return distance / camera["focal_px"]
