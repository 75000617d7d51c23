"""The summary of an evaluation's records: means per method and per shape, and the ranking."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from .metrics import METRICS


def _mean(values: list) -> Optional[float]:
    values = [v for v in values if v is not None]
    return float(np.mean(values)) if values else None


def aggregate(records: list[dict]) -> dict:
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
    per_method = {m: aggregate([r for r in records if r["method"] == m]) for m in methods}
    per_shape = {
        s: {m: aggregate([r for r in records if r["shape"] == s and r["method"] == m]) for m in methods}
        for s in shapes
    }
    ranking = sorted(
        methods,
        key=lambda m: (per_method[m]["failed"] > 0, math.inf if per_method[m]["mean_deg"] is None
                       else per_method[m]["mean_deg"]),
    )
    return {"methods": per_method, "shapes": per_shape, "ranking": ranking}
