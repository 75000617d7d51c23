"""Peak memory of one reconstruct() call per pixel, over what its input holds: the model that
reconstruct() checks a call against before it starts (docs/benchmarks.md, "Memory").

Run: PYTHONPATH=addon /usr/bin/python3 scripts/measure_memory.py SIZE [METHOD] [OPTIONS]
(a full-frame bump field of SIZE x SIZE pixels under (0.7, 0.2, 1); OPTIONS a Python dict of
ReconstructOptions fields, e.g. "{'coarse_to_fine_band': -1}"). Each run is its own process, so that
its peak is the call's.
"""

import ast
import sys

import shadecut
from shadecut import synthetic


def main() -> int:
    size = int(sys.argv[1])
    method = sys.argv[2] if len(sys.argv) > 2 else "graphcut"
    options = ast.literal_eval(sys.argv[3]) if len(sys.argv) > 3 else {}
    image = synthetic.bumps((0.7, 0.2, 1.0), size).image.copy()
    # The scene's own float64 work arrays peak above the call's: start a fresh high-water mark.
    with open("/proc/self/clear_refs", "w") as refs:
        refs.write("5")
    before = _status_kilobytes("VmRSS")
    shadecut.reconstruct(image, (0.7, 0.2, 1.0), None, method=method, **options)
    added = (_status_kilobytes("VmHWM") - before) * 1024
    print(f"{size} x {size}, {method} {options}: peak {added / 2**20:.0f} MB above the input, "
          f"{added / size**2:.0f} bytes per pixel")
    return 0


def _status_kilobytes(key: str) -> int:
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith(f"{key}:"))


if __name__ == "__main__":
    sys.exit(main())
