"""The relief defaults by the one procedure (scripts/tune_parameters.py --detail-size), on training reliefs.

Training reliefs: shadecut.synthetic_reliefs' families (bricks with bright mortar, pebbles casting
shadows, a coin on a white ground, bark) at TRAINING_SEEDS, each under TRAINING_LIGHTS; the tests use
TEST_SEEDS and lights of their own, and no real photograph takes part. Every setting on a grid is
scored by the mean, over those renders (the light given, every other option at its default), of the
correlation of the returned height with the true height; the highest wins. First the paint lines
(paint_line_width, off or with each paint_line_contrast), then detail_scale_factor with them.
"""

from __future__ import annotations

import numpy as np

import shadecut
from shadecut import synthetic_reliefs
from shadecut.evaluation.relief_metrics import height_correlation

TRAINING_LIGHTS = ((0.6, 0.3, 1.0), (-0.5, 0.7, 1.0), (0.2, -0.8, 0.9))
DETAIL_SCALE_FACTORS = (1.0, 1.5, 2.0)  # 0.5, 3, 4 and 8 scored lower in the first run (parameters.md)
PAINT_LINES = [(0, 2.0)] + [(width, contrast) for width in (5, 7, 9) for contrast in (1.6, 2.0, 2.5)]


def training_reliefs(size: int = 256) -> list:
    return [make(light, size, seed) for make in synthetic_reliefs.RELIEFS.values()
            for seed in synthetic_reliefs.TRAINING_SEEDS for light in TRAINING_LIGHTS]


def best_setting(reliefs: list, settings: list) -> dict:
    """The setting (a dict of options) of the highest mean correlation, each printed with its score."""
    families = list(synthetic_reliefs.RELIEFS)
    scored = []
    for options in settings:
        correlations = [height_correlation(shadecut.reconstruct(relief.image, relief.light, scene="relief",
                                                                **options).depth, relief.depth)
                        for relief in reliefs]
        per_family = np.reshape(correlations, (len(families), -1)).mean(axis=1)
        scored.append((float(np.mean(correlations)), options))
        print(f"  {options}: mean correlation {np.mean(correlations):.3f}  "
              + ", ".join(f"{name} {value:.2f}" for name, value in zip(families, per_family)), flush=True)
    best = max(scored, key=lambda item: item[0])[1]
    print(f"  chosen: {best}")
    return best


def tune_detail_size(size: int = 256) -> dict:
    reliefs = training_reliefs(size)
    lines = best_setting(reliefs, [dict(paint_line_width=width, paint_line_contrast=contrast)
                                   for width, contrast in PAINT_LINES])
    return best_setting(reliefs, [dict(lines, detail_scale_factor=factor) for factor in DETAIL_SCALE_FACTORS])
