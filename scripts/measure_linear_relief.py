"""A linear reading of a material's relief (issue 46): Pentland's linear shape from shading
(shadecut.evaluation.linear_relief) on the scanned materials' test half, rendered Lambertian under the
materials evaluation's four lights, its smoothness chosen on the training half, beside flat.

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_linear_relief.py [MATERIALS_FOLDER] [--cast-shadows]

MATERIALS_FOLDER defaults to ../shared/data/materials. It prints docs/results.md's table "A linear
reading of the relief" and the training curves; with --cast-shadows, of renders black where the relief
hides the light (both halves).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from shadecut.evaluation.linear_relief import INPUTS, SMOOTHNESSES, evaluate_linear_relief
from shadecut.evaluation.materials import LIGHT_COUNT
from shadecut.materials import TEST

DEFAULT_FOLDER = Path(__file__).resolve().parents[2] / "shared" / "data" / "materials"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", nargs="?", type=Path, default=DEFAULT_FOLDER)
    parser.add_argument("--cast-shadows", action="store_true", help="render with cast shadows")
    args = parser.parse_args()
    result = evaluate_linear_relief(args.folder, args.cast_shadows)
    print("Training half, mean error by smoothness: " + "; ".join(
        f"{name}: " + ", ".join(f"{w:g}: {e:.2f}°" for w, e in zip(SMOOTHNESSES, part["training_curve"]))
        for name, part in result["inputs"].items()))
    print()
    print("| input | smoothness (training-chosen) | mean ° | renders below flat | " + " | ".join(TEST) + " |")
    print("|---" * (4 + len(TEST)) + "|")
    print(f"| flat | — | {result['flat']:.2f} | — | " + " | ".join("" for _ in TEST) + " |")
    for name in INPUTS:
        part = result["inputs"][name]
        per_material = np.array(part["per_render"]).reshape(len(TEST), LIGHT_COUNT).mean(axis=1)
        print(f"| {name} | {part['smoothness']:g} | {part['mean_deg']:.2f} | {part['below_flat']} of {result['renders']} | "
              + " | ".join(f"{e:.2f}" for e in per_material) + " |")


if __name__ == "__main__":
    main()
