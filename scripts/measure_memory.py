"""Peak memory of one reconstruct() call per pixel, over what its input holds: the model that
reconstruct() checks a call against before it starts (docs/benchmarks.md, "Memory").

Run: PYTHONPATH=addon /usr/bin/python3 scripts/measure_memory.py SIZE [METHOD] [OPTIONS] [--object N]
(a full-frame bump field of SIZE x SIZE pixels under (0.7, 0.2, 1), or with --object a sphere N
pixels across, masked, somewhere in a SIZE x SIZE black frame; OPTIONS a Python dict of
ReconstructOptions fields, e.g. "{'coarse_to_fine_band': -1}"). Each run is its own process, so that
its peak is the call's.
"""

import argparse
import ast
import sys
import time

import numpy as np

import shadecut
from shadecut import synthetic

LIGHT = (0.7, 0.2, 1.0)


def scene(size: int, object_size: int):
    """The image and mask of the call: a full-frame bump field, or a sphere off-centre in a black frame."""
    if not object_size:
        return synthetic.bumps(LIGHT, size).image.copy(), None
    sphere = synthetic.sphere(LIGHT, object_size)
    image, mask = np.zeros((size, size), np.float32), np.zeros((size, size), bool)
    top, left = size * 2 // 5 + 3, size * 2 // 3 + 5
    image[top:top + object_size, left:left + object_size] = sphere.image
    mask[top:top + object_size, left:left + object_size] = sphere.mask
    return image, mask


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("size", type=int)
    parser.add_argument("method", nargs="?", default="graphcut")
    parser.add_argument("options", nargs="?", type=ast.literal_eval, default={})
    parser.add_argument("--object", type=int, default=0, metavar="N", help="a sphere N pixels across in the frame")
    args = parser.parse_args()
    image, mask = scene(args.size, args.object)
    # The scene's own float64 work arrays peak above the call's: start a fresh high-water mark.
    with open("/proc/self/clear_refs", "w") as refs:
        refs.write("5")
    before = _status_kilobytes("VmRSS")
    started = time.perf_counter()
    shadecut.reconstruct(image, LIGHT, mask, method=args.method, **args.options)
    seconds = time.perf_counter() - started
    added = (_status_kilobytes("VmHWM") - before) * 1024
    what = f"a {args.object}-pixel sphere in " if args.object else ""
    print(f"{what}{args.size} x {args.size}, {args.method} {args.options}: peak {added / 2**20:.0f} MB above the input, "
          f"{added / args.size**2:.0f} bytes per pixel, {seconds:.2f} s")
    return 0


def _status_kilobytes(key: str) -> int:
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith(f"{key}:"))


if __name__ == "__main__":
    sys.exit(main())
