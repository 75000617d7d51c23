"""Painted objects: graphcut with one albedo (top_fit) and with the paint separated (retinex) on the
painted test set of tests/python/test_paint.py and on DiLiGenT's colour photographs (calibrated and
estimated light), beside the flat plane: the figures of docs/results.md#painted-objects-retinex.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/measure_paint.py [DILIGENT_FOLDER]
(DILIGENT_FOLDER defaults to ../shared/data/diligent; objects absent there are skipped), or with
--speed: the paint step's own seconds (stats.seconds["albedo"]) beside the whole call's, median of
five calls, on the painted bump field at 512 and 1024 pixels (docs/benchmarks.md).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import shadecut

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "python"))
import test_paint  # noqa: E402  (the test set and the DiLiGenT reader the tests use)

METHODS = ("top_fit", "retinex")


def painted_set() -> None:
    errors = {method: [] for method in (*METHODS, "unpainted")}
    for image, uniform, _, scene in test_paint.painted_test_set():
        for method in METHODS:
            errors[method].append(scene.mean_error(shadecut.reconstruct(image, scene.light, scene.mask,
                                                                        albedo_method=method).normals))
        errors["unpainted"].append(scene.mean_error(shadecut.reconstruct(uniform, scene.light, scene.mask).normals))
    print("| painted test set (12 renders) | " + " | ".join(f"{np.mean(e):.2f}" for e in errors.values()) + " |")


def diligent(folder: Path) -> None:
    test_paint.DILIGENT = folder
    for name in ("ball", "cat", "reading"):
        if not (folder / f"{name}PNG").is_dir():
            continue
        photos, mask, normals = test_paint.diligent_photos(name)
        inner = shadecut.erode_mask(mask, 2)
        flat = np.zeros_like(normals)
        flat[..., 2] = 1.0
        row = []
        for light_given in (True, False):
            for method in METHODS:
                row.append(np.mean([shadecut.angular_error(
                    shadecut.reconstruct(rgb, light if light_given else None, mask, albedo_method=method).normals,
                    normals, inner) for rgb, light in photos]))
        print(f"| {name} | " + " | ".join(f"{v:.2f}" for v in row) + f" | {shadecut.angular_error(flat, normals, inner):.2f} |",
              flush=True)


def speed() -> None:
    from shadecut import synthetic

    print("| size | retinex step, s | whole call with retinex, s | whole call with top_fit, s |\n|---|---|---|---|")
    for size in (512, 1024):
        scene = synthetic.bumps((0.7, 0.2, 1.0), size)
        colour, _ = synthetic.painted(scene, "patches", 1)
        runs = {method: [shadecut.reconstruct(colour, scene.light, scene.mask, albedo_method=method).stats.seconds
                         for _ in range(5)] for method in METHODS}
        step = np.median([seconds["albedo"] for seconds in runs["retinex"]])
        total = {method: np.median([seconds["total"] for seconds in runs[method]]) for method in METHODS}
        print(f"| {size} | {step:.3f} | {total['retinex']:.2f} | {total['top_fit']:.2f} |", flush=True)


def main() -> int:
    if "--speed" in sys.argv:
        speed()
        return 0
    print("| | one albedo | retinex | unpainted |\n|---|---|---|---|")
    painted_set()
    print("\n| DiLiGenT | calibrated, one albedo | calibrated, retinex | estimated, one albedo | estimated, retinex "
          "| flat plane |\n|---|---|---|---|---|---|")
    diligent(Path(sys.argv[1]) if len(sys.argv) > 1 else REPO.parent / "shared" / "data" / "diligent")
    return 0


if __name__ == "__main__":
    sys.exit(main())
