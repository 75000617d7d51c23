"""The relief defaults by the one procedure (scripts/tune_parameters.py --detail-size), on training reliefs.

Training reliefs: shadecut.synthetic_reliefs' families (bricks with bright mortar, pebbles casting
shadows, a coin on a white ground, bark) at TRAINING_SEEDS, each under TRAINING_LIGHTS; the tests use
TEST_SEEDS and lights of their own, and no real photograph takes part. Every detail_scale_factor on
the grid is scored by the mean, over those renders (the light given, every other option at its
default), of the correlation of the returned height with the true height; the highest wins.
"""

from __future__ import annotations

import numpy as np

import shadecut
from shadecut import synthetic_reliefs
from shadecut.evaluation.relief_metrics import height_correlation

TRAINING_LIGHTS = ((0.6, 0.3, 1.0), (-0.5, 0.7, 1.0), (0.2, -0.8, 0.9))
DETAIL_SCALE_FACTORS = (0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 8.0)


def training_reliefs(size: int = 256) -> list:
    return [make(light, size, seed) for make in synthetic_reliefs.RELIEFS.values()
            for seed in synthetic_reliefs.TRAINING_SEEDS for light in TRAINING_LIGHTS]


def tune_detail_size(size: int = 256) -> float:
    reliefs = training_reliefs(size)
    families = list(synthetic_reliefs.RELIEFS)
    scored = []
    for factor in DETAIL_SCALE_FACTORS:
        correlations = [height_correlation(shadecut.reconstruct(relief.image, relief.light, scene="relief",
                                                                detail_scale_factor=factor).depth, relief.depth)
                        for relief in reliefs]
        per_family = np.reshape(correlations, (len(families), -1)).mean(axis=1)
        scored.append((float(np.mean(correlations)), factor))
        print(f"  detail_scale_factor {factor:4}: mean correlation {np.mean(correlations):.3f}  "
              + ", ".join(f"{name} {value:.2f}" for name, value in zip(families, per_family)), flush=True)
    best = max(scored)[1]
    print(f"  chosen detail_scale_factor: {best}")
    return best
