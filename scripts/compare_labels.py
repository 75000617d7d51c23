"""Mean angular error of graphcut for several label counts K, with and without `refine`.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/compare_labels.py
"""

from pathlib import Path

import shadecut
from shadecut import synthetic

REPO = Path(__file__).resolve().parents[1]
scenes = {
    "sphere (1.5, 0.866, 1)": synthetic.sphere((1.5, 0.866, 1.0)),
    "Mozart (1, 0, 1)": synthetic.mozart(REPO / "data" / "mozart" / "moz256.depth"),
}
print(f"{'K':>3s} {'refine':>6s} " + " ".join(f"{name:>24s}" for name in scenes))
for labels in (18, 36, 72):
    for refine in (True, False):
        errors = [
            scene.mean_error(shadecut.reconstruct(scene.image, scene.light, scene.mask, labels=labels,
                                                  refine=refine).normals)
            for scene in scenes.values()
        ]
        print(f"{labels:3d} {str(refine):>6s} " + " ".join(f"{e:24.2f}" for e in errors))
