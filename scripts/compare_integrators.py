"""Depth RMSE of both integrators from exact normals (the integrator alone, no shape from shading).

Run: PYTHONPATH=addon /usr/bin/python3 scripts/compare_integrators.py
"""

from pathlib import Path

import numpy as np

import shadecut
from shadecut import synthetic

REPO = Path(__file__).resolve().parents[1]

scenes = {
    "sphere 128": synthetic.sphere((1.0, 0.0, 1.0)),
    "Mozart 256": synthetic.mozart(REPO / "data" / "mozart" / "moz256.depth"),
}
print(f"{'surface':12s} {'integrator':18s} {'RMSE px':>8s} {'% of range':>10s}")
for name, scene in scenes.items():
    for integrator in ("poisson", "frankot_chellappa"):
        depth = shadecut.integrate(scene.normals, scene.mask, integrator)
        residual = (depth - scene.depth)[scene.mask]
        rmse = float(np.sqrt(np.mean((residual - residual.mean()) ** 2)))
        print(f"{name:12s} {integrator:18s} {rmse:8.3f} {100 * rmse / np.ptp(scene.depth[scene.mask]):10.2f}")
