"""Cycles, seconds and error of graphcut on Mozart for several convergence tolerances.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/compare_tolerance.py
"""

import time
from pathlib import Path

import shadecut
from shadecut import synthetic

REPO = Path(__file__).resolve().parents[1]
scene = synthetic.mozart(REPO / "data" / "mozart" / "moz256.depth")
print(f"{'tolerance':>9s} {'cycles':>6s} {'seconds':>7s} {'energy':>9s} {'error deg':>9s}")
for tolerance in (0.0, 1e-3, 1e-2):
    start = time.perf_counter()
    result = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo, tolerance=tolerance)
    seconds = time.perf_counter() - start
    print(f"{tolerance:9g} {result.stats.cycles:6d} {seconds:7.2f} {result.stats.energy_per_cycle[-1]:9.1f} "
          f"{scene.mean_error(result.normals):9.2f}")
