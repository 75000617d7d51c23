"""Several photographs (issue 45): shadecut.reconstruct given several photographs and their lights,
against plain least squares over the same photographs (every one, nothing left out), one photograph
alone (the mean over the set) and, for the materials, a flat normal map.

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_photometric.py [DATA_FOLDER] [--rug-figure PNG] [--rug-nearness]
        [--two-photograph-bounds [--albedo-weights W ...] [--iterations N] [--objects NAME ...]]

- DiLiGenT (DATA_FOLDER/diligent): 2, 4, 8 and all 19 of an object's photographs with their
  calibrated lights; one photograph is graphcut with its light. Then 4, 8 and all with the lights
  estimated from them (the default hint), beside what lights at one slant can do at best. Mean angular error in degrees over the
  mask eroded by 2 pixels, as every evaluation measures.
- The scanned materials (DATA_FOLDER/materials): each measured normal map rendered Lambertian
  (albedo x max(0, n . S)) under 4 and 8 lights at slant 40 degrees around the viewer, without and
  with cast shadows (materials.lambertian_photographs); one photograph is the relief reconstruction
  with its light. Mean over every pixel.

- With --two-photograph-bounds, only what DiLiGenT's two photographs (079, 031) can give, by the
  bounds of shadecut.evaluation.two_photograph_bounds: one albedo for the object, and the descent
  from the truth on the circles of the paper's smoothness plus an albedo term of each weight
  (--albedo-weights, default 0 1), at most --iterations steps (default 2000), on --objects.
- The felt rug (DATA_FOLDER/multi_angle/felt_rug), with --rug-figure: its four real photographs,
  the lights named by their sides, drawn beside the normal map, the de-lit colour and the depth.
  With --rug-nearness, only whether its lamp stood near: the residual at lamp distances and the four
  photographs' singular values.

DATA_FOLDER defaults to ../shared/data; a part whose folder is absent is left out. The tables and the
figure in docs/results.md are its output. Nothing is tuned here: the thresholds are the option
table's defaults.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import shadecut
from shadecut import diligent, imaging, materials
from shadecut.evaluation import PHOTOGRAPH_SETS, median_light_error, plain_least_squares, set_label
from shadecut.evaluation import two_photograph_bounds

OBJECTS = ("ball", "cat", "reading")

MATERIAL_SLANT_DEGREES = 40.0


def timed(photographs: list, lights: np.ndarray, mask=None) -> tuple[shadecut.Reconstruction, float]:
    start = time.perf_counter()
    result = shadecut.reconstruct(photographs, lights, mask)
    return result, time.perf_counter() - start


def diligent_row(folder: Path, set_name: str, images) -> str:
    loaded = diligent.load_object(folder, images=images)
    label = set_label(set_name, images, len(loaded.photos))
    inner = shadecut.erode_mask(loaded.mask, 2)
    ours, seconds = timed(loaded.photos, loaded.lights, loaded.mask)
    single = np.mean([shadecut.angular_error(shadecut.reconstruct(photo, light, loaded.mask).normals, loaded.normals, inner)
                      for photo, light in zip(loaded.photos, loaded.lights)])
    least_squares = np.where(loaded.mask[..., None], plain_least_squares(loaded.photos, loaded.lights), 0.0)
    return (f"| {folder.name[:-3]} | {label} | {shadecut.angular_error(ours.normals, loaded.normals, inner):.2f} | "
            f"{shadecut.angular_error(least_squares, loaded.normals, inner):.2f} | {single:.2f} | "
            f"{ours.stats.pair_pixels / loaded.mask.sum():.1%} | {seconds:.2f} |")


def estimated_row(folder: Path, set_name: str, images) -> str:
    """The lights estimated from the photographs (default hint) against the calibrated ones and the
    hint's own limit: the true lights' azimuths at the hint's slant, and at their own mean slant."""
    loaded = diligent.load_object(folder, images=images)
    inner = shadecut.erode_mask(loaded.mask, 2)
    truth = loaded.lights / np.linalg.norm(loaded.lights, axis=1, keepdims=True)

    def error(lights) -> float:
        return shadecut.angular_error(shadecut.reconstruct(loaded.photos, lights, loaded.mask).normals, loaded.normals, inner)

    estimated, seconds = timed(loaded.photos, None, loaded.mask)
    hint = shadecut.ReconstructOptions().light_slant
    mean_slant = float(np.degrees(np.arccos(truth[:, 2])).mean())
    return (f"| {folder.name[:-3]} | {set_label(set_name, images, len(loaded.photos))} | {error(loaded.lights):.2f} | "
            f"{shadecut.angular_error(estimated.normals, loaded.normals, inner):.2f} | {error(materials.at_one_slant(truth, hint)):.2f} | "
            f"{error(materials.at_one_slant(truth, mean_slant)):.2f} ({mean_slant:.1f}°) | "
            f"{median_light_error(estimated.lights, truth):.1f} | "
            f"{estimated.stats.light_uncertainty:.1f} | {seconds:.2f} |")


def single_photograph_error(material: materials.Material, photographs: list, lights: np.ndarray) -> float:
    return float(np.mean([shadecut.angular_error(shadecut.reconstruct(photo, light, scene="relief").normals,
                                                 material.normals) for photo, light in zip(photographs, lights)]))


def material_row(material: materials.Material, half: str, count: int) -> str:
    lights = materials.lights_around(count, MATERIAL_SLANT_DEGREES)
    photographs = materials.lambertian_photographs(material, lights)
    ours, seconds = timed(photographs, lights)
    shadowed = materials.lambertian_photographs(material, lights, cast_shadows=True)
    ours_shadowed = shadecut.reconstruct(shadowed, lights)
    flat = np.broadcast_to(np.array([0.0, 0.0, 1.0], np.float32), material.normals.shape)
    return (f"| {material.name} | {half} | {count} | {shadecut.angular_error(ours.normals, material.normals):.2f} | "
            f"{shadecut.angular_error(plain_least_squares(photographs, lights), material.normals):.2f} | "
            f"{single_photograph_error(material, photographs, lights):.2f} | "
            f"{shadecut.angular_error(ours_shadowed.normals, material.normals):.2f} | "
            f"{single_photograph_error(material, shadowed, lights):.2f} | "
            f"{shadecut.angular_error(flat, material.normals):.2f} | "
            f"{ours.stats.pair_pixels / material.height.size:.1%} | {seconds:.2f} |")


RUG_SIDES = ("above", "below", "left", "right")


def rug_figure(folder: Path, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    photographs = [shadecut.load_image(folder / f"{side}.jpg") for side in RUG_SIDES]
    result = shadecut.reconstruct([photo.colour for photo in photographs], list(RUG_SIDES), scene="relief")
    relief = shadecut.render(result.depth, shadecut.light_from_side("top-left"))
    low, high = np.percentile(result.depth, [1, 99])
    shown = [(photo.colour, f"lit from {side}") for photo, side in zip(photographs, RUG_SIDES)]
    shown += [(imaging.normal_colors(result.normals), "normal map"),
              (result.albedo_colour / np.percentile(result.albedo_colour, 99.5), "de-lit colour"),
              ((result.depth - low) / (high - low), "depth (brighter = higher)"),
              (relief ** 2.2, "depth, lit from the top left")]
    figure, axes = plt.subplots(2, 4, figsize=(16, 6.6))
    for axis, (picture, title) in zip(axes.flat, shown):
        axis.imshow(np.clip(picture, 0, 1) ** (1 / 2.2) if title != "normal map" else picture, cmap="gray")
        axis.set_title(title)
    for axis in axes.flat:
        axis.axis("off")
    figure.tight_layout()
    figure.savefig(out, dpi=45)


def rug_nearness(folder: Path) -> None:
    """Whether the rug's lamp stood near: the photographs' median residual over the albedo, the lights
    named by their sides, read at lamp distances from distant (0) to 4 frame widths; and the singular
    values of the four photographs (smoothed by 4 px, pixels lit in all), which distant lights leave
    of rank three."""
    from scipy import ndimage

    images = [shadecut.load_image(folder / f"{side}.jpg").image for side in RUG_SIDES]
    sides = ["top", "bottom", "left", "right"]
    for distance in (0.0, 0.5, 1.0, 2.0, 4.0):
        result = shadecut.reconstruct(images, sides, scene="relief", light_distance=distance)
        print(f"felt rug, light_distance {distance:g}: median residual / median albedo "
              f"{np.median(result.residual) / np.median(result.albedo_map):.2f}")
    smoothed = np.stack([ndimage.gaussian_filter(image, 4.0).ravel() for image in images])
    lit = (smoothed > 0.1 * smoothed.max(axis=0)).all(axis=0)
    values = np.linalg.svd(smoothed[:, lit], compute_uv=False)
    print("felt rug, singular values of the four photographs (smoothed by 4 px, lit in all): "
          + ", ".join(f"{value / values[0]:.2f}" for value in values))


def two_photograph_row(folder: Path, albedo_weights: list[float], iterations: int) -> str:
    loaded = diligent.load_object(folder, images=PHOTOGRAPH_SETS["two"])
    scored = shadecut.erode_mask(loaded.mask, 2)
    circles = two_photograph_bounds.pair_circles(loaded.photos, loaded.lights, loaded.mask)
    error, quantile = two_photograph_bounds.one_albedo_bound(circles, loaded.normals, scored)
    cells = [f"{error:.2f} (quantile {quantile:.3f})"]
    for weight in albedo_weights:
        descent = two_photograph_bounds.circle_descent(circles, loaded.normals, scored, weight, iterations)
        cells.append(f"{descent.error_before:.2f} → {descent.error_after:.2f} ({descent.iterations} steps)")
    return f"| {folder.name[:-3]} | {circles.usable[scored].mean():.1%} | " + " | ".join(cells) + " |"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("data", nargs="?", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data")
    parser.add_argument("--rug-figure", type=Path, help="draw the felt rug's reconstruction into this PNG")
    parser.add_argument("--rug-nearness", action="store_true",
                        help="only measure whether the felt rug's lamp stood near (residuals, singular values)")
    parser.add_argument("--two-photograph-bounds", action="store_true",
                        help="only what two of DiLiGenT's photographs can give (the bounds, slow: minutes)")
    parser.add_argument("--albedo-weights", type=float, nargs="+", default=[0.0, 1.0],
                        help="with --two-photograph-bounds: the albedo weights of the descents (default 0 1)")
    parser.add_argument("--iterations", type=int, default=2000,
                        help="with --two-photograph-bounds: L-BFGS steps of each descent at most (default 2000)")
    parser.add_argument("--objects", nargs="+", choices=OBJECTS, default=list(OBJECTS),
                        help="with --two-photograph-bounds: the DiLiGenT objects (default all three)")
    arguments = parser.parse_args()
    data = arguments.data
    if arguments.two_photograph_bounds:
        weights = arguments.albedo_weights
        print("| object | lit in both | one albedo, the truth's choice | "
              + " | ".join(f"descent from the truth, albedo weight {w:g}" for w in weights) + " |")
        print("|---" * (3 + len(weights)) + "|")
        for name in arguments.objects:
            if (data / "diligent" / f"{name}PNG").is_dir():
                print(two_photograph_row(data / "diligent" / f"{name}PNG", weights, arguments.iterations), flush=True)
        return 0
    if arguments.rug_nearness:
        rug_nearness(data / "multi_angle" / "felt_rug")
        return 0
    if arguments.rug_figure:
        rug_figure(data / "multi_angle" / "felt_rug", arguments.rug_figure)
    print("| object | photographs | ShadeCut | plain least squares | one photograph (mean) | two lit | seconds |")
    print("|---|---|---|---|---|---|---|")
    for name in ("ball", "cat", "reading"):
        if (data / "diligent" / f"{name}PNG").is_dir():
            for set_name, images in PHOTOGRAPH_SETS.items():
                print(diligent_row(data / "diligent" / f"{name}PNG", set_name, images), flush=True)
    print("\n| object | photographs | calibrated lights | lights estimated | true azimuths at the hint's slant | "
          "true azimuths at their mean slant | light error (median) | uncertainty | seconds |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in ("ball", "cat", "reading"):
        if (data / "diligent" / f"{name}PNG").is_dir():
            for set_name in ("four", "eight", "all"):
                print(estimated_row(data / "diligent" / f"{name}PNG", set_name, PHOTOGRAPH_SETS[set_name]), flush=True)
    if not (data / "materials").is_dir():
        return 0
    print("\n| material | half | photographs | ShadeCut | plain least squares | one photograph (mean) | "
          "ShadeCut, cast shadows | one photograph, cast shadows | flat | two lit | seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for half, names in (("training", materials.TRAINING), ("test", materials.TEST)):
        for name in names:
            material = materials.load_material(data / "materials" / name)
            for count in (4, 8):
                print(material_row(material, half, count), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
