"""Measuring reconstructions against ground truth: metrics, aggregates, reports and figures.

Used by ``blender_scripts/eval.py`` (which adds Blender's 3-D renders) and usable on its own; no
``bpy`` here. Every metric is taken on the ground-truth mask eroded by :data:`ERODE_PIXELS`, where
the central differences of the image and of the true normals see no background.

A record is one (sample, method) pair: a flat dict of the metrics below, or ``status == "failed"``
with the error message. Angles are in degrees, depth in pixel units.
"""

from __future__ import annotations

import csv
import json
import math
import os
import tempfile
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np

from . import METHODS, angular_error_map, erode_mask, estimate_light, reconstruct, synthetic
from . import dataset as _dataset

ERODE_PIXELS = 2
THRESHOLDS = (11.25, 22.5, 30.0)  # degrees, the customary shares of shape-from-shading papers
PAPER_LIGHT = (1.0, 0.0, 1.0)  # the paper's experiment: Mozart lit from the right-front

# The numeric columns of a record, in the order of results.csv and of the tables.
METRICS = (
    "mean_deg",
    "median_deg",
    "under_11.25_pct",
    "under_22.5_pct",
    "under_30_pct",
    "depth_rmse",
    "depth_rmse_scaled",
    "depth_scale",
    "seconds",
    "light_error_deg",
)
CSV_COLUMNS = ("sample", "shape", "method", "status", *METRICS, "error")


class EvaluationError(Exception):
    """Input the user can fix (dataset, method names, output folder); the message says what."""


def normal_errors(normals: np.ndarray, truth: np.ndarray, mask: np.ndarray, erode: int = ERODE_PIXELS) -> dict:
    """Mean and median angular error and the share (percent) of pixels under each of THRESHOLDS.

    Taken on ``mask`` eroded by ``erode`` pixels. Raises ValueError when the eroded mask is empty or
    the normals are not finite there (a method that produced NaN has failed, not scored 0).
    """
    inside = erode_mask(mask, erode)
    errors = angular_error_map(normals, truth, inside)[inside]
    if errors.size == 0:
        raise ValueError(f"the mask eroded by {erode} pixels is empty: nothing to measure")
    if not np.isfinite(errors).all():
        raise ValueError("the reconstructed normals are not finite (or are zero) on the mask")
    metrics = {"mean_deg": float(np.mean(errors, dtype=np.float64)), "median_deg": float(np.median(errors))}
    for threshold in THRESHOLDS:
        metrics[f"under_{threshold:g}_pct"] = float(100.0 * np.count_nonzero(errors < threshold) / errors.size)
    return metrics


def mask_parts(mask: np.ndarray) -> np.ndarray:
    """Labels the 4-connected parts of a mask: each pixel gets the smallest flat index of its part.

    Outside the mask the label is ``mask.size``. Labels spread to the smaller 4-neighbour, then jump
    to the label of the pixel they name (pointer jumping), so that long, thin parts settle in a few
    sweeps instead of one sweep per pixel of their length. Numpy only: the add-on runs inside
    Blender builds that bundle numpy but no scipy.
    """
    mask = np.asarray(mask, dtype=bool)
    outside = mask.size
    labels = np.where(mask, np.arange(mask.size).reshape(mask.shape), outside)
    while True:
        spread = labels.copy()
        np.minimum(spread[1:], labels[:-1], out=spread[1:])
        np.minimum(spread[:-1], labels[1:], out=spread[:-1])
        np.minimum(spread[:, 1:], labels[:, :-1], out=spread[:, 1:])
        np.minimum(spread[:, :-1], labels[:, 1:], out=spread[:, :-1])
        spread = np.where(mask, spread, outside)
        spread = np.append(spread.ravel(), outside)[spread]
        if np.array_equal(spread, labels):
            return labels
        labels = spread


def depth_errors(depth: np.ndarray, truth: np.ndarray, mask: np.ndarray, erode: int = ERODE_PIXELS) -> dict:
    """Depth RMSE after the best offset, and after the best scale and offset, on the eroded mask.

    Shape from shading fixes depth only up to a constant per connected part of the mask (4-neighbour
    parts, as the integrator), so each part gets its own best offset; the scale is one for the image.
    Returns ``depth_rmse``, ``depth_rmse_scaled`` and the fitted ``depth_scale`` (truth ~ scale *
    depth + offsets; 1 for a reconstruction of the right amplitude).
    """
    inside = erode_mask(mask, erode)
    if not inside.any():
        raise ValueError(f"the mask eroded by {erode} pixels is empty: nothing to measure")
    _, part = np.unique(mask_parts(mask)[inside], return_inverse=True)  # parts numbered 0, 1, ...
    pixels = np.bincount(part)

    def centred(values: np.ndarray) -> np.ndarray:
        values = values[inside].astype(np.float64)
        return values - (np.bincount(part, weights=values) / pixels)[part]

    estimate, true = centred(np.asarray(depth)), centred(np.asarray(truth))
    if not np.isfinite(estimate).all():
        raise ValueError("the reconstructed depth is not finite on the mask")
    power = float(np.dot(estimate, estimate))
    scale = float(np.dot(estimate, true)) / power if power > 0 else 0.0
    return {
        "depth_rmse": float(np.sqrt(np.mean((estimate - true) ** 2))),
        "depth_rmse_scaled": float(np.sqrt(np.mean((true - scale * estimate) ** 2))),
        "depth_scale": scale,
    }


def light_error(estimated: Sequence[float], truth: Sequence[float]) -> float:
    """The angle in degrees between two light directions (either length)."""
    a = np.asarray(estimated, dtype=np.float64)
    b = np.asarray(truth, dtype=np.float64)
    # atan2 of |a x b| and a . b stays accurate for small angles, where arccos of the cosine does not.
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b))))


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
    """Creates the output folder and checks that files can be written in it."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        # A real write: permissions, read-only mounts and full disks all show up here, before any work.
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as error:
        raise EvaluationError(f"cannot write to the output folder {folder}: {error.strerror or error}") from None
    return folder


def read_manifest(dataset_dir: os.PathLike | str) -> list[dict]:
    """The dataset's manifest entries, checked; EvaluationError for a missing or malformed dataset."""
    dataset_dir = Path(dataset_dir)
    if not dataset_dir.is_dir():
        raise EvaluationError(f"the dataset folder {dataset_dir} does not exist")
    try:
        entries = _dataset.load_manifest(dataset_dir)
    # json.JSONDecodeError is a ValueError; a manifest of the wrong JSON type fails on .get or [].
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as error:
        raise EvaluationError(f"the dataset {dataset_dir} has no readable manifest: {error}") from None
    if not isinstance(entries, list) or not all(isinstance(entry, dict) for entry in entries):
        raise EvaluationError(f"the manifest of {dataset_dir} does not hold a list of samples")
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
                    light_method: Optional[str] = None) -> SampleResult:
    """Reconstructs one sample with every method and measures each against the truth.

    ``truth`` has ``image``, ``normals``, ``depth``, ``mask``, ``light`` and ``albedo`` (a
    dataset Sample or a synthetic Scene). The methods get the true light and albedo, as in the
    paper, or with ``light_method`` (one of shadecut.LIGHT_METHODS) those that
    :func:`shadecut.estimate_light` finds with that estimator (one estimate per sample, shared by
    all methods); default parameters otherwise. A method that raises, or whose result is
    not finite, is recorded as failed with its message; the others go on.
    """
    true_light = np.asarray(truth.light, dtype=np.float64)
    true_light = true_light / np.linalg.norm(true_light)
    info = {"id": sample_id, "shape": shape, "size": list(truth.mask.shape), "light": true_light.tolist(),
            "albedo": float(truth.albedo), "used_light": true_light.tolist(), "used_albedo": float(truth.albedo),
            "light_error_deg": None}
    records = [_record(sample_id, shape, method) for method in methods]
    light, albedo = true_light, float(truth.albedo)
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
            result = reconstruct(truth.image, light, truth.mask, albedo, method=method)
        # Whatever one method raises on one sample is that method's result there: recorded, and the
        # run goes on. BaseException (Ctrl-C) still stops the run.
        except Exception as error:  # noqa: BLE001
            record.update(status="failed", error=f"{type(error).__name__}: {error}")
            continue
        try:
            record.update(normal_errors(result.normals, truth.normals, truth.mask))
            record.update(depth_errors(result.depth, truth.depth, truth.mask))
        except ValueError as error:
            record.update(status="failed", error=str(error))
            continue
        record["seconds"] = float(result.stats.seconds["total"])
        record["light_error_deg"] = info["light_error_deg"]
        reconstructions[method] = result
    return SampleResult(info, records, reconstructions, truth)


def _mean(values: list) -> Optional[float]:
    values = [v for v in values if v is not None]
    return float(np.mean(values)) if values else None


def _aggregate(records: list[dict]) -> dict:
    done = [r for r in records if r["status"] == "ok"]
    summary = {"samples": len(done), "failed": len(records) - len(done)}
    summary.update({name: _mean([r[name] for r in done]) for name in METRICS})
    return summary


def summarize(records: list[dict]) -> dict:
    """Means over samples per method and per (shape, method), and the ranking.

    The ranking orders the methods by their mean angular error; a method that failed on some sample
    is ranked after every method that did not, since its mean covers fewer (possibly easier) samples.
    """
    methods = list(dict.fromkeys(r["method"] for r in records))
    shapes = list(dict.fromkeys(r["shape"] for r in records))
    per_method = {m: _aggregate([r for r in records if r["method"] == m]) for m in methods}
    per_shape = {
        s: {m: _aggregate([r for r in records if r["shape"] == s and r["method"] == m]) for m in methods}
        for s in shapes
    }
    ranking = sorted(
        methods,
        key=lambda m: (per_method[m]["failed"] > 0, math.inf if per_method[m]["mean_deg"] is None
                       else per_method[m]["mean_deg"]),
    )
    return {"methods": per_method, "shapes": per_shape, "ranking": ranking}


def _cell(value: Optional[float], digits: int = 2) -> str:
    return "—" if value is None else f"{value:.{digits}f}"


def method_table(summary: dict) -> str:
    """The ranking as a Markdown table: one row per method, the mean of every metric over samples."""
    with_light = any(s["light_error_deg"] is not None for s in summary["methods"].values())
    header = ["rank", "method", "mean °", "median °", "< 11.25° %", "< 22.5° %", "< 30° %", "depth RMSE",
              "RMSE scale+offset", "seconds", "failed"] + (["light error °"] if with_light else [])
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for rank, method in enumerate(summary["ranking"], 1):
        s = summary["methods"][method]
        row = [str(rank), method, _cell(s["mean_deg"]), _cell(s["median_deg"]), _cell(s["under_11.25_pct"], 1),
               _cell(s["under_22.5_pct"], 1), _cell(s["under_30_pct"], 1), _cell(s["depth_rmse"]),
               _cell(s["depth_rmse_scaled"]), _cell(s["seconds"], 3), f"{s['failed']}/{s['samples'] + s['failed']}"]
        if with_light:
            row.append(_cell(s["light_error_deg"]))
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def shape_table(summary: dict) -> str:
    """Mean angular error per shape (rows) and method (columns, in ranking order), Markdown."""
    methods = summary["ranking"]
    lines = ["| shape | " + " | ".join(methods) + " |", "|---|" + "---|" * len(methods)]
    for shape, by_method in summary["shapes"].items():
        lines.append(f"| {shape} | " + " | ".join(_cell(by_method[m]["mean_deg"]) for m in methods) + " |")
    return "\n".join(lines)


def _normal_colours(normals: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The usual normal-map colours (n + 1) / 2, white outside the mask."""
    return np.where(mask[..., None], np.clip((normals + 1) / 2, 0, 1), 1.0)


def save_strip(path: os.PathLike | str, title: str, truth, reconstructions: dict, records: list[dict],
               erode: int = ERODE_PIXELS) -> None:
    """A figure of one sample: the input and the true normals, then a column per method.

    Top row: input, true normals, each method's normals; bottom row, under each method: its
    angular-error map on the eroded mask. The error maps share one colour scale, 0 to 90 degrees,
    with its colour bar at the right end; a failed method's column says so and shows its error.
    """
    # The object-oriented API with its own Agg canvas leaves pyplot's global backend alone.
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    inside = erode_mask(truth.mask, erode)
    columns = 2 + len(records)
    figure = Figure(figsize=(1.9 * columns + 0.6, 4.3))
    FigureCanvasAgg(figure)
    # A narrow last column holds the colour bar, so that no panel shrinks to make room for it.
    axes = figure.subplots(2, columns + 1, gridspec_kw={"width_ratios": [1] * columns + [0.07]})
    for axis in axes.flat:
        axis.set_axis_off()
    axes[0, 0].imshow(truth.image, cmap="gray", vmin=0, vmax=max(float(truth.image.max()), 1e-6))
    axes[0, 0].set_title("input", fontsize=9)
    axes[0, 1].imshow(_normal_colours(truth.normals, truth.mask))
    axes[0, 1].set_title("true normals", fontsize=9)
    light = np.asarray(truth.light, dtype=np.float64) / np.linalg.norm(truth.light)
    axes[1, 0].text(0.0, 0.5, "light ({:.2f}, {:.2f}, {:.2f})\n\nthis row: angular error\non the mask eroded\n"
                    "by {} pixels".format(*light, erode), fontsize=8, va="center", transform=axes[1, 0].transAxes)
    shown = None
    for column, record in enumerate(records, 2):
        method = record["method"]
        if record["status"] != "ok":
            axes[0, column].set_title(f"{method}: failed", fontsize=9)
            axes[0, column].text(0.5, 0.5, textwrap.fill(record["error"] or "", 30), ha="center", va="center",
                                 fontsize=6, transform=axes[0, column].transAxes)
            continue
        axes[0, column].imshow(_normal_colours(reconstructions[method].normals, truth.mask))
        axes[0, column].set_title(method, fontsize=9)
        error_map = angular_error_map(reconstructions[method].normals, truth.normals, inside)
        shown = axes[1, column].imshow(error_map, cmap="magma", vmin=0, vmax=90)
        axes[1, column].set_title(f"mean {record['mean_deg']:.1f}°, median {record['median_deg']:.1f}°", fontsize=8)
    if shown is not None:
        axes[1, -1].set_axis_on()
        figure.colorbar(shown, cax=axes[1, -1], label="degrees")
    figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=72)


@dataclass
class Evaluation:
    """A whole run: the samples, one record per (sample, method), and its summary."""

    settings: dict
    samples: list[dict]
    records: list[dict]
    paper: Optional[dict] = None  # the paper's experiment: its sample, records and summary

    @property
    def summary(self) -> dict:
        return summarize(self.records)

    @property
    def failed(self) -> list[dict]:
        return [r for r in self.records + (self.paper["records"] if self.paper else []) if r["status"] != "ok"]


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
                     light_method: Optional[str] = None, figures_dir: Optional[os.PathLike | str] = None,
                     log: Callable[[str], None] = print) -> Evaluation:
    """Evaluates every sample of a dataset (made by make_dataset.py or dataset.write_sample).

    ``light_method``: None = the true light and albedo; else the estimator that gives them (see
    :func:`evaluate_sample`). Prints one progress line per sample through ``log``; with
    ``figures_dir``, writes a strip per sample there (``<id>.png``). A sample whose files cannot be
    read is recorded as failed for every method.
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
            result = evaluate_sample(sample_id, shape, truth, methods, light_method=light_method)
            if figures_dir is not None:
                save_strip(Path(figures_dir) / f"{sample_id}.png", f"{sample_id} ({shape})", truth,
                           result.reconstructions, result.records)
        log(_progress_line(index, len(entries), result))
        samples.append(result.sample)
        records.extend(result.records)
    settings = {"dataset": str(dataset_dir), "methods": list(methods), "light_method": light_method,
                "erode_pixels": ERODE_PIXELS}
    return Evaluation(settings, samples, records)


def paper_experiment(mozart_path: os.PathLike | str, methods: Sequence[str], *,
                     figures_dir: Optional[os.PathLike | str] = None,
                     log: Callable[[str], None] = print) -> tuple[dict, SampleResult]:
    """The paper's experiment: the Mozart depth map rendered under light (1, 0, 1), every method.

    True light and albedo, as in the paper. Returns the paper section of results.json (sample,
    records, summary) and the SampleResult with the truth and reconstructions (for the 3-D figure).
    """
    truth = synthetic.mozart(mozart_path, PAPER_LIGHT)
    result = evaluate_sample("mozart_paper", "mozart", truth, methods)
    if figures_dir is not None:
        save_strip(Path(figures_dir) / "mozart_paper.png", "Mozart, light (1, 0, 1)", truth,
                   result.reconstructions, result.records)
    log(_progress_line(1, 1, result))
    section = {"sample": result.sample, "records": result.records, "summary": summarize(result.records)}
    return section, result


def _json_ready(value):
    """Plain JSON: NaN and infinities (a diverged method) become null instead of invalid JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    return value


def write_results(out_dir: os.PathLike | str, evaluation: Evaluation, figures: Sequence[str] = ()) -> dict:
    """Writes results.json, results.csv (one row per sample and method) and report.md.

    ``figures``: PNG paths relative to ``out_dir`` that report.md shows. Returns the paths written.
    """
    out_dir = Path(out_dir)
    summary = evaluation.summary
    document = {"settings": evaluation.settings, "samples": evaluation.samples, "records": evaluation.records,
                "summary": summary, "paper": evaluation.paper}
    paths = {"json": out_dir / "results.json", "csv": out_dir / "results.csv", "report": out_dir / "report.md"}
    paths["json"].write_text(json.dumps(_json_ready(document), indent=1, ensure_ascii=False) + "\n")

    with open(paths["csv"], "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        for record in evaluation.records + (evaluation.paper["records"] if evaluation.paper else []):
            writer.writerow({k: ("" if v is None else v) for k, v in record.items()})

    settings = evaluation.settings
    light = (f"estimated from each image (shadecut.estimate_light, {settings['light_method']})"
             if settings["light_method"] else "given (true)")
    lines = [
        "# ShadeCut evaluation",
        "",
        f"Dataset `{settings['dataset']}`: {len(evaluation.samples)} samples; methods "
        f"{', '.join(settings['methods'])}; light and albedo {light}. Metrics on the mask eroded by "
        f"{settings['erode_pixels']} pixels; means over the samples.",
        "",
        "## Ranking",
        "",
        method_table(summary),
        "",
        "## Mean angular error per shape (degrees)",
        "",
        shape_table(summary),
        "",
    ]
    if evaluation.paper:
        lines += ["## The paper's experiment: Mozart, light (1, 0, 1)", "",
                  method_table(evaluation.paper["summary"]), ""]
    failed = evaluation.failed
    if failed:
        lines += ["## Failures", ""] + [f"- {r['sample']} / {r['method']}: {r['error']}" for r in failed] + [""]
    if figures:
        lines += ["## Figures", ""] + [f"![{Path(f).stem}]({Path(f).as_posix()})" for f in figures] + [""]
    paths["report"].write_text("\n".join(lines))
    return paths
