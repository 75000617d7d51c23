"""Times building the add-on's result object from a reconstruction (mesh or displaced plane, UVs,
material, link), at the automatic density and at density 1; with --operator, also the whole
"Reconstruct" operator with the panel's default settings on a synthetic sphere image (an object on a
transparent background, light given) and a full-frame bump field (Subject Relief, light estimated: a
photo of a wall or a texture, as artists bring).

    blender -b --factory-startup --python-exit-code 1 -P blender_scripts/benchmark_mesh.py -- \\
        [--sizes 2048] [--repeat 3] [--max-vertices 250000] [--operator]

Prints the command, the machine and the median over the repetitions; the core's own time is
shadecut_bench's business.
"""

import argparse
import datetime
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "addon"))
import shadecut  # noqa: E402
from shadecut import synthetic  # noqa: E402
from shadecut.blender.reconstruct_job import mesh_step  # noqa: E402
from shadecut.blender.result import result_object  # noqa: E402

LIGHT = (1.0, 0.0, 1.0)


def cpu_model() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown CPU"


def timed(repeat: int, run, clean) -> str:
    seconds = []
    for _ in range(repeat):
        start = time.perf_counter()
        made = run()
        seconds.append(time.perf_counter() - start)
        clean(made)
    return f"median {statistics.median(seconds):.2f} s over {repeat} (min {min(seconds):.2f}, max {max(seconds):.2f})"


def remove_result(obj) -> None:
    """Removes a result object and every datablock it brought (mesh, material, height image)."""
    mesh, textures = obj.data, [modifier.texture for modifier in obj.modifiers]
    bpy.data.objects.remove(obj)
    for material in mesh.materials:
        bpy.data.materials.remove(material)
    bpy.data.meshes.remove(mesh)
    for texture in textures:
        bpy.data.images.remove(texture.image)
        bpy.data.textures.remove(texture)


def benchmark_result_object(size: int, repeat: int, max_vertices: int) -> None:
    scene = synthetic.sphere(light=LIGHT, size=size, radius_fraction=0.5)
    mask = np.ones_like(scene.mask)  # every pixel a vertex: the worst case
    source = bpy.data.images.new("source", 4, 4)
    for density in (0, 1):
        step = mesh_step(mask, density, max_vertices)
        vertices = np.count_nonzero(mask[::step, ::step])
        for displace in (False, True):
            def run():
                return result_object(bpy.context, "bench", scene.depth, scene.normals, mask, source_image=source,
                                     width=2.0, depth_scale=1.0, density=step, displace=displace,
                                     normal_map=False)

            kind = "displaced plane" if displace else "mesh"
            label = f"automatic (Max vertices {max_vertices:,})" if density == 0 else "1"
            print(f"{kind} of a {size} x {size} result, density {label} = step {step}, {vertices:,} vertices: "
                  f"{timed(repeat, run, remove_result)}", flush=True)
    bpy.data.images.remove(source)


def benchmark_operator(size: int, repeat: int, subject: str) -> None:
    """The operator as an artist runs it, default settings: working size, reconstruction, mesh.
    ``subject`` "sphere": an object on a transparent background, the light typed; "relief": a bump
    field filling the frame, Subject Relief, the light estimated."""
    scene = (synthetic.sphere(light=LIGHT, size=size) if subject == "sphere" else
             synthetic.bumps(light=LIGHT, size=size))
    image = bpy.data.images.new(subject, size, size, alpha=True, float_buffer=True)
    rgba = np.dstack([scene.image, scene.image, scene.image, scene.mask.astype(np.float32)])
    image.pixels.foreach_set(np.ascontiguousarray(rgba[::-1], dtype=np.float32).ravel())
    settings = bpy.context.scene.shadecut
    for name in ("scene", "light_source"):
        settings.property_unset(name)
    settings.image = image
    if subject == "sphere":
        settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    else:
        settings.scene = "relief"

    def run():
        assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
        return bpy.context.active_object

    method = shadecut.ReconstructOptions().method.name if settings.method == "DEFAULT" else settings.method
    print(f"operator on a {size} x {size} {subject} image (Subject {settings.scene}, light {settings.light_source}, "
          f"method {method}, Max size {settings.max_resolution}, auto density {settings.auto_density}, "
          f"Vertex limit {settings.max_vertices:,}): {timed(repeat, run, remove_result)}", flush=True)
    bpy.data.images.remove(image)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="benchmark_mesh.py")
    parser.add_argument("--sizes", default="2048", help="square result sizes, comma-separated")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--max-vertices", type=int, default=shadecut.MAX_VERTICES,
                        help="the automatic density's budget")
    parser.add_argument("--operator", action="store_true", help="also time the whole operator per size")
    args = parser.parse_args(argv)
    print(f"command: blender {' '.join(sys.argv[1:])}")
    # Another process's load slows every figure: the load average says how busy the machine was.
    print(f"machine: nproc {len(os.sched_getaffinity(0))}, {cpu_model()}, load average "
          f"{os.getloadavg()[0]:.1f}, Blender {bpy.app.version_string}; "
          f"{datetime.datetime.now().isoformat(timespec='minutes')}", flush=True)
    if args.operator:
        shadecut.register()
    for size in (int(value) for value in args.sizes.split(",")):
        benchmark_result_object(size, args.repeat, args.max_vertices)
        if args.operator:
            for subject in ("sphere", "relief"):
                benchmark_operator(size, args.repeat, subject)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []))
