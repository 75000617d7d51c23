"""The straight seams of graphcut's normal maps (shadecut.evaluation.seam_share: percent of the masked
pixels on axis-aligned straight steps, the rectangles issue 44 is about) beside their truth.

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_seams.py

Its table is docs/results.md's "Rectangles".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import skimage.data

import shadecut
from shadecut import synthetic
from shadecut.evaluation import seam_share
from shadecut.imaging import srgb_to_linear

MOZART = Path(__file__).resolve().parents[1] / "data" / "mozart" / "moz256.depth"


def scenes():
    yield "Mozart (1, 0, 1)", synthetic.mozart(MOZART, light=(1.0, 0.0, 1.0))
    yield "Mozart (-0.5, 0.8, 1)", synthetic.mozart(MOZART, light=(-0.5, 0.8, 1.0))
    yield "bumps", synthetic.bumps((0.5, 0.3, 1.0), size=256)
    yield "torus", synthetic.torus((0.4, 0.7, 1.0), size=256)
    yield "vase", synthetic.vase((0.5, 0.3, 1.0), size=256)
    yield "sphere", synthetic.sphere((1.0, 0.0, 1.0), size=256)
    yield "bowl", synthetic.sphere((0.3, 0.5, 1.0), size=256, bowl=True)


def main() -> None:
    print("| scene | truth | graphcut | `viscosity_weight=0` |")
    print("|---|---|---|---|")
    for name, scene in scenes():
        shares = [seam_share(scene.normals, scene.mask)]
        for overrides in ({}, {"viscosity_weight": 0.0}):
            shares.append(seam_share(shadecut.reconstruct(scene.image, scene.light, scene.mask, **overrides).normals, scene.mask))
        print(f"| {name} | " + " | ".join(f"{share:.2f}" for share in shares) + " |")
    coins = srgb_to_linear(skimage.data.coins().astype(np.float32) / 255.0).astype(np.float32)
    relief = shadecut.reconstruct(coins, None, None, scene="relief")
    print(f"| scikit-image's coins (relief, light estimated) | — | {seam_share(relief.normals, relief.mask):.2f} | — |")


if __name__ == "__main__":
    main()
