"""Renders Mozart under light (1, 0, 1), reconstructs it with graphcut (the defaults, then with the
depth fitted to the image: fit_shading) and lee_rosenfeld, prints the mean angular errors and writes the
outputs (images, depth, normals, meshes, a comparison figure).

Run: bash scripts/demo.sh [--out DIR]   (or PYTHONPATH=addon /usr/bin/python3 scripts/demo.py)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import shadecut
from shadecut import synthetic

REPO = Path(__file__).resolve().parents[1]
LIGHT = (1.0, 0.0, 1.0)
# name (the output files' prefix) -> the figure's title and reconstruct()'s options
RUNS = {
    "graphcut": ("graphcut", dict(method="graphcut")),
    "graphcut_fit": ("graphcut, fit to image", dict(method="graphcut", fit_shading=True)),
    "lee_rosenfeld": ("lee_rosenfeld", dict(method="lee_rosenfeld")),
}


def save_figure(path: Path, scene: synthetic.Scene, results: dict, errors: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    eroded = shadecut.erode_mask(scene.mask, 2)
    columns = 2 + 2 * len(results)
    figure, axes = plt.subplots(1, columns, figsize=(2.6 * columns, 3.0))
    colour = lambda n: np.where(scene.mask[..., None], (n + 1) / 2, 1.0)  # noqa: E731
    axes[0].imshow(scene.image, cmap="gray", vmin=0, vmax=1)
    axes[0].set_title("input, light (1,0,1)", fontsize=9)
    axes[1].imshow(colour(scene.normals))
    axes[1].set_title("true normals", fontsize=9)
    for i, (name, result) in enumerate(results.items()):
        axes[2 + 2 * i].imshow(colour(result.normals))
        axes[2 + 2 * i].set_title(f"{RUNS[name][0]} normals", fontsize=9)
        error_map = shadecut.angular_error_map(result.normals, scene.normals, eroded)
        shown = axes[3 + 2 * i].imshow(error_map, cmap="magma", vmin=0, vmax=90)
        axes[3 + 2 * i].set_title(f"error, mean {errors[name]:.1f}°", fontsize=9)
    for axis in axes:
        axis.set_axis_off()
    figure.colorbar(shown, ax=axes[-1], fraction=0.046, label="degrees")
    figure.tight_layout()
    figure.savefig(path, dpi=80)
    plt.close(figure)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=REPO / "out" / "demo", help="output folder (default out/demo)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    scene = synthetic.mozart(REPO / "data" / "mozart" / "moz256.depth", LIGHT)
    shadecut.save_image(args.out / "mozart_input.png", scene.image, scene.mask)
    print(f"Mozart 256 x 256 rendered under light {LIGHT}; mean angular error on the mask eroded by 2 px:")
    results, errors = {}, {}
    for name, (title, options) in RUNS.items():
        result = shadecut.reconstruct(scene.image, LIGHT, scene.mask, **options)
        results[name], errors[name] = result, scene.mean_error(result.normals)
        print(f"  {title:24s} {errors[name]:6.2f} deg   ({result.stats.seconds['total']:.2f} s)")
        shadecut.save_depth(args.out / f"{name}_depth.exr", result.depth, result.mask)
        shadecut.save_depth(args.out / f"{name}_depth.png", result.depth, result.mask)
        shadecut.save_normals(args.out / f"{name}_normals.png", result.normals, result.mask)
        shadecut.save_mesh(args.out / f"{name}_mesh.ply", result.depth, result.mask)
    save_figure(args.out / "mozart_comparison.png", scene, results, errors)
    print(f"wrote input, depth (.exr, .png), normals (.png), meshes (.ply) and mozart_comparison.png to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
