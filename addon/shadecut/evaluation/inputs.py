"""What a run is given, checked before any work: method names, the dataset, the output folder.

Also writes :mod:`shadecut.synthetic` scenes as a dataset, the quick one that needs no Blender.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional, Sequence

from .. import METHODS
from .. import dataset as _dataset
from ..atomic_write import check_writable


class EvaluationError(Exception):
    """Input the user can fix (dataset, method names, output folder); the message says what."""


def check_methods(names: Optional[Sequence[str]]) -> tuple[str, ...]:
    """The method names to run (None = all of shadecut.METHODS); EvaluationError for unknown ones."""
    if names is None:
        return tuple(METHODS)
    names = tuple(dict.fromkeys(name.strip() for name in names if name.strip()))
    unknown = [name for name in names if name not in METHODS]
    if unknown or not names:
        raise EvaluationError(
            f"unknown method {', '.join(repr(n) for n in unknown) or '(none given)'}; "
            f"choose among {', '.join(METHODS)}"
        )
    return names


def prepare_output(folder: os.PathLike | str) -> Path:
    """Creates the output folder and checks that files can be written in it (atomic_write.check_writable)."""
    try:
        return check_writable(folder)
    except OSError as error:
        raise EvaluationError(f"cannot write to the output folder {folder}: {error.strerror or error}") from None


def read_manifest(dataset_dir: os.PathLike | str) -> list[dict]:
    """The dataset's manifest entries, checked; EvaluationError for a missing or malformed dataset."""
    dataset_dir = Path(dataset_dir)
    if not dataset_dir.exists():
        raise EvaluationError(f"the dataset folder {dataset_dir} does not exist")
    if not dataset_dir.is_dir():
        raise EvaluationError(f"the dataset {dataset_dir} is not a folder (give the folder that holds "
                              f"{_dataset.MANIFEST_JSON} and the sample folders)")
    try:
        entries = _dataset.load_manifest(dataset_dir)
    except OSError as error:  # missing or unreadable file
        raise EvaluationError(f"the dataset {dataset_dir} has no readable manifest: {error}") from None
    except ValueError as error:  # not JSON (json.JSONDecodeError), or JSON of the wrong shape
        raise EvaluationError(f"the dataset {dataset_dir} has a malformed manifest: {error}") from None
    if not isinstance(entries, list) or not all(isinstance(entry, dict) for entry in entries):
        raise EvaluationError(f"the dataset {dataset_dir} has a malformed manifest: it does not hold a list of samples")
    if not entries:
        raise EvaluationError(f"the dataset {dataset_dir} lists no sample")
    for entry in entries:
        missing = [key for key in ("id", "shape", "folder") if key not in entry]
        if missing:
            raise EvaluationError(f"the manifest of {dataset_dir} has an entry without {', '.join(missing)}: {entry}")
    return entries


def write_synthetic_dataset(dataset_dir: os.PathLike | str, scenes: dict) -> Path:
    """Writes :mod:`shadecut.synthetic` scenes as a dataset that :func:`evaluate_dataset` reads.

    ``scenes``: sample id -> (shape name, Scene). A quick dataset without Blender's renderer: the
    images are the core's own Lambertian renders. One pixel is one scene unit (pixel_size 1).
    """
    dataset_dir = Path(dataset_dir)
    entries = []
    for sample_id, (shape, scene) in scenes.items():
        _dataset.write_sample(dataset_dir / sample_id, image=scene.image, normals=scene.normals, depth=scene.depth,
                              mask=scene.mask, light=scene.light, albedo=scene.albedo,
                              meta={"id": sample_id, "shape": shape, "pixel_size": 1.0, "renderer": "shadecut.render"})
        entries.append({"id": sample_id, "shape": shape, "folder": sample_id, "light": list(scene.light),
                        "albedo": scene.albedo, "size": scene.mask.shape[1], "seed": None})
    _dataset.write_manifest(dataset_dir, entries, {"generator": "shadecut.evaluation.write_synthetic_dataset"})
    return dataset_dir
