"""Issue 29's figures for reliefs: the test reliefs against their truth, the CC0 photographs alone,
and the gallery figure (photo, height, raking-light render) of docs/method.md, "Reliefs".

Test reliefs: shadecut.synthetic_reliefs at TEST_SEEDS under TEST_LIGHTS (the light given), each
figure of shadecut.evaluation.relief_metrics. Photographs: python3-skimage's CC0 brick, gravel, grass
and coins, sRGB decoded to linear, light estimated, every default.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/measure_reliefs.py [--gallery docs/relief_gallery.png]
[--every-form-kept] [--true-paint]. --every-form-kept measures the reliefs as they were before the
damping and the paint lines (detail_size=-1, paint_line_width=0): the drift of the slopes then shows
beside the true large forms. --true-paint divides each test relief's image by its true paint (albedo)
first: what is left of the error is the shading's.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import shadecut
from shadecut import synthetic_reliefs
from shadecut.evaluation.relief_metrics import relief_figures
from shadecut.imaging import srgb_to_linear

TEST_LIGHTS = ((0.5, 0.6, 1.0), (-0.8, 0.2, 1.0), (0.1, -0.9, 0.8))
PHOTOS = ("brick", "gravel", "grass", "coins")
RAKING_LIGHT = (-1.0, 1.0, 0.6)


def photo(name: str) -> np.ndarray:
    """skimage's CC0 photograph ``name`` as linear intensity."""
    import skimage.data

    return srgb_to_linear(getattr(skimage.data, name)() / 255.0)


def relief_test_figures(true_paint: bool = False, **options) -> dict:
    """{family: [figures of each seed and light]} over the test reliefs; with ``true_paint`` each
    image divided by its true albedo first."""
    def image_of(relief):
        return relief.image / relief.albedo_map if true_paint else relief.image

    return {name: [relief_figures(shadecut.reconstruct(image_of(relief), light, scene="relief", **options).depth,
                                  relief.depth)
                   for seed in synthetic_reliefs.TEST_SEEDS for light in TEST_LIGHTS
                   for relief in [make(light, 256, seed)]]
            for name, make in synthetic_reliefs.RELIEFS.items()}


def photo_results(**options) -> dict:
    return {name: shadecut.reconstruct(photo(name), None, scene="relief", **options) for name in PHOTOS}


def gallery(results: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(3, len(results), figsize=(3.2 * len(results), 9.6))
    for column, (name, result) in enumerate(results.items()):
        figures = relief_figures(result.depth)
        axes[0, column].imshow(photo(name) ** (1 / 2.2), cmap="gray", vmin=0, vmax=1)
        axes[0, column].set_title(f"{name} (skimage, CC0)")
        axes[1, column].imshow(result.depth, cmap="viridis")
        axes[1, column].set_title(f"height: range {100 * figures['depth_range_fraction']:.1f}% of width,\n"
                                  f"large forms {figures['low_frequency_share']:.2f} of variance", fontsize=9)
        axes[2, column].imshow(shadecut.render(result.normals, RAKING_LIGHT), cmap="gray", vmin=0, vmax=1)
        axes[2, column].set_title("rendered under a raking light", fontsize=9)
    for axis in axes.flat:
        axis.set_axis_off()
    figure.tight_layout()
    figure.savefig(path, dpi=60)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gallery", help="also write the gallery figure to this PNG")
    parser.add_argument("--every-form-kept", action="store_true",
                        help="no damping and no paint lines (detail_size=-1, paint_line_width=0)")
    parser.add_argument("--true-paint", action="store_true", help="the test reliefs' images divided by their true paint")
    args = parser.parse_args()
    options = {"detail_size": -1.0, "paint_line_width": 0} if args.every_form_kept else {}
    print("test reliefs (light given): family, correlation mean [min], range ratio median [max], "
          "large-form share mean (truth's)")
    for name, figures in relief_test_figures(args.true_paint, **options).items():
        correlation = [f["correlation"] for f in figures]
        ratio = [f["range_ratio"] for f in figures]
        print(f"  {name:14s} {np.mean(correlation):.2f} [{min(correlation):.2f}]  {np.median(ratio):.2f} "
              f"[{max(ratio):.2f}]  {np.mean([f['low_frequency_share'] for f in figures]):.2f} "
              f"({np.mean([f['truth_low_frequency_share'] for f in figures]):.2f})")
    results = photo_results(**options)
    print("photographs (light estimated): large-form share, depth range / width, detail size")
    for name, result in results.items():
        figures = relief_figures(result.depth)
        print(f"  {name:8s} {figures['low_frequency_share']:.2f}  {100 * figures['depth_range_fraction']:.1f}%  "
              f"{result.stats.detail_size:.0f} px")
    if args.gallery:
        gallery(results, args.gallery)
    return 0


if __name__ == "__main__":
    sys.exit(main())
