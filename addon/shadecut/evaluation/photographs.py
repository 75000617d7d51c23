"""Several photographs of one DiLiGenT object (issue 45): ShadeCut's reconstruction from a set of
photographs with their calibrated lights, beside plain least squares over the same photographs, and
ShadeCut with the lights estimated from the photographs alone (the default hint), scored against the
same measured normals, its lights against the calibrated ones. The library estimates lights from
:data:`shadecut.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS` photographs or more: a smaller set has no
such record.

The sets are :data:`PHOTOGRAPH_SETS` (``scripts/measure_photometric.py`` measures the same); the set
"one" is not reconstructed here: it is the mean of the single-photograph graphcut records the
real-photograph evaluation already holds.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np

from .. import FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS, diligent, reconstruct
from ..imaging import luminance
from ..file_kinds import read_text
from .inputs import EvaluationError, read_manifest
from .metrics import light_error, normal_errors

# Set name -> DiLiGenT image numbers (None: every photograph present). Two lit about 100 degrees
# apart; four and eight lit from around the object.
PHOTOGRAPH_SETS = {"two": (79, 31), "four": (85, 7, 37, 49), "eight": (85, 79, 7, 31, 37, 25, 49, 73), "all": None}
ONE = "one"
SHADECUT = "ShadeCut"
LEAST_SQUARES = "plain least squares"
ESTIMATED = "ShadeCut, lights estimated"
_SHARED_METRICS = ("mean_deg", "median_deg", "under_11.25_pct", "under_22.5_pct", "under_30_pct", "seconds")


def set_label(name: str, images: Optional[Sequence[int]], count: int) -> str:
    """How a set is named in a table: "four (085, 007, 037, 049)", "eight", "all 19"."""
    if images is None:
        return f"{name} {count}"
    return f"{name} ({', '.join(f'{number:03d}' for number in images)})" if len(images) <= 4 else name


def plain_least_squares(photographs: Sequence[np.ndarray], lights: np.ndarray) -> np.ndarray:
    """The baseline: per pixel, the luminances times the pseudo-inverse of the K x 3 lights,
    normalized; every photograph used, nothing left out (shadows and highlights included)."""
    grey = np.stack([luminance(photo) for photo in photographs], axis=-1)
    scaled = grey @ np.linalg.pinv(np.asarray(lights, dtype=np.float64)).T
    return scaled / np.maximum(np.linalg.norm(scaled, axis=-1, keepdims=True), 1e-12)


def median_light_error(estimated: np.ndarray, calibrated: np.ndarray) -> float:
    """The median, over a set's photographs, of the angle in degrees between each estimated light and
    its calibrated one (K x 3 each, any lengths)."""
    return float(np.median([light_error(found, truth) for found, truth in zip(estimated, calibrated)]))


def _source_folder(dataset_dir: Path) -> Path:
    """The DiLiGenT object folder a dataset was imported from (its first sample's meta.json says)."""
    first = read_manifest(dataset_dir)[0]["folder"]
    return Path(json.loads(read_text(dataset_dir / first / "meta.json"))["source_folder"])


def _scored(set_name: str, count: int, method: str, images: list, run: Callable[[], tuple], truth,
            light: str = "calibrated") -> dict:
    """One record: ``run`` returns (normals, extra fields); scored on the eroded mask, timed.
    ``light``: "calibrated" or "estimated", the lights the method was given."""
    record = {"set": set_name, "count": count, "method": method, "light": light, "images": images, "status": "ok"}
    start = time.perf_counter()
    try:
        normals, extra = run()
        record["seconds"] = time.perf_counter() - start
        record.update(normal_errors(normals, truth.normals, truth.mask), **extra)
    except ValueError as error:
        record.update(status="failed", error=str(error).removeprefix("shadecut: "))
    return record


def _set_records(set_name: str, chosen: list, loaded: diligent.DiligentObject) -> list[dict]:
    """ShadeCut and plain least squares on the photographs ``chosen`` (indices into ``loaded``), then
    ShadeCut with the lights estimated when the set has enough photographs for it."""
    photos = [loaded.photos[i] for i in chosen]
    lights = loaded.lights[chosen]
    names = [loaded.names[i] for i in chosen]

    def ours(given: Optional[np.ndarray]):
        result = reconstruct(photos, given, loaded.mask)
        extra = {"two_lit_share": float(result.stats.pair_pixels / loaded.mask.sum())}
        if given is None:
            extra.update(light_error_deg=median_light_error(result.lights, lights),
                         light_uncertainty_deg=float(result.stats.light_uncertainty))
        return result.normals, extra

    def baseline():
        return np.where(loaded.mask[..., None], plain_least_squares(photos, lights), 0.0), {}

    records = [_scored(set_name, len(chosen), SHADECUT, names, lambda: ours(lights), loaded),
               _scored(set_name, len(chosen), LEAST_SQUARES, names, baseline, loaded)]
    if len(chosen) >= FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS:
        records.append(_scored(set_name, len(chosen), ESTIMATED, names, lambda: ours(None), loaded, "estimated"))
    return records


def one_photograph_record(summary: dict) -> Optional[dict]:
    """The set "one": the mean of graphcut's single-photograph records under the calibrated light
    (``summary`` is the object's summary), or None when graphcut was not evaluated."""
    graphcut = summary["calibrated"]["methods"].get("graphcut")
    if graphcut is None or graphcut["mean_deg"] is None:
        return None
    record = {"set": ONE, "count": 1, "method": SHADECUT, "light": "calibrated",
              "images": f"each of the {graphcut['samples']} photographs alone (graphcut, mean)",
              "status": "ok"}
    record.update({name: graphcut[name] for name in _SHARED_METRICS})
    return record


def _outcome(record: dict) -> str:
    """One record in a log line: its method and mean error (with the light error when estimated)."""
    if record["status"] != "ok":
        return f"{record['method']} failed: {record['error']}"
    lights = (f" (light error {record['light_error_deg']:.1f}°, median)" if record.get("light_error_deg") is not None
              else "")
    return f"{record['method']} {record['mean_deg']:.2f}°{lights}"


def evaluate_sets(dataset_dir: Path, summary: dict, log: Callable[[str], None] = print) -> list[dict]:
    """The object's "photographs" records: the set "one" from ``summary``, then each of
    :data:`PHOTOGRAPH_SETS` whose photographs are all present (the others skipped with a log line),
    with the lights estimated too where the set has enough photographs (else a log line says so)."""
    records = []
    try:
        loaded = diligent.load_object(_source_folder(dataset_dir))
    except (OSError, ValueError, KeyError, IndexError, EvaluationError) as error:
        log(f"several photographs of {dataset_dir.name}: cannot read the source object: {error}")
        return records
    one = one_photograph_record(summary)
    records += [one] if one else []
    numbers = [int(Path(name).stem) if Path(name).stem.isdigit() else None for name in loaded.names]
    for set_name, images in PHOTOGRAPH_SETS.items():
        missing = [n for n in images or () if n not in numbers]
        if missing:
            log(f"several photographs of {dataset_dir.name}: the set {set_name} skipped "
                f"({', '.join(f'{n:03d}' for n in missing)} not present)")
            continue
        chosen = list(range(len(numbers))) if images is None else [numbers.index(n) for n in images]
        measured = _set_records(set_name, chosen, loaded)
        records += measured
        unestimated = ([f"lights not estimated (fewer than {FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS} photographs)"]
                       if len(chosen) < FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS else [])
        log(f"several photographs of {dataset_dir.name}, {set_label(set_name, images, len(chosen))}: "
            + "; ".join([_outcome(r) for r in measured] + unestimated))
    return records
