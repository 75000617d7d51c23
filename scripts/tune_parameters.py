"""Chooses the default parameters of every method by one procedure, on training surfaces only.

Training surfaces: a sphere, a bowl, Gaussian bumps and dents in a layout of their own and two egg
crates, each under its own light. None of them is a test surface (the tests use other lights,
another bump layout, and Mozart), so the defaults are not fitted to what the tests measure.
For each method, every combination of its parameters on the grid below is scored by the mean, over
the training surfaces rendered at every size of --sizes, of the mean angular error on the mask eroded
by 2 pixels; the best wins. Scoring at more than one resolution keeps the choice from fitting one
pixel scale; the mean per size is printed beside the score to show how far apart they are.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/tune_parameters.py [--methods NAME ...] [--sizes N ...]
(every method of the grid, at 128 and 256 pixels, by default; --methods tunes only those named, by
the same procedure).
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time

import numpy as np

import shadecut
from shadecut import synthetic

TRAINING_BUMPS = (
    (-0.2, 0.2, 0.09, -0.08),
    (0.2, 0.2, 0.06, 0.09),
    (-0.2, -0.2, 0.06, 0.09),
    (0.2, -0.2, 0.09, -0.08),
)


SPARSE_TRAINING_BUMPS = (
    (-0.25, 0.25, 0.06, 0.08),
    (0.25, 0.0, 0.06, -0.08),
    (-0.1, -0.28, 0.05, 0.07),
)


def training_surfaces(size: int) -> dict[str, synthetic.Scene]:
    return {
        "sphere": synthetic.sphere((0.5, 0.5, 1.0), size, radius_fraction=0.4),
        "bowl": synthetic.sphere((-0.6, -0.4, 1.0), size, radius_fraction=0.4, bowl=True),
        "bumps": synthetic.bumps((0.8, -0.5, 1.0), size, features=TRAINING_BUMPS),
        "egg_crate": synthetic.egg_crate((1.0, 0.4, 1.0), size),
        "egg_crate_wide": synthetic.egg_crate((-0.5, 0.9, 1.0), size, periods=1.5, amplitude=0.08),
        "bumps_sparse": synthetic.bumps((-0.7, 0.3, 1.0), size, features=SPARSE_TRAINING_BUMPS),
    }


GRID = {
    "graphcut": {
        "data_weight": [0.2, 0.5, 1.0, 2.0],
        "min_curvature": [0.3, 1.0, 2.0],
        "undefined_weight": [0.0, 0.05, 0.2, 0.5],
    },
    "graphcut_two": {"min_curvature": [0.3, 1.0, 2.0], "undefined_weight": [0.0, 0.05, 0.2, 0.5]},
    "lee_rosenfeld": {"min_curvature": [0.3, 1.0, 2.0]},
    "brooks_horn": {"smoothness": [0.3, 0.6, 1.0, 2.0, 4.0, 8.0], "iterations": [500, 2000, 8000],
                    "tolerance": [0.0, 1e-5, 1e-4]},
    "tsai_shah": {"iterations": [1, 2, 3, 5, 10, 20, 50, 100]},
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", nargs="+", choices=list(GRID), default=list(GRID))
    parser.add_argument("--sizes", nargs="+", type=int, default=[128, 256],
                        help="image sizes (pixels) at which every training surface is rendered")
    args = parser.parse_args()
    surfaces = {size: training_surfaces(size) for size in args.sizes}
    for method in args.methods:
        grid = GRID[method]
        names = list(grid)
        scored = []
        settings = list(itertools.product(*grid.values()))
        started = time.monotonic()
        for done, values in enumerate(settings):
            params = dict(zip(names, values))
            if done:
                left = (time.monotonic() - started) / done * (len(settings) - done)
                print(f"\r{method}: setting {done + 1}/{len(settings)}, about {left / 60:.0f} min left ",
                      end="", file=sys.stderr, flush=True)
            errors = {
                size: [scene.mean_error(shadecut.reconstruct(scene.image, scene.light, scene.mask, albedo=scene.albedo,
                                                             method=method, **params).normals)
                       for scene in scenes.values()]
                for size, scenes in surfaces.items()
            }
            scored.append((float(np.mean(list(errors.values()))), params, errors))
        scored.sort(key=lambda item: item[0])
        print(f"\n{method}: the five best of {len(scored)} settings (mean error in degrees over every size; "
              f"then per size, the mean and per surface: {', '.join(surfaces[args.sizes[0]])})")
        for score, params, errors in scored[:5]:
            per_size = "; ".join(f"{size} px {np.mean(e):.2f} [{', '.join(f'{v:.2f}' for v in e)}]"
                                 for size, e in errors.items())
            print(f"  {score:6.2f}  {params}  {per_size}")
        print(f"  chosen for {method}: {scored[0][1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
