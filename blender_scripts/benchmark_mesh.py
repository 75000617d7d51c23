"""Times building the add-on's result object from a reconstruction (mesh, UVs, material, link).

    blender -b --factory-startup --python-exit-code 1 -P blender_scripts/benchmark_mesh.py -- [--sizes 512,1024] [--repeat 5]

Prints the median over the repetitions per size; the core's own time is shadecut_bench's business.
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "addon"))
from shadecut import synthetic  # noqa: E402
from shadecut.blender.result import result_object  # noqa: E402


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="benchmark_mesh.py")
    parser.add_argument("--sizes", default="512,1024", help="square image sizes, comma-separated")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    source = bpy.data.images.new("source", 4, 4)
    for size in (int(value) for value in args.sizes.split(",")):
        scene = synthetic.sphere(light=(1, 0, 1), size=size, radius_fraction=0.5)
        mask = np.ones_like(scene.mask)  # every pixel a vertex: the worst case
        seconds = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            obj = result_object(bpy.context, "bench", scene.depth, scene.normals, mask, source_image=source,
                                width=2.0, depth_scale=1.0, density=1, displace=False, normal_map=False)
            seconds.append(time.perf_counter() - start)
            mesh = obj.data
            bpy.data.objects.remove(obj)
            bpy.data.meshes.remove(mesh)
        print(f"result object {size} x {size} ({size * size} vertices): median {statistics.median(seconds):.3f} s "
              f"over {args.repeat} (min {min(seconds):.3f}, max {max(seconds):.3f})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []))
