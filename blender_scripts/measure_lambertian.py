"""Measures the Lambertian renderer: agreement with shadecut.render, analytic sphere errors, render
times per catalogue shape, and the noise of indirect light against the number of samples.

    blender -b --factory-startup -P blender_scripts/measure_lambertian.py -- [--size 256] [--no-indirect]

Prints the figures of the README's "Synthetic renders and datasets" section.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
for _path in (str(REPO / "addon"), str(Path(__file__).resolve().parent)):  # shadecut; shapes.py, dataset_generator.py
    if _path not in sys.path:
        sys.path.insert(0, _path)

import shadecut  # noqa: E402  (after the path insert: the repository's package)
import shapes  # noqa: E402
from dataset_generator import quiet_stdout  # noqa: E402
from shadecut.blender import lambertian  # noqa: E402

LIGHT = (1.0, 0.5, 1.0)


def timed_render(objects, **kwargs):
    start = time.perf_counter()
    render = lambertian.render_lambertian(objects, **kwargs)
    return render, time.perf_counter() - start


def agreement(render) -> float:
    expected = shadecut.render(render.normals, render.light, render.albedo, render.mask)
    return float(np.abs(render.image - expected)[shadecut.erode_mask(render.mask, 2)].mean())


def sphere_truth(render):
    """Exact normals and camera-frame z of the unit sphere at the origin at the pixel centres."""
    width, height = render.meta["resolution"]
    size = render.meta["pixel_size"]
    camera = np.array(render.meta["camera"]["matrix_world"])
    rows, cols = np.mgrid[0:height, 0:width]
    centre = camera[:3, :3].T @ -camera[:3, 3]
    dx = (cols + 0.5 - width / 2) * size - centre[0]
    dy = (height / 2 - rows - 0.5) * size - centre[1]
    h = np.sqrt(np.maximum(1 - dx**2 - dy**2, 0))
    return np.dstack([dx, dy, h]).astype(np.float32), centre[2] + h


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="blender -b -P blender_scripts/measure_lambertian.py --")
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--no-indirect", action="store_true", help="skip the (slow) indirect-light noise table")
    args = parser.parse_args(argv)
    resolution = (args.size, args.size)

    print(f"| shape ({args.size} px) | render s | mean abs vs shadecut.render (mask eroded 2 px) |")
    print("|---|---|---|")
    for name in shapes.CATALOGUE:
        objects = shapes.BUILDERS[name](0)
        with quiet_stdout(True):
            timed_render(objects, light=LIGHT, resolution=(16, 16))  # Cycles' first start is slower
            render, seconds = timed_render(objects, light=LIGHT, resolution=resolution)
        print(f"| {name} | {seconds:.2f} | {agreement(render):.2e} |")
        if name == "sphere":
            sphere = render
        shapes.remove_objects(objects)

    normals, z = sphere_truth(sphere)
    inside = shadecut.erode_mask(sphere.mask, 2)
    angles = shadecut.angular_error_map(sphere.normals, normals, inside)[inside]
    depth = np.abs(sphere.depth - z)[inside] / sphere.meta["pixel_size"]
    print(f"\nsphere {args.size} px against the analytic sphere: normals {angles.mean():.3f} deg mean, "
          f"{angles.max():.3f} max; depth {depth.mean():.3f} px mean, {depth.max():.3f} max "
          f"(radius {1 / sphere.meta['pixel_size']:.1f} px)")

    if args.no_indirect:
        return 0
    objects = shapes.BUILDERS["suzanne"](0)
    kwargs = dict(light=(0.5, 0.3, 1.0), resolution=(64, 64), indirect=True)
    with quiet_stdout(True):
        reference, _ = timed_render(objects, samples=8192, **kwargs)
        direct, _ = timed_render(objects, light=(0.5, 0.3, 1.0), resolution=(64, 64))
    inside = shadecut.erode_mask(reference.mask, 2)
    share = (reference.clean_image - direct.clean_image)[inside]
    print(f"\nSuzanne 64 px with indirect light: it adds {share.mean():.4f} on average, up to {share.max():.3f}")
    print("| samples | seconds | rms difference to 8192 samples | mean abs |")
    print("|---|---|---|---|")
    for samples in (64, 256, 512, 1024):
        with quiet_stdout(True):
            render, seconds = timed_render(objects, samples=samples, **kwargs)
        difference = (render.clean_image - reference.clean_image)[inside]
        rms, mean = np.sqrt(np.mean(difference**2)), np.abs(difference).mean()
        print(f"| {samples} | {seconds:.2f} | {rms:.4f} | {mean:.4f} |")
    shapes.remove_objects(objects)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []))
