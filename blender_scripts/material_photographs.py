"""The scanned materials photographed in Blender: each material's surface (its measured normal map
integrated, in pixel units) as a textured mesh, rendered by Cycles under several distant lights with
the shadows it casts on itself and the light bouncing between its parts, then read by
``shadecut.reconstruct`` given all the photographs, beside plain least squares, each photograph read
alone (scene "relief") and a flat normal map, against the render's own normals.

    blender -b --factory-startup -P blender_scripts/material_photographs.py -- [--materials DIR]
        [--size 128] [--samples 512] [--half test|training|both] [--figure PNG]

Prints docs/results.md's "Scanned materials in Blender" table (mean angular error in degrees over the
frame eroded by 2 pixels); with --figure, draws the rock's four photographs and normals
(docs/material_photographs.png).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import bpy
import numpy as np

REPO = Path(__file__).resolve().parents[1]
for _path in (str(REPO / "addon"), str(Path(__file__).resolve().parent)):  # shadecut; dataset_generator.py
    if _path not in sys.path:
        sys.path.insert(0, _path)

import shadecut  # noqa: E402  (after the path insert: the repository's package)
from dataset_generator import quiet_stdout  # noqa: E402
from shadecut import materials  # noqa: E402
from shadecut.evaluation import plain_least_squares  # noqa: E402
from shadecut.imaging import normal_colors  # noqa: E402
from shadecut.blender import lambertian  # noqa: E402
from shadecut.blender.mesh import depth_mesh  # noqa: E402

MATERIALS = REPO.parent / "shared" / "data" / "materials"
FIGURE_MATERIAL = "Rock029"  # the steepest of the test half: the most shadow and bounce
SLANT = 40.0  # issue 45's multi-angle capture: the lights at 40 degrees from the viewer, evenly around


@dataclass
class Errors:
    """Mean angular errors (degrees) of one material under one set of lights."""

    several: float  # shadecut.reconstruct given every photograph and its light
    plain: float  # plain least squares over the same photographs, nothing left out
    alone: float  # the mean over the photographs of each read alone (scene "relief", light given)
    flat: float  # a flat normal map
    render_seconds: float


@dataclass
class Reading:
    """Photographs of one material rendered by Cycles and the normals read from them."""

    images: list  # K (H, W) float32 linear grey photographs
    truth: np.ndarray  # (H, W, 3) the render's own normals, camera frame
    frame: np.ndarray  # (H, W) bool, every pixel the surface covers
    several: np.ndarray  # (H, W, 3) shadecut.reconstruct given every photograph and its light
    plain: np.ndarray  # (H, W, 3) plain least squares over the same photographs
    alone: list  # K (H, W, 3): each photograph read alone (scene "relief", light given)
    render_seconds: float


def surface_depth(material: materials.Material, size: int) -> tuple[np.ndarray, slice]:
    """The depth (pixel units) of the material's centre ``size`` pixels square, with the rows' and
    columns' slice of it: the measured normals integrated over the whole map, so that its slopes, its
    shadows and its bounces are those of the measured surface at its own resolution."""
    side = min(material.normals.shape[:2])
    if not 2 <= size <= side:
        raise ValueError(f"a {material.normals.shape[1]} x {material.normals.shape[0]} material cannot be rendered "
                         f"at {size} px: give a size from 2 to {side}")
    start = (side - size) // 2
    window = slice(start, start + size)
    return shadecut.integrate(material.normals)[window, window], window


def colour_image(name: str, albedo: np.ndarray) -> bpy.types.Image:
    """A new float image of ``albedo`` ((H, W, 3) linear RGB, row 0 at the top)."""
    height, width = albedo.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)  # float: scene linear
    pixels = np.ones((height, width, 4), dtype=np.float32)
    pixels[..., :3] = albedo[::-1]  # Blender's rows run from the bottom
    image.pixels.foreach_set(pixels.ravel())
    return image


def material_object(material: materials.Material, size: int) -> bpy.types.Object:
    """The material's centre ``size`` pixels square as a new mesh object facing the renderer's front
    camera (-Y), its colour as the base colour; the caller removes it (:func:`remove_object`)."""
    depth, window = surface_depth(material, size)
    mesh = depth_mesh(f"{material.name} surface", depth, np.ones(depth.shape, dtype=bool), size=float(size))
    shader = bpy.data.materials.new(f"{material.name} colour")
    shader.use_nodes = True
    tree = shader.node_tree
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = colour_image(f"{material.name} colour", material.albedo[window, window])
    texture.interpolation = "Closest"  # one texel per pixel, as the render samples pixel centres
    principled = next(node for node in tree.nodes if node.type == "BSDF_PRINCIPLED")
    tree.links.new(texture.outputs["Color"], principled.inputs["Base Color"])
    mesh.materials.append(shader)
    surface = bpy.data.objects.new(material.name, mesh)
    surface.rotation_euler = (math.pi / 2.0, 0.0, 0.0)  # the mesh's +Z (toward its viewer) becomes -Y
    return surface


def remove_object(surface: bpy.types.Object) -> None:
    """Removes ``surface`` with its mesh, material and colour image."""
    mesh = surface.data
    shader = mesh.materials[0]
    image = next(node.image for node in shader.node_tree.nodes if node.type == "TEX_IMAGE")
    bpy.data.objects.remove(surface)
    bpy.data.meshes.remove(mesh)
    bpy.data.materials.remove(shader)
    image.user_clear()  # the renders' stand-ins of the material, removed, still count as its users in Blender 3.4
    bpy.data.images.remove(image)


def photographs(surface: bpy.types.Object, size: int, lights: np.ndarray, samples: int) -> list:
    """One Cycles render (:class:`shadecut.blender.lambertian.LambertianRender`), ``size`` pixels
    square, per light (K x 3, camera frame): the material's own colours, cast shadows and bounces."""
    with quiet_stdout(True):
        return [lambertian.render_lambertian([surface], light=light, resolution=(size, size), albedo=None,
                                             shadows=True, indirect=True, samples=samples, margin=0.0)
                for light in lights]


def read(material: materials.Material, size: int, count: int, samples: int) -> Reading:
    """``count`` photographs (:data:`SLANT`) of the centre ``size`` pixels square of ``material``, read."""
    lights = materials.lights_around(count, SLANT)
    surface = material_object(material, size)
    try:
        start = time.perf_counter()
        renders = photographs(surface, size, lights, samples)
        seconds = time.perf_counter() - start
    finally:
        remove_object(surface)
    frame = renders[0].mask
    images = [render.image for render in renders]
    return Reading(images=images, truth=renders[0].normals, frame=frame,
                   several=shadecut.reconstruct(images, lights, frame).normals,
                   plain=plain_least_squares(images, lights),
                   alone=[shadecut.reconstruct(image, light, frame, scene="relief").normals
                          for image, light in zip(images, lights)], render_seconds=seconds)


def error_of(reading: Reading, normals: np.ndarray) -> float:
    """The mean angular error of ``normals`` against the render's, the frame eroded by 2 pixels."""
    return shadecut.angular_error(normals, reading.truth, shadecut.erode_mask(reading.frame, 2))


def errors(reading: Reading) -> Errors:
    flat = np.zeros_like(reading.truth)
    flat[..., 2] = 1.0
    return Errors(several=error_of(reading, reading.several), plain=error_of(reading, reading.plain),
                  alone=float(np.mean([error_of(reading, normals) for normals in reading.alone])),
                  flat=error_of(reading, flat), render_seconds=reading.render_seconds)


def draw(reading: Reading, title: str, out: Path) -> None:
    """The photographs, the render's normals, ShadeCut's from all of them and from the first alone."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = [(np.clip(image, 0.0, 1.0) ** (1 / 2.2), f"photograph {k + 1}") for k, image in enumerate(reading.images)]
    shown += [(normal_colors(reading.truth), "true normals"),
              (normal_colors(reading.several), f"ShadeCut, all: {error_of(reading, reading.several):.2f}°"),
              (normal_colors(reading.alone[0]), f"photograph 1 alone: {error_of(reading, reading.alone[0]):.2f}°")]
    columns = max(len(reading.images), 3)
    figure, axes = plt.subplots(2, columns, figsize=(3.2 * columns, 6.8), constrained_layout=True)
    for axis, (picture, caption) in zip(axes[0], shown[:len(reading.images)]):
        axis.imshow(picture, cmap="gray", vmin=0.0, vmax=1.0)
        axis.set_title(caption)
    for axis, (picture, caption) in zip(axes[1], shown[len(reading.images):]):
        axis.imshow(picture)
        axis.set_title(caption)
    for axis in axes.flat:
        axis.axis("off")
    figure.suptitle(title)
    figure.savefig(out, dpi=60)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="material_photographs.py", description=__doc__.splitlines()[0])
    parser.add_argument("--materials", type=Path, default=MATERIALS, help="the scanned materials' folder")
    parser.add_argument("--size", type=int, default=128, help="pixels on a side of every render")
    parser.add_argument("--samples", type=int, default=lambertian.INDIRECT_SAMPLES, help="Cycles samples per pixel")
    parser.add_argument("--half", choices=("test", "training", "both"), default="test")
    parser.add_argument("--figure", type=Path, help=f"draw {FIGURE_MATERIAL}'s four photographs and normals into this PNG")
    args = parser.parse_args(argv)
    names = {"test": materials.TEST, "training": materials.TRAINING,
             "both": materials.TRAINING + materials.TEST}[args.half]
    print("| material | half | photographs | ShadeCut | plain least squares | one photograph (mean) | flat | render seconds |")
    print("|---|---|---|---|---|---|---|---|")
    for name in names:
        material = materials.load_material(args.materials / name)
        half = "test" if name in materials.TEST else "training"
        for count in (4, 8):
            reading = read(material, args.size, count, args.samples)
            found = errors(reading)
            if args.figure and name == FIGURE_MATERIAL and count == 4:
                draw(reading, f"{name}: four Cycles photographs (shadows, bounces), {args.size} px", args.figure)
            print(f"| {name} | {half} | {count} | {found.several:.2f} | {found.plain:.2f} | {found.alone:.2f} | "
                  f"{found.flat:.2f} | {found.render_seconds:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []))
