"""The residual map (Reconstruction.residual, the add-on's Residual map) of two scanned materials of
the test half, beside the photograph and the true paint: where the result does not explain the
photograph, which is where to trust it less.

    PYTHONPATH=addon /usr/bin/python3 scripts/draw_residual_maps.py [MATERIALS_FOLDER] --out docs/residual_map.png

Each material is rendered Lambertian under the materials evaluation's first light (from the top, slant
40 degrees) and read with that light, scene "relief", by the default method and by pentland; the
residual is shown over the albedo, 0 (black) to 1 (white), as the add-on's image holds it.
MATERIALS_FOLDER defaults to ../shared/data/materials.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import shadecut
from shadecut import materials
from shadecut.evaluation.materials import default_lights, load_half
from shadecut.imaging import luminance, residual_share

DEFAULT_FOLDER = Path(__file__).resolve().parents[2] / "shared" / "data" / "materials"
SHOWN = ("Bricks061", "PaintedPlaster009")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", nargs="?", type=Path, default=DEFAULT_FOLDER)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    light = default_lights()[0]
    figure, axes = plt.subplots(len(SHOWN), 4, figsize=(12, 3.2 * len(SHOWN)))
    for row, material in enumerate(load_half(args.folder, SHOWN)):
        (photograph,) = materials.lambertian_photographs(material, [light])
        default = shadecut.reconstruct(photograph, light, scene="relief")
        linear = shadecut.reconstruct(photograph, light, scene="relief", method="pentland")
        # The photograph and its paint shown with a display gamma of 2.2, the residual as stored.
        panels = ((np.clip(photograph, 0.0, 1.0) ** (1 / 2.2), f"{material.name}: photograph"),
                  (luminance(material.albedo) ** (1 / 2.2), "its paint (true albedo)"),
                  (residual_share(default.residual, default.albedo_map), "residual map, the default (graphcut)"),
                  (residual_share(linear.residual, linear.albedo_map), "residual map, pentland"))
        for column, (picture, title) in enumerate(panels):
            axes[row, column].imshow(picture, cmap="gray", vmin=0.0, vmax=1.0, interpolation="nearest")
            axes[row, column].set_title(title, fontsize=9)
            axes[row, column].axis("off")
    figure.tight_layout()
    figure.savefig(args.out, dpi=56)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
