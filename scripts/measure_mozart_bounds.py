"""Issue 44's bounds on the paper's bust: Mozart at 256 px under its two lights, the light given and
the albedo estimated (as test_grid.py reads it), read by the default call, by the paper's energy at
one level with every label (what coarse to fine approximates), with and without the viscosity
pull, and with fit_shading; the mean angular error and the bust's seconds per call; beside them
the bump field and the torus at 256 px under the issue's lights (the bounds that keep the pull).

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_mozart_bounds.py

It prints docs/results.md's table "What the bust's bounds need".
"""

from __future__ import annotations

import time
from pathlib import Path

import shadecut
from shadecut import synthetic

MOZART = Path(__file__).resolve().parents[1] / "data" / "mozart" / "moz256.depth"
LIGHTS = ((1.0, 0.0, 1.0), (-0.5, 0.8, 1.0))
OTHERS = (("bumps", lambda: synthetic.bumps((0.5, 0.3, 1.0), size=256)),
          ("torus", lambda: synthetic.torus((0.4, 0.7, 1.0), size=256)))
SETTINGS = (
    ("default", {}),
    ("the paper's energy, no pull (`viscosity_weight=0`)", {"viscosity_weight": 0.0}),
    ("one level, every label (`coarse_to_fine_band=-1`)", {"coarse_to_fine_band": -1}),
    ("one level, every label, no pull", {"coarse_to_fine_band": -1, "viscosity_weight": 0.0}),
    ("`fit_shading=True`", {"fit_shading": True}),
)


def main() -> None:
    busts = [synthetic.mozart(MOZART, light) for light in LIGHTS]
    others = [make() for _, make in OTHERS]
    print("| setting | " + " | ".join(f"Mozart {light} °" for light in LIGHTS) + " | seconds | "
          + " | ".join(f"{name} °" for name, _ in OTHERS) + " |")
    print("|---" * (2 + len(LIGHTS) + len(OTHERS)) + "|")
    for name, options in SETTINGS:
        errors, seconds = [], []
        for bust in busts:
            start = time.perf_counter()
            result = shadecut.reconstruct(bust.image, bust.light, bust.mask, **options)
            seconds.append(time.perf_counter() - start)
            errors.append(bust.mean_error(result.normals))
        other_errors = [scene.mean_error(shadecut.reconstruct(scene.image, scene.light, scene.mask, **options).normals)
                        for scene in others]
        print(f"| {name} | " + " | ".join(f"{e:.2f}" for e in errors) + " | "
              + " / ".join(f"{s:.2f}" for s in seconds) + " | " + " | ".join(f"{e:.2f}" for e in other_errors) + " |")


if __name__ == "__main__":
    main()
