"""The ShadeCut dataset format: one folder per rendered sample, and a manifest listing the samples.

A sample folder holds

- ``image.exr``: the Lambertian image, linear float (channel Y), alpha = mask.
- ``image.png``: the same image, 16-bit, sRGB-encoded with alpha = mask, so that
  :func:`shadecut.load_image` returns the linear values of ``image.exr`` (to 16-bit precision;
  values above 1, which only noise can make, are clipped to 1 there).
- ``normals.exr``: unit normals in the camera frame (channels R, G, B = x, y, z), 0 outside the mask.
- ``depth.exr``: **camera-frame z in scene units** (grey channel Y, Z in samples written before
  ShadeCut wrote Y; alpha = mask, z = 0 outside it). The
  camera looks down -z, so z is negative in front of it and larger = closer, as in pixel units.
  ``meta["pixel_size"]`` is the size of one pixel in scene units (for a perspective camera: at the
  objects' distance), and :func:`load_sample` returns ``z / pixel_size``, i.e. depth in pixel units.
  Absent when the depth is unknown (real photographs): ``depth`` is then None.
- ``mask.png``: 8-bit, 255 inside the objects.
- ``shadow_mask.png`` (only when cast shadows were rendered): 255 where a lit-facing pixel is in a
  cast shadow.
- ``albedo.exr`` (only when the objects kept their own colours): per-pixel albedo, linear float.
- ``meta.json``: the light (unit vector toward the light, camera frame), the albedo (null when unknown,
  as for a photograph), the pixel size, the camera, the resolution, the conventions, the noise and
  seed, the Blender version, ...

Samples are written atomically (into a hidden temporary folder renamed into place), so a folder named
like a sample is always complete. A dataset folder holds sample folders plus ``manifest.json`` and
``manifest.csv``, one entry per sample (``id``, ``shape``, ``folder`` relative to the dataset folder,
``light``, ``albedo``, ``size``, ``seed``, ...).

Real photographs come in through :func:`import_diligent` (module :mod:`shadecut.diligent`).

Conventions are those of the project README: image row 0 at the top; camera frame x right, y up,
z toward the viewer (Blender's camera-local axes). This module does not need ``bpy``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from .api import light_direction, load_image
from .file_kinds import read_text
# Part of this module's interface, written where they are built.
from .dataset_files import (CONVENTIONS, FORMAT, MANIFEST_CSV, MANIFEST_JSON, META, VERSION,  # noqa: F401
                            SAMPLE_CHANNELS, pixel_size, read_image_channels, write_manifest,
                            write_sample)
from .diligent import import_diligent  # noqa: F401


@dataclass
class Sample:
    """One sample as :func:`load_sample` returns it."""

    id: str
    folder: Path
    image: np.ndarray  # (H, W) float32, linear
    normals: np.ndarray  # (H, W, 3) float32, camera frame, 0 outside the mask
    depth: Optional[np.ndarray]  # (H, W) float32, pixel units, larger = closer (camera z: negative), 0 outside
    # the mask; None when unknown (a photograph)
    mask: np.ndarray  # (H, W) bool
    light: np.ndarray  # (3,) unit vector toward the light, camera frame
    albedo: Optional[float]  # the uniform albedo, or the mean of albedo_map over the mask; None = unknown
    meta: dict
    shadow_mask: Optional[np.ndarray] = None  # (H, W) bool, when rendered with cast shadows
    albedo_map: Optional[np.ndarray] = None  # (H, W) float32, when the objects kept their own colours


def _read_channels(path: Path, names: Optional[list[str]] = None) -> np.ndarray:
    """(H, W, C) pixels of an image file; ``names`` picks channels by name."""
    pixels, channel_names = read_image_channels(path)
    if names is None:
        return pixels
    missing = [name for name in names if name not in channel_names]
    if missing:
        raise OSError(f"shadecut: {path} has no channel {missing[0]} (it has {channel_names})")
    return pixels[..., [channel_names.index(name) for name in names]]


def is_sample(folder) -> bool:
    """True when ``folder`` is a complete sample (written by :func:`write_sample`)."""
    return (Path(folder) / META).is_file()


# save_depth's channel, then the one it wrote before (Z, which Blender loads as black): samples
# already rendered and cached keep loading.
DEPTH_CHANNELS = ("Y", "Z")


def _depth_channel(pixels: np.ndarray, channel_names: list[str]) -> Optional[np.ndarray]:
    """The depth plane (H, W) of a depth.exr's pixels, or None when it has none of DEPTH_CHANNELS."""
    name = next((name for name in DEPTH_CHANNELS if name in channel_names), None)
    return None if name is None else pixels[..., channel_names.index(name)]


def _present(path: Path) -> bool:
    """Whether a sample holds the optional file ``path``: anything under its name counts, so that a
    named pipe or a folder there is refused by the reader instead of taken for an absent file."""
    return path.exists() or path.is_symlink()


def check_sample(folder) -> Optional[str]:
    """None when ``folder`` is a complete, readable sample; otherwise what is wrong with it.

    Unlike :func:`is_sample`, which only looks for meta.json, this parses meta.json and reads every
    file it lists in full, checking its resolution and channels: a file truncated or damaged after
    it was written (a full disk, a copy cut short) is found. Reads every pixel, so it costs about as
    much as :func:`load_sample`.
    """
    folder = Path(folder)
    if not is_sample(folder):
        return f"{folder} is not a sample (no {META})"
    try:
        meta = load_sample_meta(folder)
    except (OSError, ValueError) as error:
        return f"{folder / META} is unreadable: {error}"
    files, resolution = meta.get("files") if isinstance(meta, dict) else None, None
    if isinstance(meta, dict):
        resolution = meta.get("resolution")
    if not isinstance(files, list) or META not in files or not isinstance(resolution, list) or len(resolution) != 2:
        return f"{folder / META} is malformed (no list of files or no resolution)"
    for name in files:
        if name == META:
            continue
        path = folder / str(name)
        if not _present(path):
            return f"{path} is missing"
        try:
            pixels, channels = read_image_channels(path)
        except OSError as error:
            return f"{path} is unreadable ({error})"
        if [pixels.shape[1], pixels.shape[0]] != resolution:
            return f"{path} is {pixels.shape[1]} x {pixels.shape[0]} pixels, not {resolution[0]} x {resolution[1]}"
        missing = [c for c in SAMPLE_CHANNELS.get(str(name), []) if c not in channels]
        if missing:
            return f"{path} has no channel {missing[0]} (it has {channels})"
        if name == "depth.exr" and _depth_channel(pixels, channels) is None:
            return f"{path} has no channel {' or '.join(DEPTH_CHANNELS)} (it has {channels})"
        if name == "depth.exr":
            try:
                pixel_size(meta, folder)
            except ValueError as error:
                return str(error).removeprefix("shadecut: ")
    return None


def load_sample_meta(folder) -> dict:
    """The meta.json of a sample folder, without reading its images."""
    meta_path = Path(folder) / META
    if not meta_path.is_file():
        raise OSError(f"shadecut: {folder} is not a ShadeCut sample (no {META})")
    return json.loads(read_text(meta_path))


def load_sample(folder) -> Sample:
    """Reads a sample folder; depth comes back in pixel units (z / meta["pixel_size"]), 0 outside the mask,
    or None when the sample has none (a photograph), as the albedo when unknown."""
    folder = Path(folder)
    meta = load_sample_meta(folder)
    mask = _read_channels(folder / "mask.png")[..., 0] > 0.5
    image = load_image(folder / "image.exr").image
    normals = _read_channels(folder / "normals.exr", ["R", "G", "B"])
    depth = None
    if _present(folder / "depth.exr"):
        pixels, channel_names = read_image_channels(folder / "depth.exr")
        z = _depth_channel(pixels, channel_names)
        if z is None:
            raise OSError(f"shadecut: {folder / 'depth.exr'} has no channel {' or '.join(DEPTH_CHANNELS)} "
                          f"(it has {channel_names})")
        depth = np.where(mask, z / np.float32(pixel_size(meta, folder)), 0).astype(np.float32)
    shadow_path, albedo_path = folder / "shadow_mask.png", folder / "albedo.exr"
    return Sample(
        id=meta.get("id", folder.name),
        folder=folder,
        image=image,
        normals=np.where(mask[..., None], normals, 0).astype(np.float32),
        depth=depth,
        mask=mask,
        light=light_direction(meta["light"]),
        albedo=None if meta.get("albedo") is None else float(meta["albedo"]),
        meta=meta,
        shadow_mask=_read_channels(shadow_path)[..., 0] > 0.5 if _present(shadow_path) else None,
        albedo_map=load_image(albedo_path).image if _present(albedo_path) else None,
    )


def load_manifest(dataset_dir) -> list[dict]:
    """The entries of ``manifest.json``; ``folder`` is relative to ``dataset_dir``."""
    path = Path(dataset_dir) / MANIFEST_JSON
    if not path.is_file():
        raise OSError(f"shadecut: {dataset_dir} holds no {MANIFEST_JSON}")
    document = json.loads(read_text(path))  # json.JSONDecodeError (a ValueError) when not JSON
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise ValueError(f"shadecut: {path} is malformed: not a ShadeCut dataset manifest (a JSON object with "
                         f'"format": "{FORMAT}")')
    samples = document.get("samples")
    if not isinstance(samples, list) or not all(isinstance(entry, dict) for entry in samples):
        raise ValueError(f'shadecut: {path} is malformed: "samples" is not a list of objects')
    return samples


def load_dataset_info(dataset_dir) -> dict:
    """The dataset-wide settings stored in ``manifest.json`` (the generator's options, seed, ...)."""
    path = Path(dataset_dir) / MANIFEST_JSON
    if not path.is_file():
        raise OSError(f"shadecut: {dataset_dir} holds no {MANIFEST_JSON}")
    document = json.loads(read_text(path))
    info = document.get("dataset", {}) if isinstance(document, dict) else None
    if not isinstance(info, dict):
        raise ValueError(f'shadecut: {path} is malformed: "dataset" is not a JSON object')
    return info
