"""DiLiGenT (Shi et al., CVPR 2016): real photographs with calibrated lights and measured normals,
imported as ShadeCut dataset samples.

An object folder of the benchmark (``ballPNG/``, ``catPNG/``, ...) holds ``NNN.png`` (16-bit linear
RGB photographs), ``filenames.txt`` (the names of all the benchmark's images, in the order of the
two light files), ``light_directions.txt`` (one unit vector toward the light per line, camera frame
x right, y up, z toward the camera: ShadeCut's), ``light_intensities.txt`` (the RGB intensity of each
light), ``mask.png`` and ``Normal_gt.mat`` (variable ``Normal_gt``, H x W x 3, same frame). Only the
images present are imported. The benchmark is research-use data: this module reads it from where the
user keeps it and writes samples elsewhere; it never ships with ShadeCut.

A sample's image is the mean of R, G and B after dividing each channel by that image's light
intensity (linear; values may exceed 1 where the intensity is below 1: image.exr keeps them,
image.png clips). The albedo of a photograph is unknown: the sample records ``albedo`` None. There
is no measured depth: the sample has no depth.exr (``load_sample`` gives ``depth`` None).

Needs scipy (``scipy.io.loadmat``), imported only when a folder is read.
"""

from __future__ import annotations

import contextlib
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Optional, Union

import numpy as np

from . import dataset_files
from .api import light_direction
from .file_kinds import read_text

REQUIRED = ("filenames.txt", "light_directions.txt", "light_intensities.txt", "mask.png", "Normal_gt.mat")
CITATION = ("B. Shi, Z. Wu, Z. Mo, D. Duan, S.-K. Yeung, P. Tan, \"A Benchmark Dataset and Evaluation for "
            "Non-Lambertian and Uncalibrated Photometric Stereo\", CVPR 2016")
# About 1.5 m from a camera of focal length about 3772 px (the benchmark's calibration): metres per pixel.
PIXEL_SIZE = 1.5 / 3772.0


def is_object_folder(folder: Union[os.PathLike, str]) -> bool:
    """True when ``folder`` looks like a DiLiGenT object folder (it holds filenames.txt)."""
    return (Path(folder) / "filenames.txt").is_file()


def object_name(folder: Union[os.PathLike, str]) -> str:
    """The object's name: the folder's name without the benchmark's ``PNG`` suffix (``ballPNG`` -> ``ball``)."""
    name = Path(folder).resolve().name
    return name[:-3] if name.endswith("PNG") and len(name) > 3 else name


def _table(path: Path, rows: int) -> np.ndarray:
    try:
        values = np.loadtxt(path, dtype=np.float64, ndmin=2)
    except ValueError as error:
        raise ValueError(f"shadecut: {path} is not a table of numbers: {error}") from None
    if values.shape != (rows, 3):
        raise ValueError(f"shadecut: {path} must hold {rows} lines of 3 numbers (one per line of "
                         f"filenames.txt); it holds shape {values.shape}")
    if not np.isfinite(values).all():
        line = int(np.argwhere(~np.isfinite(values))[0, 0]) + 1
        raise ValueError(f"shadecut: {path} line {line} holds a value that is not a finite number "
                         f"({' '.join(str(value) for value in values[line - 1])})")
    return values


def _check_lights(path: Path, lights: np.ndarray, names: list[str]) -> None:
    """ValueError naming the file, the line and its image for a light shape from shading cannot use
    (at or below the horizon, or of length 0), before any sample is written."""
    for line, (light, name) in enumerate(zip(lights, names), 1):
        try:
            light_direction(light)
        except ValueError as error:
            reason = str(error).removeprefix("shadecut: ")
            raise ValueError(f"shadecut: {path} line {line} (the light of {name}: "
                             f"{' '.join(f'{value:g}' for value in light)}): {reason}") from None


def read_layout(source: Union[os.PathLike, str]) -> dict:
    """Checks an object folder's layout without reading its images or normals.

    Returns ``names`` (filenames.txt), ``lights`` and ``intensities`` ((N, 3) arrays in that order) and
    ``present`` (the names whose file exists). Raises OSError for a missing folder or file, ValueError
    for a file whose content does not fit the layout; the message names the path.
    """
    source = Path(source)
    if not source.is_dir():
        raise OSError(f"shadecut: the DiLiGenT object folder {source} does not exist")
    missing = [name for name in REQUIRED if not (source / name).is_file()]
    if missing:
        raise OSError(f"shadecut: {source} is not a DiLiGenT object folder: it lacks {', '.join(missing)} "
                      f"(expected {', '.join(REQUIRED)} and NNN.png images)")
    names = read_text(source / "filenames.txt").split()
    if not names:
        raise ValueError(f"shadecut: {source / 'filenames.txt'} lists no image")
    first_line = {}
    for line, name in enumerate(names, 1):
        if name in first_line:  # one image with two lights: which one is meant is unknown
            raise ValueError(f"shadecut: {source / 'filenames.txt'} lists {name} twice (lines {first_line[name]} and "
                             f"{line}); each line pairs one image with the light on the same line of the light files")
        first_line[name] = line
    lights = _table(source / "light_directions.txt", len(names))
    _check_lights(source / "light_directions.txt", lights, names)
    intensities = _table(source / "light_intensities.txt", len(names))
    if not (intensities > 0).all():
        raise ValueError(f"shadecut: {source / 'light_intensities.txt'} holds an intensity <= 0")
    present = [name for name in names if (source / name).is_file()]
    if not present:
        raise OSError(f"shadecut: {source} holds none of the images filenames.txt lists ({names[0]}, ...)")
    return {"names": names, "lights": lights, "intensities": intensities, "present": present}


def _select(layout: dict, images: Optional[Iterable[Union[int, str]]], source: Path) -> list[str]:
    """The image names chosen by numbers (7) or names ("007", "007.png"); None = every image present."""
    if images is None:
        return list(layout["present"])
    if isinstance(images, (int, str)):
        images = [images]
    chosen = []
    for image in images:
        if isinstance(image, (int, np.integer)):
            matches = [n for n in layout["names"] if Path(n).stem.isdigit() and int(Path(n).stem) == int(image)]
        else:
            matches = [n for n in layout["names"] if image in (n, Path(n).stem)]
        if not matches:
            raise ValueError(f"shadecut: no image {image!r} in {source / 'filenames.txt'}")
        if matches[0] not in layout["present"]:
            raise OSError(f"shadecut: the image {source / matches[0]} is listed but not present")
        if matches[0] not in chosen:
            chosen.append(matches[0])
    if not chosen:
        raise ValueError("shadecut: images= selects no image")
    return chosen


def read_normals(path: Path, shape: tuple) -> np.ndarray:
    """The measured normals of Normal_gt.mat, (H, W, 3) float32 in the camera frame (NaN as 0);
    ValueError naming the file when it cannot be read or is not of the mask's shape."""
    from scipy.io import loadmat  # only here: the add-on's other modules run without scipy

    try:
        contents = loadmat(str(path))
    except Exception as error:  # noqa: BLE001  (a damaged file raises whatever scipy's parser meets first)
        raise ValueError(f"shadecut: cannot read {path}: it is not a readable MATLAB file "
                         f"({type(error).__name__}: {error})") from None
    if "Normal_gt" not in contents:
        raise ValueError(f"shadecut: {path} holds no variable Normal_gt")
    normals = contents["Normal_gt"]
    if not (isinstance(normals, np.ndarray) and normals.dtype.kind in "fiu" and normals.shape == (*shape, 3)):
        raise ValueError(f"shadecut: {path} holds Normal_gt of shape {np.shape(normals)} "
                         f"({np.asarray(normals).dtype}); the mask is {shape}, so numbers of shape (H, W, 3) = "
                         f"{(*shape, 3)} were expected")
    return np.nan_to_num(np.asarray(normals, dtype=np.float32))


@dataclass
class DiligentObject:
    """One object's photographs with their calibrated lights, cropped to its mask with a margin."""

    names: list  # the photographs' file names
    photos: list  # (H, W, 3) float32 linear RGB, each channel divided by that photograph's light intensity
    lights: np.ndarray  # (K, 3) unit vectors toward each photograph's light, camera frame
    mask: np.ndarray  # (H, W) bool
    normals: np.ndarray  # (H, W, 3) float32 measured normals, 0 outside the mask


def load_object(source: Union[os.PathLike, str], images: Optional[Iterable[Union[int, str]]] = None,
                margin: int = 8) -> DiligentObject:
    """The photographs (numbers such as 7 or names such as "007.png"; None = every one present) of a
    DiLiGenT object folder, with their lights, mask and normals, cropped to the mask plus ``margin``
    pixels: what a reconstruction of several photographs, or of each, reads."""
    source = Path(source)
    layout = read_layout(source)
    names = _select(layout, images, source)
    mask = dataset_files.read_image_channels(source / "mask.png")[0][..., 0] > 0.5
    normals = read_normals(source / "Normal_gt.mat", mask.shape)
    rows, cols = np.nonzero(mask)
    if rows.size == 0:
        raise ValueError(f"shadecut: {source / 'mask.png'} selects no pixel")
    crop = np.s_[max(rows.min() - margin, 0):rows.max() + margin + 1, max(cols.min() - margin, 0):cols.max() + margin + 1]
    photos = []
    for name in names:
        pixels, channels = dataset_files.read_image_channels(source / name)
        if pixels.shape[-1] < 3:
            raise ValueError(f"shadecut: {source / name} has channels {channels}; DiLiGenT's photographs are RGB")
        intensity = layout["intensities"][layout["names"].index(name)]
        photos.append((pixels[..., :3] / intensity)[crop].astype(np.float32))
    lights = np.array([layout["lights"][layout["names"].index(name)] for name in names], dtype=np.float64)
    return DiligentObject(names=names, photos=photos, lights=lights, mask=mask[crop], normals=normals[crop])


def read_photo(source: Union[os.PathLike, str], name: str, intensity) -> np.ndarray:
    """One photograph as a ShadeCut image: the mean over R, G, B of channel / intensity (linear).

    The PNG's 16-bit codes are read as they are stored (code / 65535, no colour conversion).
    """
    path = Path(source) / name
    pixels, channels = dataset_files.read_image_channels(path)
    if pixels.shape[-1] < 3:
        raise ValueError(f"shadecut: {path} has channels {channels}; DiLiGenT's photographs are RGB")
    rgb = pixels[..., :3].astype(np.float64) / np.asarray(intensity, dtype=np.float64)
    return rgb.mean(axis=-1).astype(np.float32)


def _import_photo(source: Path, folder: Path, name: str, layout: dict, mask: np.ndarray,
                  normals: np.ndarray) -> dict:
    """Writes the sample of photograph ``name`` into ``folder``; returns its manifest entry."""
    index = layout["names"].index(name)
    image = read_photo(source, name, layout["intensities"][index])
    if image.shape != mask.shape:
        raise ValueError(f"shadecut: {source / name} is {image.shape[1]} x {image.shape[0]} pixels; "
                         f"the mask is {mask.shape[1]} x {mask.shape[0]}")
    obj = object_name(source)
    light = light_direction(layout["lights"][index]).tolist()
    meta = {"id": folder.name, "shape": obj, "pixel_size": PIXEL_SIZE, "source": "DiLiGenT",
            "citation": CITATION, "source_folder": str(source.resolve()), "source_image": name,
            "light_index": index, "light_intensity": layout["intensities"][index].tolist(),
            "image_rule": "mean over R, G, B of channel / light intensity, linear",
            "camera": "perspective, nearly orthographic (focal length about 3772 px, object about 1.5 m away)"}
    dataset_files.write_sample(folder, image=image, normals=normals, depth=None, mask=mask, light=light,
                               albedo=None, meta=meta)
    return {"id": folder.name, "shape": obj, "folder": folder.name, "light": light, "albedo": None,
            "size": mask.shape[1], "seed": None, "source_image": name}


def import_diligent(source: Union[os.PathLike, str], out: Union[os.PathLike, str],
                    images: Optional[Iterable[Union[int, str]]] = None) -> list[dict]:
    """Writes one ShadeCut sample per photograph of a DiLiGenT object folder, and a manifest.

    ``source``: an object folder in the benchmark's layout (see the module docstring). ``out``: the
    dataset folder to write (sample folders ``<object>_<NNN>``, e.g. ``ball_001``, and
    ``manifest.json``/``.csv`` listing the samples of this call). ``images``: image numbers or
    names to import (``[1, 7]``, ``["001.png"]``); None = every image present. Each sample holds the
    image (see :func:`read_photo`), mask.png's mask, Normal_gt's normals (0 outside the mask), the
    calibrated light and ``albedo`` None (unknown); no depth. Returns the manifest entries written.
    Raises OSError/ValueError naming the path for a folder not in the benchmark's layout.
    """
    source, out = Path(source), Path(out)
    layout = read_layout(source)
    chosen = _select(layout, images, source)
    mask_pixels, _ = dataset_files.read_image_channels(source / "mask.png")
    mask = mask_pixels[..., 0] > 0.5
    if not mask.any():
        raise ValueError(f"shadecut: the mask {source / 'mask.png'} is empty")
    normals = read_normals(source / "Normal_gt.mat", mask.shape)
    normals = np.where(mask[..., None], normals, 0).astype(np.float32)
    obj = object_name(source)

    entries, new_samples, new_out = [], [], not out.exists()
    try:
        for name in chosen:
            folder = out / f"{obj}_{Path(name).stem}"
            if not folder.exists():
                new_samples.append(folder)
            entries.append(_import_photo(source, folder, name, layout, mask, normals))
    except BaseException:
        # No manifest would list what this call wrote: the samples new to ``out`` go (and ``out``, if
        # this call made it); one that replaced a sample of the same name stays, complete, where an
        # earlier manifest lists it.
        for folder in new_samples:
            shutil.rmtree(folder, ignore_errors=True)
        if new_out:
            with contextlib.suppress(OSError):
                out.rmdir()
        raise
    dataset_files.write_manifest(out, entries, {"generator": "shadecut.dataset.import_diligent", "source": "DiLiGenT",
                                                "source_folder": str(source.resolve()), "citation": CITATION})
    return entries
