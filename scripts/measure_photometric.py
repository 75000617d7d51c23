"""Several photographs on DiLiGenT (issue 45): shadecut.reconstruct with 2, 4, 8 and all 19 of an
object's photographs and their calibrated lights, against plain least squares over the same
photographs (every one, nothing left out) and one photograph alone (graphcut, the mean over the set).

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_photometric.py [DILIGENT_FOLDER]

DILIGENT_FOLDER defaults to ../shared/data/diligent. Mean angular error in degrees over the mask
eroded by 2 pixels, as every evaluation measures; the table in docs/results.md is its output. Nothing
is tuned here: the thresholds are the option table's defaults.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import shadecut
from shadecut import diligent

SETS = {"two (079, 031)": [79, 31], "four (085, 007, 037, 049)": [85, 7, 37, 49],
        "eight": [85, 79, 7, 31, 37, 25, 49, 73], "all 19": None}
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def plain_least_squares(loaded: diligent.DiligentObject) -> np.ndarray:
    grey = np.stack([photo @ LUMINANCE for photo in loaded.photos], axis=-1)
    scaled = grey[loaded.mask] @ np.linalg.pinv(loaded.lights).T
    normals = np.zeros_like(loaded.normals)
    normals[loaded.mask] = scaled / np.maximum(np.linalg.norm(scaled, axis=-1, keepdims=True), 1e-12)
    return normals


def row(folder: Path, label: str, images) -> str:
    loaded = diligent.load_object(folder, images=images)
    inner = shadecut.erode_mask(loaded.mask, 2)
    start = time.perf_counter()
    ours = shadecut.reconstruct(loaded.photos, loaded.lights, loaded.mask)
    seconds = time.perf_counter() - start
    single = np.mean([shadecut.angular_error(shadecut.reconstruct(photo, light, loaded.mask).normals, loaded.normals, inner)
                      for photo, light in zip(loaded.photos, loaded.lights)])
    return (f"| {folder.name[:-3]} | {label} | {shadecut.angular_error(ours.normals, loaded.normals, inner):.2f} | "
            f"{shadecut.angular_error(plain_least_squares(loaded), loaded.normals, inner):.2f} | {single:.2f} | "
            f"{ours.stats.pair_pixels / loaded.mask.sum():.1%} | {seconds:.2f} |")


def main() -> int:
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "shared" / "data" / "diligent"
    print("| object | photographs | ShadeCut | plain least squares | one photograph (mean) | two lit | seconds |")
    print("|---|---|---|---|---|---|---|")
    for name in ("ball", "cat", "reading"):
        if (folder / f"{name}PNG").is_dir():
            for label, images in SETS.items():
                print(row(folder / f"{name}PNG", label, images), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
