"""Real photographs: DiLiGenT objects imported as datasets, every method run with the calibrated and
with the estimated light (the albedo always estimated), beside the floor of a flat plane.

The flat plane is the normal (0, 0, 1) at every pixel: what a method scores by reconstructing
nothing. A method below it on a photograph has learned nothing from the shading there.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from types import SimpleNamespace
from typing import Callable, Optional, Sequence

import numpy as np

from .. import ReconstructOptions, diligent
from .. import dataset as _dataset
from ..atomic_write import write_text
from ..file_kinds import read_text
from .figures import save_strip
from .inputs import EvaluationError, read_manifest
from .metrics import ERODE_PIXELS, normal_errors
from .photographs import PHOTOGRAPH_SETS, evaluate_sets
from .summary import aggregate, summarize
from .runner import _progress_line, _record, evaluate_sample

FLAT = "flat plane"
LIGHTS = ("calibrated", "estimated")
_COMPLETE = ".complete"


def default_estimator() -> str:
    """The light estimator :func:`shadecut.reconstruct` uses when given no light."""
    return ReconstructOptions().light_method_used().name


def find_objects(path: os.PathLike | str) -> list[Path]:
    """The DiLiGenT object folders at ``path`` (an object folder, or a folder of them), checked.

    EvaluationError when the path does not exist, holds no object folder, or one of them is not in
    the benchmark's layout (the message names the path and what is missing).
    """
    path = Path(path)
    if not path.is_dir():
        raise EvaluationError(f"the DiLiGenT folder {path} does not exist")
    if diligent.is_object_folder(path):
        objects = [path]
    else:
        objects = sorted(p for p in path.iterdir() if p.is_dir() and diligent.is_object_folder(p))
    if not objects:
        raise EvaluationError(f"{path} is neither a DiLiGenT object folder (with {', '.join(diligent.REQUIRED)} "
                              "and NNN.png images) nor a folder of such folders")
    names = [diligent.object_name(folder) for folder in objects]
    if len(set(names)) != len(names):
        raise EvaluationError(f"{path} holds two object folders of one name: {names}")
    for folder in objects:
        try:
            diligent.read_layout(folder)
        except (OSError, ValueError) as error:
            raise EvaluationError(str(error).removeprefix("shadecut: ")) from None
    return objects


def import_objects(objects: Sequence[Path], out_dir: os.PathLike | str,
                   log: Callable[[str], None] = print) -> dict[str, Path]:
    """Imports each object folder into ``out_dir/<object>`` unless an earlier run completed it there.

    A marker written after the import names the source folder; a missing marker (or another source)
    means a new import. Returns object name -> dataset folder. EvaluationError for unreadable data.
    """
    folders, new_out = {}, not Path(out_dir).exists()
    try:
        for source in objects:
            folders[diligent.object_name(source)] = _imported(Path(source), Path(out_dir), log)
    except EvaluationError:
        if new_out:  # a refused import leaves no empty folder of its own (the object's is gone already)
            with contextlib.suppress(OSError):
                Path(out_dir).rmdir()
        raise
    return folders


def _imported(source: Path, out_dir: Path, log: Callable[[str], None]) -> Path:
    """The dataset folder of one DiLiGenT object, imported into ``out_dir`` unless done before."""
    target = out_dir / diligent.object_name(source)
    marker = target / _COMPLETE
    if marker.is_file() and read_text(marker).strip() == str(source.resolve()):
        log(f"reusing the imported DiLiGenT object {target}")
        return target
    log(f"importing the DiLiGenT object {source} into {target}")
    try:
        diligent.import_diligent(source, target)
    except (OSError, ValueError) as error:
        raise EvaluationError(str(error).removeprefix("shadecut: ")) from None
    write_text(marker, f"{source.resolve()}\n")
    return target


def flat_record(sample_id: str, shape: str, truth) -> dict:
    """The flat plane's record on one sample: normal (0, 0, 1) everywhere against the truth."""
    record = _record(sample_id, shape, FLAT)
    record["light"] = None  # the same under any light
    flat = np.zeros((*truth.mask.shape, 3), dtype=np.float32)
    flat[..., 2] = 1
    try:
        record.update(normal_errors(flat, truth.normals, truth.mask))
    except ValueError as error:
        record.update(status="failed", error=str(error))
    return record


def _cropped(truth, reconstructions: dict, margin: int = 8):
    """The truth and normals cut to the mask's bounding box (plus a margin), for a readable strip."""
    rows, cols = np.nonzero(truth.mask)
    box = (slice(max(rows.min() - margin, 0), rows.max() + margin + 1),
           slice(max(cols.min() - margin, 0), cols.max() + margin + 1))
    cut = SimpleNamespace(image=truth.image[box], normals=truth.normals[box], mask=truth.mask[box], light=truth.light)
    return cut, {m: SimpleNamespace(normals=r.normals[box]) for m, r in reconstructions.items()}


def evaluate_object(dataset_dir: os.PathLike | str, methods: Sequence[str], *, options: Optional[dict] = None,
                    figures_dir: Optional[os.PathLike | str] = None,
                    log: Callable[[str], None] = print) -> dict:
    """Evaluates every sample of one imported object with the calibrated and the estimated light.

    The estimated light is :func:`default_estimator`'s (what reconstruct(light=None) uses); the
    albedo is estimated in both cases (the samples record none). Returns the object's part of the
    real-photograph section: ``samples``, ``records`` (each with ``light``: "calibrated",
    "estimated", or None for the flat plane), ``summary`` (``flat``, and summarize() per light) and
    ``figures`` (the strips of the first sample, one per light, under ``figures_dir``) and
    ``photographs`` (several photographs at once, calibrated lights: :func:`.photographs.evaluate_sets`).
    """
    dataset_dir = Path(dataset_dir)
    entries = read_manifest(dataset_dir)
    estimator = default_estimator()
    samples, records, figures = [], [], []
    for index, entry in enumerate(entries, 1):
        sample_id, shape = str(entry["id"]), str(entry["shape"])
        try:
            truth = _dataset.load_sample(dataset_dir / entry["folder"])
        except (OSError, ValueError, KeyError) as error:
            for light in (None, *LIGHTS):
                for method in (FLAT,) if light is None else methods:
                    records.append({**_record(sample_id, shape, method), "light": light, "status": "failed",
                                    "error": f"cannot read the sample {entry['folder']}: {error}"})
            log(f"[{index}/{len(entries)}] {sample_id}: cannot read the sample: {error}")
            continue
        flat = flat_record(sample_id, shape, truth)
        records.append(flat)
        for light, light_method in zip(LIGHTS, (None, estimator)):
            result = evaluate_sample(sample_id, shape, truth, methods, light_method=light_method, options=options)
            for record in result.records:
                record["light"] = light
            records.extend(result.records)
            samples.append({**result.sample, "light": light})
            flat_text = f"{flat['mean_deg']:.2f}°" if flat["status"] == "ok" else "failed"
            head, tail = _progress_line(index, len(entries), result).split(": ", 1)
            log(f"{head}, {light} light: {FLAT} {flat_text}; {tail}")
            if figures_dir is not None and index == 1:
                path = Path(figures_dir) / f"diligent_{shape}_{light}.png"
                flat_normals = SimpleNamespace(normals=np.broadcast_to(np.float32([0, 0, 1]), truth.normals.shape))
                cut, cut_results = _cropped(truth, {FLAT: flat_normals, **result.reconstructions})
                title = f"{sample_id} ({light} light" + (f", {estimator})" if light_method else ")")
                save_strip(path, title, cut, cut_results, [flat] + result.records)
                figures.append(path)
    summary = {"flat": aggregate([r for r in records if r["method"] == FLAT])}
    summary.update({light: summarize([r for r in records if r["light"] == light]) for light in LIGHTS})
    return {"dataset": str(dataset_dir), "samples": samples, "records": records, "summary": summary,
            "figures": [str(path) for path in figures], "photographs": evaluate_sets(dataset_dir, summary, log)}


def evaluate_real(objects: dict[str, Path], methods: Sequence[str], *, options: Optional[dict] = None,
                  figures_dir: Optional[os.PathLike | str] = None, log: Callable[[str], None] = print) -> dict:
    """The real-photograph section of results.json: ``settings`` and ``objects`` (name -> the part
    :func:`evaluate_object` returns), for ``objects`` (name -> imported dataset folder)."""
    parts = {}
    for name, folder in objects.items():
        log(f"real photographs: {name} ({folder})")
        parts[name] = evaluate_object(folder, methods, options=options, figures_dir=figures_dir, log=log)
    settings = {"source": "DiLiGenT", "citation": diligent.CITATION, "methods": list(methods),
                "estimator": default_estimator(), "options": dict(options or {}), "albedo": "estimated",
                "erode_pixels": ERODE_PIXELS, "photograph_sets": {k: v and list(v) for k, v in PHOTOGRAPH_SETS.items()},
                "objects": {name: str(folder) for name, folder in objects.items()}}
    return {"settings": settings, "objects": parts}
