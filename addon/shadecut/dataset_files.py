"""Writing the ShadeCut dataset format (described in :mod:`shadecut.dataset`): sample folders and
the manifest, each written atomically; and reading any image file's channels, which the readers of
samples and of DiLiGenT's photographs share.

Here rather than in :mod:`shadecut.dataset` so that :mod:`shadecut.diligent` can write samples
while :mod:`shadecut.dataset` offers its importer: neither imports the other's importer.
"""

from __future__ import annotations

import csv
import io
import json
import math
import shutil
from pathlib import Path
from typing import Optional

import numpy as np
import OpenImageIO as oiio

from .api import light_direction, save_depth, save_image, save_normals
from .atomic_write import remove_leftovers, temporary_name, write_text
from .file_kinds import refuse_special_file
from .image_header import oriented

FORMAT = "shadecut-dataset"
VERSION = 1
CONVENTIONS = (
    "image row 0 at the top, linear intensity; camera frame x right, y up, z toward the viewer "
    "(Blender camera-local); light points toward the light; depth.exr holds camera-frame z in scene "
    "units (larger = closer), divide by pixel_size for pixel units; normals unit, camera frame"
)
MANIFEST_JSON = "manifest.json"
MANIFEST_CSV = "manifest.csv"
META = "meta.json"


def read_image_channels(path) -> tuple[np.ndarray, list[str]]:
    """(H, W, C) float32 pixels of any image file OpenImageIO reads, row 0 at the top (upright as its
    EXIF orientation says), and the channel names (EXR stores them sorted, so "Y" of a Y + A file is
    not the first)."""
    refuse_special_file(path)
    image = oiio.ImageInput.open(str(path))
    if image is None:
        raise OSError(f"shadecut: cannot read {path}: {oiio.geterror()}")
    try:
        spec = image.spec()
        pixels = image.read_image(oiio.FLOAT)
        several = image.seek_subimage(1, 0)
    finally:
        image.close()
    if several:  # which one is meant is unknown: the first would be read without a word
        raise OSError(f"shadecut: cannot read {path}: it holds several images (the pages of a TIFF, the frames of a "
                      "GIF); save the one to read as a file of its own")
    if pixels is None:
        raise OSError(f"shadecut: cannot read the pixels of {path}")
    orientation = spec.get_int_attribute("Orientation", 1)  # EXIF's: turned upright, as viewers show it
    pixels = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, -1)
    return oriented(pixels, orientation if 1 <= orientation <= 8 else 1), list(spec.channelnames)


def pixel_size(meta: dict, folder) -> float:
    """The sample's pixel size (scene units per pixel), which converts depth.exr to pixel units;
    ValueError when meta.json lacks it or holds no positive finite number (0 would make every depth
    infinite). The readers and :func:`write_sample` hold meta.json to this one rule."""
    value = meta.get("pixel_size") if isinstance(meta, dict) else None
    number = isinstance(value, (int, float, np.number)) and not isinstance(value, (bool, np.bool_))
    if not (number and math.isfinite(value) and value > 0):
        raise ValueError(f"shadecut: {Path(folder) / META}: pixel_size {value!r} is not a positive number "
                         "of scene units per pixel, which depth.exr needs")
    return float(value)


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
    sample (or empty folder) of the same name is replaced; anything else of that name is refused
    (OSError) before any work. The files are written into a hidden folder of this call's
    own beside the folder (``.<name>.<pid>-<random>.partial``), which is then renamed: an interrupted
    call never leaves a folder named like the sample.
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
    if depth is not None:
        pixel_size(meta, folder)

    files = ["image.exr", "image.png", "normals.exr", "depth.exr", "mask.png", META]
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

    _check_replaceable(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    remove_leftovers(folder)  # of an earlier run that was killed
    partial = temporary_name(folder)  # this call's own: two runs writing one dataset never share it
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
        (partial / META).write_text(json.dumps(_json_ready(record), indent=2) + "\n")
        if folder.exists():
            previous = temporary_name(folder)
            folder.rename(previous)
            partial.rename(folder)
            shutil.rmtree(previous)
        else:
            partial.rename(folder)
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        raise


# Every image file a sample folder may hold (write_sample), with the channels it must have (check_sample);
# a folder of these and meta.json alone is a sample, whole or damaged.
SAMPLE_CHANNELS = {"image.exr": ["Y"], "image.png": ["Y"], "normals.exr": ["R", "G", "B"], "depth.exr": [],
                   "mask.png": [], "shadow_mask.png": [], "albedo.exr": ["Y"]}
SAMPLE_FILES = {*SAMPLE_CHANNELS, META}


def _check_replaceable(folder: Path) -> None:
    """OSError before any work when ``folder`` exists as something a sample may not replace: a file,
    or a folder holding anything but a sample's files (the user's own, which would be lost). A sample,
    a damaged one (a file missing or cut short) and an empty folder are replaced."""
    if folder.is_symlink() or (folder.exists() and not folder.is_dir()):
        raise OSError(f"shadecut: {folder} exists and is not a folder: a sample of that name would replace it")
    if folder.is_dir():
        foreign = sorted(path.name for path in folder.iterdir() if path.name not in SAMPLE_FILES or not path.is_file())
        if foreign:
            raise OSError(f"shadecut: {folder} exists and is not a ShadeCut sample (it holds {', '.join(foreign[:3])}"
                          f"{', ...' if len(foreign) > 3 else ''}): a sample of that name would replace it and every "
                          "file in it; move it, or write the samples elsewhere")


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
    write_text(dataset_dir / MANIFEST_JSON, json.dumps(document, indent=2) + "\n")

    rows = [_csv_row(entry) for entry in entries]
    columns: list[str] = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    write_text(dataset_dir / MANIFEST_CSV, text.getvalue())
