"""The straight seams of graphcut's normal maps (shadecut.evaluation.seam_share: percent of the masked
pixels on axis-aligned straight steps, the rectangles issue 44 is about) beside their truth.

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_seams.py [--figure PNG]

Its table is docs/results.md's "Rectangles"; with --figure it also draws every scene's true normals
above graphcut's and graphcut's with fit_shading, the seams found in red, with the mean angular error
(docs/rectangles.png).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import skimage.data

import shadecut
from shadecut import synthetic
from shadecut.evaluation import seam_pixels, seam_share
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


def normal_colours(normals: np.ndarray, mask: np.ndarray, seams: np.ndarray) -> np.ndarray:
    """The normal map as RGB, (n + 1) / 2, black outside the mask and red on the seams."""
    colours = np.where(mask[..., None], np.clip((normals + 1.0) / 2.0, 0.0, 1.0), 0.0)
    colours[seams] = (1.0, 0.0, 0.0)
    return colours


def draw_figure(results: list, out: Path) -> None:
    """Each scene's truth above graphcut's normals and those with fit_shading, the seams found in red."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(3, len(results), figsize=(2.2 * len(results), 7.4))
    for column, (name, scene, default, fitted) in enumerate(results):
        for row, (map_, title) in enumerate(((scene.normals, f"{name}\ntruth"),
                                             (default, f"graphcut {scene.mean_error(default):.2f}°"),
                                             (fitted, f"fit_shading {scene.mean_error(fitted):.2f}°"))):
            seams = seam_pixels(map_, scene.mask)
            axes[row, column].imshow(normal_colours(map_, scene.mask, seams), interpolation="nearest")
            axes[row, column].set_title(title, fontsize=8)
            axes[row, column].axis("off")
    figure.tight_layout()
    figure.savefig(out, dpi=60)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--figure", type=Path, help="draw the truth and graphcut's normals of every scene into this PNG")
    args = parser.parse_args()
    print("| scene | truth | graphcut | `viscosity_weight=0` | `fit_shading=True` |")
    print("|---|---|---|---|---|")
    drawn = []
    for name, scene in scenes():
        default = shadecut.reconstruct(scene.image, scene.light, scene.mask).normals
        without_pull = shadecut.reconstruct(scene.image, scene.light, scene.mask, viscosity_weight=0.0).normals
        fitted = shadecut.reconstruct(scene.image, scene.light, scene.mask, fit_shading=True).normals
        shares = [seam_share(normals, scene.mask) for normals in (scene.normals, default, without_pull, fitted)]
        print(f"| {name} | " + " | ".join(f"{share:.2f}" for share in shares) + " |")
        drawn.append((name, scene, default, fitted))
    coins = srgb_to_linear(skimage.data.coins().astype(np.float32) / 255.0).astype(np.float32)
    relief = shadecut.reconstruct(coins, None, None, scene="relief")
    print(f"| scikit-image's coins (relief, light estimated) | — | {seam_share(relief.normals, relief.mask):.2f} | — | — |")
    if args.figure:
        draw_figure(drawn, args.figure)


if __name__ == "__main__":
    main()
