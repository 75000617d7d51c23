"""Running the methods on ground-truth samples: one sample, a whole dataset, the paper's experiment.

A record is one (sample, method) pair: a flat dict of the metrics, or ``status == "failed"`` with
the error message.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np

from .. import estimate_light, reconstruct, synthetic
from .. import dataset as _dataset
from .figures import save_strip
from .inputs import read_manifest
from .metrics import ERODE_PIXELS, METRICS, depth_errors, light_error, normal_errors
from .summary import summarize

PAPER_LIGHT = (1.0, 0.0, 1.0)  # the paper's experiment: Mozart lit from the right-front


@dataclass
class SampleResult:
    """What :func:`evaluate_sample` measured on one ground-truth sample."""

    sample: dict  # id, shape, true and used light and albedo, light_error_deg, size
    records: list[dict]  # one per method
    reconstructions: dict = field(default_factory=dict)  # method -> Reconstruction, for the figures
    truth: object = None  # the ground truth measured against (Sample or Scene), for the figures


def _record(sample_id: str, shape: str, method: str) -> dict:
    return {"sample": sample_id, "shape": shape, "method": method, "status": "ok",
            **{name: None for name in METRICS}, "error": None}


def evaluate_sample(sample_id: str, shape: str, truth, methods: Sequence[str], *,
                    light_method: Optional[str] = None, options: Optional[dict] = None) -> SampleResult:
    """Reconstructs one sample with every method and measures each against the truth.

    ``truth`` has ``image``, ``normals``, ``depth``, ``mask``, ``light`` and ``albedo`` (a
    dataset Sample or a synthetic Scene; ``albedo`` None = unknown, as for a photograph: the methods
    then get albedo None and estimate it; ``depth`` None = unknown: no depth metrics). The methods
    get the true light and albedo, as in the paper, or with ``light_method`` (one of
    shadecut.LIGHT_METHODS) those that
    :func:`shadecut.estimate_light` finds with that estimator (one estimate per sample, shared by
    all methods); default parameters otherwise, with ``options`` (ReconstructOptions fields, e.g.
    ``{"fit_shading": True}``) set for every method. A method that raises, or whose result is
    not finite, is recorded as failed with its message; the others go on.
    """
    true_light = np.asarray(truth.light, dtype=np.float64)
    true_light = true_light / np.linalg.norm(true_light)
    known_albedo = None if truth.albedo is None else float(truth.albedo)
    # An unknown albedo: used_albedo is the one reconstruct() estimated (the same for every method).
    info = {"id": sample_id, "shape": shape, "size": list(truth.mask.shape), "light": true_light.tolist(),
            "albedo": known_albedo, "used_light": true_light.tolist(), "used_albedo": known_albedo,
            "light_error_deg": None}
    records = [_record(sample_id, shape, method) for method in methods]
    light, albedo = true_light, known_albedo
    if light_method is not None:
        try:
            light, albedo = estimate_light(truth.image, truth.mask, light_method)
        except ValueError as error:
            for record in records:
                record.update(status="failed", error=f"light estimation: {error}")
            return SampleResult(info, records, truth=truth)
        light = np.asarray(light, dtype=np.float64)
        info.update(used_light=light.tolist(), used_albedo=float(albedo),
                    light_error_deg=light_error(light, true_light))

    reconstructions = {}
    for record in records:
        method = record["method"]
        try:
            result = reconstruct(truth.image, light, truth.mask, albedo, method=method, **(options or {}))
        # Whatever one method raises on one sample is that method's result there: recorded, and the
        # run goes on. BaseException (Ctrl-C) still stops the run.
        except Exception as error:  # noqa: BLE001
            record.update(status="failed", error=f"{type(error).__name__}: {error}")
            continue
        try:
            record.update(normal_errors(result.normals, truth.normals, truth.mask))
            if truth.depth is not None:
                record.update(depth_errors(result.depth, truth.depth, truth.mask))
        except ValueError as error:
            record.update(status="failed", error=str(error))
            continue
        record["seconds"] = float(result.stats.seconds["total"])
        if info["used_albedo"] is None:
            info["used_albedo"] = float(result.albedo)
        record["light_error_deg"] = info["light_error_deg"]
        reconstructions[method] = result
    return SampleResult(info, records, reconstructions, truth)


@dataclass
class Evaluation:
    """A whole run: the samples, one record per (sample, method), and its summary."""

    settings: dict
    samples: list[dict]
    records: list[dict]
    paper: Optional[dict] = None  # the paper's experiment: its sample, records and summary
    real: Optional[dict] = None  # real photographs (see .real): settings, and per object records and summary

    @property
    def summary(self) -> dict:
        return summarize(self.records)

    @property
    def failed(self) -> list[dict]:
        return [r for r in self.all_records if r["status"] != "ok"]

    @property
    def all_records(self) -> list[dict]:
        """The records of the dataset, then of the paper's experiment, then of the real photographs."""
        real = [r for part in (self.real or {}).get("objects", {}).values() for r in part["records"]]
        return self.records + (self.paper["records"] if self.paper else []) + real


def _progress_line(index: int, total: int, result: SampleResult) -> str:
    parts = []
    for record in result.records:
        if record["status"] == "ok":
            parts.append(f"{record['method']} {record['mean_deg']:.2f}° {record['seconds']:.2f} s")
        else:
            parts.append(f"{record['method']} FAILED ({record['error']})")
    light = result.sample["light_error_deg"]
    light_text = f", light error {light:.2f}°" if light is not None else ""
    return f"[{index}/{total}] {result.sample['id']} ({result.sample['shape']}{light_text}): " + "; ".join(parts)


def evaluate_dataset(dataset_dir: os.PathLike | str, methods: Sequence[str], *,
                     light_method: Optional[str] = None, options: Optional[dict] = None,
                     figures_dir: Optional[os.PathLike | str] = None,
                     log: Callable[[str], None] = print) -> Evaluation:
    """Evaluates every sample of a dataset (made by make_dataset.py or dataset.write_sample).

    ``light_method``: None = the true light and albedo; else the estimator that gives them;
    ``options``: set for every method (see :func:`evaluate_sample`). Prints one progress line per
    sample through ``log``; with ``figures_dir``, writes a strip per sample there (``<id>.png``). A
    sample whose files cannot be read is recorded as failed for every method.
    """
    dataset_dir = Path(dataset_dir)
    entries = read_manifest(dataset_dir)
    samples, records = [], []
    for index, entry in enumerate(entries, 1):
        sample_id, shape = str(entry["id"]), str(entry["shape"])
        try:
            truth = _dataset.load_sample(dataset_dir / entry["folder"])
        except (OSError, ValueError, KeyError) as error:
            result = SampleResult({"id": sample_id, "shape": shape, "light_error_deg": None},
                                  [_record(sample_id, shape, m) for m in methods])
            for record in result.records:
                record.update(status="failed", error=f"cannot read the sample {entry['folder']}: {error}")
        else:
            result = evaluate_sample(sample_id, shape, truth, methods, light_method=light_method, options=options)
            if figures_dir is not None:
                save_strip(Path(figures_dir) / f"{sample_id}.png", f"{sample_id} ({shape})", truth,
                           result.reconstructions, result.records)
        log(_progress_line(index, len(entries), result))
        samples.append(result.sample)
        records.extend(result.records)
    settings = {"dataset": str(dataset_dir), "methods": list(methods), "light_method": light_method,
                "options": dict(options or {}), "erode_pixels": ERODE_PIXELS}
    return Evaluation(settings, samples, records)


def paper_experiment(mozart_path: os.PathLike | str, methods: Sequence[str], *, options: Optional[dict] = None,
                     figures_dir: Optional[os.PathLike | str] = None,
                     log: Callable[[str], None] = print) -> tuple[dict, SampleResult]:
    """The paper's experiment: the Mozart depth map rendered under light (1, 0, 1), every method.

    True light and albedo, as in the paper; ``options`` as for :func:`evaluate_sample`. Returns the
    paper section of results.json (sample, records, summary) and the SampleResult with the truth and
    reconstructions (for the 3-D figure).
    """
    truth = synthetic.mozart(mozart_path, PAPER_LIGHT)
    result = evaluate_sample("mozart_paper", "mozart", truth, methods, options=options)
    if figures_dir is not None:
        save_strip(Path(figures_dir) / "mozart_paper.png", "Mozart, light (1, 0, 1)", truth,
                   result.reconstructions, result.records)
    log(_progress_line(1, 1, result))
    section = {"sample": result.sample, "records": result.records, "summary": summarize(result.records)}
    return section, result
