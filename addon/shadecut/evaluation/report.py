"""Aggregates and reports: the means per method and per shape, the ranking, the Markdown tables,
and results.json, results.csv and report.md.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import platform
import shlex
import sys
import time
from pathlib import Path
from typing import Optional, Sequence

from .. import FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS
from ..atomic_write import write_text
from .metrics import METRICS
from .photographs import ESTIMATED, LEAST_SQUARES, ONE, PHOTOGRAPH_SETS, SHADECUT, set_label

from .runner import Evaluation

# "light": empty for a dataset's records; "calibrated" or "estimated" for a real photograph's and for a
# several-photograph set's. "photographs" and "two_lit_share": a several-photograph set's count and
# ShadeCut's share of two-lit pixels; empty for one photograph's rows. A set's "light_error_deg" is the
# median over its photographs, and "light_uncertainty_deg" the estimator's (stats.light_uncertainty).
CSV_COLUMNS = ("sample", "shape", "method", "light", "status", *METRICS, "error", "photographs", "two_lit_share",
               "light_uncertainty_deg")


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


def real_table(part: dict) -> str:
    """One object's real-photograph table (Markdown): the flat plane, then each method under the
    calibrated and the estimated light, in the order of its ranking there."""
    header = ["light", "method", "mean °", "median °", "< 11.25° %", "< 22.5° %", "< 30° %", "seconds",
              "failed", "light error °"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]

    def row(light: str, method: str, s: dict) -> str:
        cells = [light, method, _cell(s["mean_deg"]), _cell(s["median_deg"]), _cell(s["under_11.25_pct"], 1),
                 _cell(s["under_22.5_pct"], 1), _cell(s["under_30_pct"], 1), _cell(s["seconds"], 3),
                 f"{s['failed']}/{s['samples'] + s['failed']}", _cell(s["light_error_deg"])]
        return "| " + " | ".join(cells) + " |"

    summary = part["summary"]
    lines.append(row("any", "**flat plane**", summary["flat"]))
    for light in ("calibrated", "estimated"):
        for method in summary[light]["ranking"]:
            lines.append(row(light, method, summary[light]["methods"][method]))
    return "\n".join(lines)


def photographs_table(part: dict) -> str:
    """One object's several-photograph table (Markdown): per set, the mean angular error of ShadeCut
    and of plain least squares over the same photographs with the calibrated lights, of ShadeCut with
    the lights estimated and their median error, and ShadeCut's share of two-lit pixels (calibrated)."""
    lines = ["| photographs | ShadeCut mean ° | plain least squares mean ° | ShadeCut, lights estimated mean ° "
             "| light error (median) ° | two lit |", "|---|---|---|---|---|---|"]
    records = part.get("photographs", [])

    def found(set_name: str, method: str) -> dict:
        return next((r for r in records if r["set"] == set_name and r["method"] == method), {})

    def cell(record: dict, key: str = "mean_deg") -> str:
        if not record:
            return "—"
        return _cell(record.get(key)) if record["status"] == "ok" else "failed"

    for set_name in dict.fromkeys(r["set"] for r in records):
        first = next(r for r in records if r["set"] == set_name)
        label = ("one (each alone, graphcut, mean)" if set_name == ONE
                 else set_label(set_name, PHOTOGRAPH_SETS.get(set_name), first["count"]))
        estimated = found(set_name, ESTIMATED)
        too_few = set_name != ONE and first["count"] < FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS
        estimated_cells = ([f"— (fewer than {FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS})", "—"] if too_few
                           else [cell(estimated), cell(estimated, "light_error_deg")])
        ours = found(set_name, SHADECUT)
        share = ours.get("two_lit_share")
        two_lit = "—" if share is None else f"{100 * share:.1f}%"
        cells = [label, cell(ours), cell(found(set_name, LEAST_SQUARES)), *estimated_cells, two_lit]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def photographs_text() -> str:
    """What the several-photograph table shows, in words (report.md says it above the table)."""
    return ("Several photographs at once: ShadeCut with the calibrated lights beside plain least squares over "
            "the same photographs, then ShadeCut with the lights estimated from the photographs alone "
            "(`reconstruct(photographs, None, mask)`, the default hint), scored against the same measured "
            "normals; \"light error\": the median angle between the estimated and the calibrated lights. The "
            f"library estimates lights from {FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS} photographs or more: a smaller "
            f"set is not run with them (\"— (fewer than {FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS})\"); one "
            "photograph's estimated light is the table above's. \"two lit\": the share of the mask where "
            "exactly two photographs were usable and the graph cut chose (calibrated lights).")


def _real_lines(real: dict, out_dir: Path) -> list[str]:
    settings = real["settings"]
    lines = ["## Real photographs", "",
             f"{settings['source']} ({settings['citation']}): every method on each photograph, given the "
             f"calibrated light, then the light estimated by {settings['estimator']} (what reconstruct() "
             "uses without a light); the albedo is always estimated. The **flat plane** row is the normal "
             "(0, 0, 1) everywhere, the floor every method must beat. Metrics on the mask eroded by "
             f"{settings['erode_pixels']} pixels; means over the photographs.", ""]
    for name, part in real["objects"].items():
        photographs = len({r["sample"] for r in part["records"]})
        lines += [f"### {name} ({photographs} photographs)", "", real_table(part), ""]
        if part.get("photographs"):
            lines += [photographs_text(), "", photographs_table(part), ""]
        for figure in part["figures"]:
            relative = Path(os.path.relpath(figure, out_dir)).as_posix()
            lines += [f"![{Path(figure).stem}]({relative})", ""]
    return lines


def _set_rows(evaluation: Evaluation) -> list[dict]:
    """results.csv's rows of the several-photograph sets: one per object, set and method, named
    <object>_<set>, the record's light ("calibrated" or "estimated") in the column "light"."""
    return [{**record, "sample": f"{name}_{record['set']}", "shape": name, "photographs": record["count"]}
            for name, part in (evaluation.real or {}).get("objects", {}).items() for record in part.get("photographs", [])]


def _json_ready(value):
    """Plain JSON: NaN and infinities (a diverged method) become null instead of invalid JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    return value


def provenance() -> str:
    """Which command measured the tables, when, and on what machine: tables are quoted with it."""
    command = " ".join(shlex.quote(arg) for arg in sys.argv)
    return (f"*Measured {time.strftime('%Y-%m-%d')} by `{command}` on {platform.system()} {platform.machine()}, "
            f"{os.cpu_count()} cores, {platform.python_implementation()} {platform.python_version()}.*")


def write_results(out_dir: os.PathLike | str, evaluation: Evaluation, figures: Sequence[str] = ()) -> dict:
    """Writes results.json, results.csv (one row per sample and method) and report.md, each whole or
    not at all (a full disk leaves the previous file as it was and raises OSError).

    ``figures``: PNG paths relative to ``out_dir`` that report.md shows. Returns the paths written.
    """
    out_dir = Path(out_dir)
    summary = evaluation.summary
    document = {"settings": evaluation.settings, "samples": evaluation.samples, "records": evaluation.records,
                "summary": summary, "paper": evaluation.paper, "real": evaluation.real}
    paths = {"json": out_dir / "results.json", "csv": out_dir / "results.csv", "report": out_dir / "report.md"}
    write_text(paths["json"], json.dumps(_json_ready(document), indent=1, ensure_ascii=False) + "\n")

    table = io.StringIO()
    writer = csv.DictWriter(table, fieldnames=CSV_COLUMNS, extrasaction="ignore")
    writer.writeheader()
    for record in evaluation.all_records + _set_rows(evaluation):
        writer.writerow({k: ("" if v is None else v) for k, v in record.items()})
    write_text(paths["csv"], table.getvalue())

    settings = evaluation.settings
    light = (f"estimated from each image (shadecut.estimate_light, {settings['light_method']})"
             if settings.get("light_method") else "given (true)")
    lines = ["# ShadeCut evaluation", "", provenance(), ""]
    if settings.get("options"):
        lines += ["Options set for every method: " + ", ".join(f"`{k}={v}`" for k, v in settings["options"].items()),
                  ""]
    if settings.get("dataset") is not None:  # None: only the real photographs were evaluated
        lines += [
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
    if evaluation.real:
        lines += _real_lines(evaluation.real, out_dir)
    failed = evaluation.failed
    if failed:
        lines += ["## Failures", ""] + [f"- {r['sample']} / {r['method']}"
                                        + (f" ({r['light']} light)" if r.get("light") else "") + f": {r['error']}"
                                        for r in failed] + [""]
    if figures:
        lines += ["## Figures", ""] + [f"![{Path(f).stem}]({Path(f).as_posix()})" for f in figures] + [""]
    write_text(paths["report"], "\n".join(lines))
    return paths
