"""The ShadeCut dataset format: one folder per rendered sample, and a manifest listing the samples.

A sample folder holds

- ``image.exr``: the Lambertian image, linear float (channel Y), alpha = mask.
- ``image.png``: the same image, 16-bit, sRGB-encoded with alpha = mask, so that
  :func:`shadecut.load_image` returns the linear values of ``image.exr`` (to 16-bit precision;
  values above 1, which only noise can make, are clipped to 1 there).
- ``normals.exr``: unit normals in the camera frame (channels R, G, B = x, y, z), 0 outside the mask.
- ``depth.exr``: **camera-frame z in scene units** (channel Z; alpha = mask, z = 0 outside it). The
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

import csv
import io
import json
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
import OpenImageIO as oiio

from .api import light_direction, load_image, save_depth, save_image, save_normals

FORMAT = "shadecut-dataset"
VERSION = 1
CONVENTIONS = (
    "image row 0 at the top, linear intensity; camera frame x right, y up, z toward the viewer "
    "(Blender camera-local); light points toward the light; depth.exr holds camera-frame z in scene "
    "units (larger = closer), divide by pixel_size for pixel units; normals unit, camera frame"
)
MANIFEST_JSON = "manifest.json"
MANIFEST_CSV = "manifest.csv"
_META = "meta.json"


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


def read_image_channels(path) -> tuple[np.ndarray, list[str]]:
    """(H, W, C) float32 pixels of any image file OpenImageIO reads, row 0 at the top, and the
    channel names (EXR stores them sorted, so "Z" of a Z + A file is not the first)."""
    image = oiio.ImageInput.open(str(path))
    if image is None:
        raise OSError(f"shadecut: cannot read {path}: {oiio.geterror()}")
    try:
        spec = image.spec()
        pixels = image.read_image(oiio.FLOAT)
    finally:
        image.close()
    if pixels is None:
        raise OSError(f"shadecut: cannot read the pixels of {path}")
    return np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, -1), list(spec.channelnames)


def _read_channels(path: Path, names: Optional[list[str]] = None) -> np.ndarray:
    """(H, W, C) pixels of an image file; ``names`` picks channels by name."""
    pixels, channel_names = read_image_channels(path)
    if names is None:
        return pixels
    missing = [name for name in names if name not in channel_names]
    if missing:
        raise OSError(f"shadecut: {path} has no channel {missing[0]} (it has {channel_names})")
    return pixels[..., [channel_names.index(name) for name in names]]


def _write_mask(path: Path, mask: np.ndarray) -> None:
    height, width = mask.shape
    out = oiio.ImageOutput.create(str(path))
    if out is None or not out.open(str(path), oiio.ImageSpec(width, height, 1, oiio.UINT8)):
        raise OSError(f"shadecut: cannot write {path}: {oiio.geterror()}")
    written = out.write_image(np.where(mask, 255, 0).astype(np.uint8)[..., None])
    out.close()
    if not written:
        raise OSError(f"shadecut: cannot write {path}")


def _json_ready(value):
    """Numpy scalars and arrays as plain JSON values."""
    if isinstance(value, dict):
        return {str(k): _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_json_ready(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    return value


def write_sample(folder, *, image, normals, depth, mask, light, albedo, meta: dict,
                 shadow_mask=None, albedo_map=None) -> None:
    """Writes one sample folder (see the module docstring) atomically.

    ``depth`` is camera-frame z in scene units; ``meta`` must hold ``pixel_size`` (scene units per
    pixel) so that readers convert it to pixel units. ``depth`` None = unknown: no depth.exr.
    ``albedo`` None = unknown (stored as null). ``light`` is stored normalized. An existing
    folder of the same name is replaced. The files are written into ``.<name>.partial`` beside the
    folder, which is then renamed: an interrupted call never leaves a folder named like the sample.
    """
    folder = Path(folder)
    image = np.asarray(image, dtype=np.float32)
    if image.ndim != 2:
        raise ValueError(f"shadecut: the image must be (H, W); got shape {image.shape}")
    shape = image.shape
    normals = np.asarray(normals, dtype=np.float32)
    depth = None if depth is None else np.asarray(depth, dtype=np.float32)
    mask = np.asarray(mask, dtype=bool)
    if normals.shape != (*shape, 3) or (depth is not None and depth.shape != shape) or mask.shape != shape:
        raise ValueError(f"shadecut: image {shape}, normals {normals.shape}, depth "
                         f"{None if depth is None else depth.shape} and mask {mask.shape} must share (H, W), "
                         "normals with 3 channels")
    for name, extra in (("shadow_mask", shadow_mask), ("albedo_map", albedo_map)):
        if extra is not None and np.shape(extra) != shape:
            raise ValueError(f"shadecut: {name} has shape {np.shape(extra)}, not {shape}")
    if depth is not None and ("pixel_size" not in meta or not float(meta["pixel_size"]) > 0):
        raise ValueError("shadecut: meta must hold a positive 'pixel_size' (scene units per pixel) for depth.exr")

    files = ["image.exr", "image.png", "normals.exr", "depth.exr", "mask.png", _META]
    if depth is None:
        files.remove("depth.exr")
    if shadow_mask is not None:
        files.insert(-1, "shadow_mask.png")
    if albedo_map is not None:
        files.insert(-1, "albedo.exr")
    record = dict(meta)
    record.update(
        format=FORMAT,
        version=VERSION,
        id=meta.get("id", folder.name),
        light=light_direction(light).tolist(),
        albedo=None if albedo is None else float(albedo),
        resolution=[shape[1], shape[0]],
        conventions=CONVENTIONS,
        files=files,
    )

    folder.parent.mkdir(parents=True, exist_ok=True)
    partial = folder.parent / f".{folder.name}.partial"
    shutil.rmtree(partial, ignore_errors=True)  # left by an earlier run that was killed
    partial.mkdir()
    try:
        save_image(partial / "image.exr", image, mask)
        save_image(partial / "image.png", image, mask)
        save_normals(partial / "normals.exr", np.where(mask[..., None], normals, 0).astype(np.float32), mask)
        if depth is not None:
            save_depth(partial / "depth.exr", depth, mask)
        _write_mask(partial / "mask.png", mask)
        if shadow_mask is not None:
            _write_mask(partial / "shadow_mask.png", np.asarray(shadow_mask, dtype=bool))
        if albedo_map is not None:
            save_image(partial / "albedo.exr", np.asarray(albedo_map, dtype=np.float32), mask)
        (partial / _META).write_text(json.dumps(_json_ready(record), indent=2) + "\n")
        if folder.exists():
            previous = folder.parent / f".{folder.name}.previous"
            shutil.rmtree(previous, ignore_errors=True)
            folder.rename(previous)
            partial.rename(folder)
            shutil.rmtree(previous)
        else:
            partial.rename(folder)
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        raise


def is_sample(folder) -> bool:
    """True when ``folder`` is a complete sample (written by :func:`write_sample`)."""
    return (Path(folder) / _META).is_file()


# Channels each image file of a sample must hold (check_sample).
_CHANNELS = {"image.exr": ["Y"], "image.png": ["Y"], "normals.exr": ["R", "G", "B"], "depth.exr": ["Z"],
             "mask.png": [], "shadow_mask.png": [], "albedo.exr": ["Y"]}


def check_sample(folder) -> Optional[str]:
    """None when ``folder`` is a complete, readable sample; otherwise what is wrong with it.

    Unlike :func:`is_sample`, which only looks for meta.json, this parses meta.json and reads every
    file it lists in full, checking its resolution and channels: a file truncated or damaged after
    it was written (a full disk, a copy cut short) is found. Reads every pixel, so it costs about as
    much as :func:`load_sample`.
    """
    folder = Path(folder)
    if not is_sample(folder):
        return f"{folder} is not a sample (no {_META})"
    try:
        meta = load_sample_meta(folder)
    except (OSError, ValueError) as error:
        return f"{folder / _META} is unreadable: {error}"
    files, resolution = meta.get("files") if isinstance(meta, dict) else None, None
    if isinstance(meta, dict):
        resolution = meta.get("resolution")
    if not isinstance(files, list) or _META not in files or not isinstance(resolution, list) or len(resolution) != 2:
        return f"{folder / _META} is malformed (no list of files or no resolution)"
    for name in files:
        if name == _META:
            continue
        path = folder / str(name)
        if not path.is_file():
            return f"{path} is missing"
        try:
            pixels, channels = read_image_channels(path)
        except OSError as error:
            return f"{path} is unreadable ({error})"
        if [pixels.shape[1], pixels.shape[0]] != resolution:
            return f"{path} is {pixels.shape[1]} x {pixels.shape[0]} pixels, not {resolution[0]} x {resolution[1]}"
        missing = [c for c in _CHANNELS.get(str(name), []) if c not in channels]
        if missing:
            return f"{path} has no channel {missing[0]} (it has {channels})"
    return None


def load_sample_meta(folder) -> dict:
    """The meta.json of a sample folder, without reading its images."""
    meta_path = Path(folder) / _META
    if not meta_path.is_file():
        raise OSError(f"shadecut: {folder} is not a ShadeCut sample (no {_META})")
    return json.loads(meta_path.read_text())


def load_sample(folder) -> Sample:
    """Reads a sample folder; depth comes back in pixel units (z / meta["pixel_size"]), 0 outside the mask,
    or None when the sample has none (a photograph), as the albedo when unknown."""
    folder = Path(folder)
    meta = load_sample_meta(folder)
    mask = _read_channels(folder / "mask.png")[..., 0] > 0.5
    image = load_image(folder / "image.exr").image
    normals = _read_channels(folder / "normals.exr", ["R", "G", "B"])
    depth = None
    if (folder / "depth.exr").is_file():
        z = _read_channels(folder / "depth.exr", ["Z"])[..., 0]
        depth = np.where(mask, z / np.float32(meta["pixel_size"]), 0).astype(np.float32)
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
        shadow_mask=_read_channels(shadow_path)[..., 0] > 0.5 if shadow_path.is_file() else None,
        albedo_map=load_image(albedo_path).image if albedo_path.is_file() else None,
    )


def _replace_text(path: Path, text: str) -> None:
    """Writes a file through a temporary one and a rename, so readers never see half of it."""
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    temporary.write_text(text)
    os.replace(temporary, path)


def _csv_row(entry: dict) -> dict:
    """A manifest entry with the light split into light_x/y/z and lists joined, for the CSV."""
    row = {}
    for key, value in entry.items():
        if key == "light":
            row.update(light_x=value[0], light_y=value[1], light_z=value[2])
        elif isinstance(value, (list, tuple)):
            row[key] = " ".join(str(v) for v in value)
        elif isinstance(value, dict):
            row[key] = json.dumps(value)
        else:
            row[key] = value
    return row


def write_manifest(dataset_dir, entries: list[dict], info: Optional[dict] = None) -> None:
    """Writes ``manifest.json`` (``{"format", "version", "dataset": info, "samples": entries}``) and
    ``manifest.csv`` (one row per entry, the light as light_x, light_y, light_z), each atomically."""
    dataset_dir = Path(dataset_dir)
    entries = [_json_ready(entry) for entry in entries]
    for entry in entries:
        missing = {"id", "shape", "folder", "light", "albedo", "size", "seed"} - entry.keys()
        if missing:
            raise ValueError(f"shadecut: manifest entry {entry.get('id')!r} lacks {sorted(missing)}")
    document = {"format": FORMAT, "version": VERSION, "dataset": _json_ready(info or {}), "samples": entries}
    _replace_text(dataset_dir / MANIFEST_JSON, json.dumps(document, indent=2) + "\n")

    rows = [_csv_row(entry) for entry in entries]
    columns: list[str] = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    _replace_text(dataset_dir / MANIFEST_CSV, text.getvalue())


def load_manifest(dataset_dir) -> list[dict]:
    """The entries of ``manifest.json``; ``folder`` is relative to ``dataset_dir``."""
    path = Path(dataset_dir) / MANIFEST_JSON
    if not path.is_file():
        raise OSError(f"shadecut: {dataset_dir} holds no {MANIFEST_JSON}")
    document = json.loads(path.read_text())  # json.JSONDecodeError (a ValueError) when not JSON
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
    document = json.loads(path.read_text())
    info = document.get("dataset", {}) if isinstance(document, dict) else None
    if not isinstance(info, dict):
        raise ValueError(f'shadecut: {path} is malformed: "dataset" is not a JSON object')
    return info


from .diligent import import_diligent  # noqa: E402, F401  (re-exported; diligent.py uses the writer above)
