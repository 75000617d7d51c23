"""Chooses the default parameters of every method by one procedure, on training surfaces only.

Training surfaces: a sphere, a bowl, Gaussian bumps and dents in a layout of their own, two egg
crates, a torus (in proportions of its own) and a vase of shadecut.synthetic, each under its own
light. None of them is a test surface (the tests use other lights, other proportions, another bump
layout, Mozart and the evaluation's Blender meshes), so the defaults are not fitted to what the
tests measure.
For each method, every combination of its parameters on the grid below is scored by the mean, over
the training surfaces rendered at every size of --sizes, of the mean angular error on the mask eroded
by 2 pixels; the best wins. Scoring at more than one resolution keeps the choice from fitting one
pixel scale; the mean per size is printed beside the score to show how far apart they are.

The albedo estimate (top_fit's window) is chosen by the same procedure with --albedo: the training
surfaces are rendered under their own light and a grazing one (slant 60 degrees), at two albedos,
clean and with Blinn-Phong highlights of several widths and strengths, clipped at 1 like a
saturated photograph, and every window on the grid is scored by the
mean relative error of the albedo it estimates (the true light is given); then, with that window, the
agreement under which the brightest value is kept instead, by the same score. Then
the threshold above which pixels count as highlights (filled from their neighbours) is scored by
graphcut's mean angular error on the same renders, the albedo estimated.

The paint separation (albedo_method retinex) is chosen by the same procedure with --retinex: the
training surfaces painted (shadecut.synthetic.paint: patches, stripes, text, seeds of their own) and
plain, under their own light, with sensor noise (sigma = 0.01 sqrt(I) + 0.003 per channel), scored by
graphcut's mean angular error (true light, albedo estimated): first the two edge thresholds together,
then the share of the albedo below which a pixel is shadow, then the rim, then, on the same renders
with each Blinn-Phong lobe of the albedo's training (TRAINING_HIGHLIGHTS, up to twice the diffuse
albedo, clipped at 1) too, the highlight factor and the highlight_threshold of the shading image
(kRetinexHighlightThreshold; the stages before it fill no highlight) together, on one grid; then, on
the same renders, the number of passes (each after the first reads the paint against the surface the
pass before found; the stages before read it once), one more while its mean gain over the renders
is more than PASS_GAIN_SIGMAS standard errors of the paired gains; last, retinex with the chosen
values against top_fit decides albedo_method's default.

graphcut's coarse_to_fine_radius trades speed for accuracy, so it is not chosen by the lowest error
but, with --band-radius, as the smallest radius whose mean error on the training surfaces (at 256
and 512 pixels, where coarse to fine runs two and three finer levels) is within
BAND_RADIUS_SLACK degrees of the band at every pixel (radius -1).

Run: PYTHONPATH=addon /usr/bin/python3 scripts/tune_parameters.py [--methods NAME ...] [--sizes N ...]
(every method of the grid, at 128 and 256 pixels, by default; --methods tunes only those named, by
the same procedure; --albedo tunes only the albedo estimate; --band-radius only graphcut's
coarse_to_fine_radius, at 256 and 512 pixels unless --sizes says otherwise; --retinex only the
paint separation, at 128 pixels unless --sizes says otherwise; --viscosity-weight only
graphcut's viscosity_weight, every other option at its default, by the same score; --fit-smoothness
only graphcut's fit_smoothness, with fit_shading on, by the same score; --fit-max-slant only graphcut's
fit_max_slant, with fit_shading on, by the same score; --light-method only the light
estimator used for objects without a light, and the contour estimator's ring, by graphcut's score with
the light estimated, the training surfaces rendered under their own light and one of slant 5 degrees;
--detail-size only the reliefs' detail_scale_factor, on training reliefs: see scripts/tune_reliefs.py).
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time
from typing import Optional

import numpy as np

import shadecut
from shadecut import synthetic

TRAINING_BUMPS = (
    (-0.2, 0.2, 0.09, -0.08),
    (0.2, 0.2, 0.06, 0.09),
    (-0.2, -0.2, 0.06, 0.09),
    (0.2, -0.2, 0.09, -0.08),
)


SPARSE_TRAINING_BUMPS = (
    (-0.25, 0.25, 0.06, 0.08),
    (0.25, 0.0, 0.06, -0.08),
    (-0.1, -0.28, 0.05, 0.07),
)


def training_surfaces(size: int) -> dict[str, synthetic.Scene]:
    return {
        "sphere": synthetic.sphere((0.5, 0.5, 1.0), size, radius_fraction=0.4),
        "bowl": synthetic.sphere((-0.6, -0.4, 1.0), size, radius_fraction=0.4, bowl=True),
        "bumps": synthetic.bumps((0.8, -0.5, 1.0), size, features=TRAINING_BUMPS),
        "egg_crate": synthetic.egg_crate((1.0, 0.4, 1.0), size),
        "egg_crate_wide": synthetic.egg_crate((-0.5, 0.9, 1.0), size, periods=1.5, amplitude=0.08),
        "bumps_sparse": synthetic.bumps((-0.7, 0.3, 1.0), size, features=SPARSE_TRAINING_BUMPS),
        "torus": synthetic.torus((-0.3, -0.8, 1.0), size, major=0.28, minor=0.12),
        "vase": synthetic.vase((0.5, 0.6, 1.0), size),
    }


GRID = {
    "graphcut": {
        "data_weight": [0.2, 0.5, 1.0, 2.0],
        "min_curvature": [0.3, 1.0, 2.0],
        "undefined_weight": [0.0, 0.05, 0.2, 0.5],
        "contour_weight": [0.0, 1.0, 3.0, 10.0],
    },
    "graphcut_two": {"min_curvature": [0.3, 1.0, 2.0], "undefined_weight": [0.0, 0.05, 0.2, 0.5],
                     "contour_weight": [0.0, 1.0, 3.0, 10.0]},
    "lee_rosenfeld": {"min_curvature": [0.3, 1.0, 2.0]},
    "brooks_horn": {"smoothness": [0.3, 0.6, 1.0, 2.0, 4.0, 8.0], "iterations": [500, 2000, 8000],
                    "tolerance": [0.0, 1e-5, 1e-4]},
    "tsai_shah": {"iterations": [1, 2, 3, 5, 10, 20, 50, 100]},
    "upwind": {"iterations": [1, 2, 3, 5, 10, 100]},
}


ALBEDO_WINDOWS = [(start, end) for start in (0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6) for end in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 0.9, 1.0)
                  if start < end]
ALBEDO_AGREEMENTS = (0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0)
HIGHLIGHT_THRESHOLDS = (0.0, 1.05, 1.1, 1.2, 1.5, 2.0)
TRAINING_ALBEDOS = (0.2, 0.5)
# (strength, shininess) of the Blinn-Phong lobe added to the Lambertian image; (0, 1) is none.
TRAINING_HIGHLIGHTS = ((0.0, 1.0), (0.3, 20.0), (0.5, 100.0), (1.0, 50.0), (2.0, 300.0))


FIT_SMOOTHNESSES = (0.03, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0)
FIT_MAX_SLANTS = (45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 90.0)
VISCOSITY_WEIGHTS = (0.0, 0.1, 0.3, 1.0, 3.0)


def tune_graphcut_option(surfaces: dict, name: str, values, reference: Optional[dict] = None, **fixed) -> None:
    """graphcut with every other option at its default (and ``fixed``), each value of option ``name``
    scored like a grid setting; ``reference``, options scored first for comparison."""
    def score(**options) -> tuple[float, dict]:
        errors = {size: [scene.mean_error(shadecut.reconstruct(scene.image, scene.light, scene.mask, albedo=scene.albedo,
                                                               **options).normals)
                         for scene in scenes.values()]
                  for size, scenes in surfaces.items()}
        return float(np.mean(list(errors.values()))), errors

    def line(error: float, errors: dict) -> str:
        return f"mean error {error:.3f} deg (" + "; ".join(
            f"{size} px {np.mean(e):.2f} [{', '.join(f'{v:.2f}' for v in e)}]" for size, e in errors.items()) + ")"

    if reference is not None:
        print(f"  {reference}: {line(*score(**reference))}")
    scored = []
    for value in values:
        error, errors = score(**fixed, **{name: value})
        print(f"  {name} {value}: {line(error, errors)}", flush=True)
        scored.append((error, value))
    print(f"  chosen {name}: {min(scored)[1]}")


BAND_RADII = (0, 1, 2, 3, 4, 6, 8)
BAND_RADIUS_SLACK = 0.1  # degrees


def tune_band_radius(surfaces: dict) -> None:
    def score(radius: int) -> tuple[float, float, dict]:
        started = time.monotonic()
        errors = {size: [scene.mean_error(shadecut.reconstruct(scene.image, scene.light, scene.mask, albedo=scene.albedo,
                                                               coarse_to_fine_radius=radius).normals)
                         for scene in scenes.values()]
                  for size, scenes in surfaces.items()}
        return float(np.mean(list(errors.values()))), time.monotonic() - started, errors

    reference, reference_seconds, _ = score(-1)
    print(f"band at every pixel (radius -1): mean error {reference:.3f} deg, {reference_seconds:.1f} s")
    chosen = None
    for radius in BAND_RADII:
        error, seconds, errors = score(radius)
        per_size = "; ".join(f"{size} px {np.mean(e):.2f}" for size, e in errors.items())
        print(f"  radius {radius}: mean error {error:.3f} deg ({per_size}), {seconds:.1f} s")
        if chosen is None and error <= reference + BAND_RADIUS_SLACK:
            chosen = radius
    print(f"  chosen coarse_to_fine_radius: {chosen if chosen is not None else -1}")


def steep_light(light, slant_degrees: float = 60.0) -> np.ndarray:
    """A light of this slant from the side opposite ``light``'s tilt: the albedo's training covers
    grazing lights as well as the surfaces' own."""
    tilt = np.arctan2(light[1], light[0]) + np.pi
    slant = np.radians(slant_degrees)
    return np.array([np.sin(slant) * np.cos(tilt), np.sin(slant) * np.sin(tilt), np.cos(slant)])


def with_highlight(scene: synthetic.Scene, light, albedo: float, strength: float, shininess: float) -> np.ndarray:
    """The scene under ``light`` at this albedo plus a specular lobe around the half vector, clipped at 1."""
    light = np.asarray(light, float) / np.linalg.norm(light)
    half = (light + (0.0, 0.0, 1.0)) / np.linalg.norm(light + (0.0, 0.0, 1.0))
    facing = np.clip(scene.normals @ light, 0.0, None)
    lobe = strength * np.clip(scene.normals @ half, 0.0, None) ** shininess * (facing > 0)
    return np.clip(np.where(scene.mask, albedo * facing + lobe, 0.0), 0.0, 1.0).astype(np.float32)


def tune_albedo(surfaces: dict) -> None:
    renders = [(with_highlight(scene, light, albedo, strength, shininess), scene, light, albedo)
               for scenes in surfaces.values() for scene in scenes.values()
               for light in (scene.light, steep_light(scene.light))
               for albedo in TRAINING_ALBEDOS for strength, shininess in TRAINING_HIGHLIGHTS]
    images = [(image, scene, albedo) for image, scene, _, albedo in renders]
    scored = sorted(
        (float(np.mean([abs(shadecut.estimate_albedo(image, scene.mask, "top_fit", (*window, 0.0)) / albedo - 1.0)
                        for image, scene, albedo in images])), window)
        for window in ALBEDO_WINDOWS)
    brightest = np.mean([abs(shadecut.estimate_albedo(image, scene.mask, "brightest") / albedo - 1.0)
                         for image, scene, albedo in images])
    print(f"albedo: mean relative error of top_fit's five best windows over {len(images)} training images "
          f"(brightest: {brightest:.4f})")
    for score, window in scored[:5]:
        print(f"  {score:.4f}  from {window[0]} to {window[1]}")
    print(f"  chosen window: {scored[0][1]}")
    window = scored[0][1]
    by_agreement = sorted(
        (float(np.mean([abs(shadecut.estimate_albedo(image, scene.mask, "top_fit", (*window, agreement)) / albedo - 1.0)
                        for image, scene, albedo in images])), agreement)
        for agreement in ALBEDO_AGREEMENTS)
    for score, agreement in by_agreement:
        print(f"  agreement {agreement}: {score:.4f}")
    window = (*window, by_agreement[0][1])
    print(f"  chosen agreement: {window[2]}")
    by_threshold = []
    for threshold in HIGHLIGHT_THRESHOLDS:
        errors = [scene.mean_error(shadecut.reconstruct(
                      image, light, scene.mask,
                      albedo=shadecut.estimate_albedo(image, scene.mask, "top_fit", window),
                      highlight_threshold=threshold).normals)
                  for image, scene, light, _ in renders]
        by_threshold.append((float(np.mean(errors)), threshold))
        print(f"  highlight_threshold {threshold}: graphcut {by_threshold[-1][0]:.2f} deg", flush=True)
    print(f"  chosen highlight_threshold: {min(by_threshold)[1]}")


CONTOUR_RINGS = (0.0, 0.01, 0.02, 0.04, 0.08)
NEAR_FRONTAL_SLANT = 5.0  # degrees


def near_frontal_light(light, slant_degrees: float = NEAR_FRONTAL_SLANT) -> np.ndarray:
    """A light of this slant toward ``light``'s tilt: the light estimators' training covers the
    lights near the viewer, where an estimate decides the orientation, as well as the surfaces' own."""
    tilt = np.arctan2(light[1], light[0])
    slant = np.radians(slant_degrees)
    return np.array([np.sin(slant) * np.cos(tilt), np.sin(slant) * np.sin(tilt), np.cos(slant)])


def tune_light_method(surfaces: dict) -> None:
    """The object light estimators scored by graphcut's mean angular error with the light estimated
    (light=None, every other option at its default), over the training surfaces under their own light
    and a near-frontal one; the contour estimator once per ring (its depth inside the outline, a share
    of the object's size). The angle between the estimated and the true light is printed beside."""
    from shadecut import _core

    renders = {size: [(shadecut.render(scene.normals, light, scene.albedo, scene.mask), scene, light)
                      for scene in scenes.values() for light in (scene.light, near_frontal_light(scene.light))]
               for size, scenes in surfaces.items()}

    def off(estimated, light) -> float:
        light = np.asarray(light, float) / np.linalg.norm(light)
        return float(np.degrees(np.arccos(np.clip(np.dot(estimated, light), -1.0, 1.0))))

    def score(estimate) -> tuple[float, float, dict]:
        errors, offs = {}, []
        for size, items in renders.items():
            errors[size] = []
            for image, scene, light in items:
                estimated, albedo = estimate(image, scene)
                result = shadecut.reconstruct(image, estimated, scene.mask, albedo)
                errors[size].append(scene.mean_error(result.normals))
                offs.append(off(result.light, light))
        return float(np.mean(list(errors.values()))), float(np.median(offs)), errors

    def line(error: float, median_off: float, errors: dict) -> str:
        return (f"mean error {error:.3f} deg, light off by {median_off:.2f} deg (median) ("
                + "; ".join(f"{size} px {np.mean(e):.2f} [{', '.join(f'{v:.2f}' for v in e)}]"
                            for size, e in errors.items()) + ")")

    print(f"surfaces (each under its own light, then slant {NEAR_FRONTAL_SLANT:g} deg toward it): "
          f"{', '.join(next(iter(surfaces.values())))}")
    scored = []
    for method in ("zheng_chellappa", "lee_rosenfeld"):
        result = score(lambda image, scene, method=method: shadecut.estimate_light(image, scene.mask, method))
        print(f"  {method}: {line(*result)}", flush=True)
        scored.append((result[0], method))
    for ring in CONTOUR_RINGS:
        def contour(image, scene, ring=ring):
            light, albedo, _ = _core.estimate_contour_light(
                image, scene.mask, shadecut.estimate_albedo(image, scene.mask), ring)
            return np.asarray(light), albedo
        result = score(contour)
        print(f"  contour, ring {ring:g}: {line(*result)}", flush=True)
        scored.append((result[0], f"contour, ring {ring:g}"))
    print(f"  chosen: {min(scored)[1]}")


RETINEX_EDGES = [(chroma, intensity) for chroma in (0.01, 0.02, 0.04, 0.08) for intensity in (0.0, 0.05, 0.1, 0.2, 0.5, 1.0)]
RETINEX_SHADOWS = (0.005, 0.01, 0.02, 0.05)
RETINEX_RIMS = (0, 2, 4, 8)
RETINEX_HIGHLIGHT_GRID = list(itertools.product((0.0, 1.0, 1.2, 1.5), (0.0, 1.0, 1.05, 1.2)))  # (factor, threshold)
PASS_GAIN_SIGMAS = 2.0  # a pass is kept when its gain is this many standard errors above none
PAINT_SEED = 100  # the tests paint with seeds below 100
NOISE = (0.01, 0.003)  # sigma = a sqrt(I) + b, per channel


def painted_renders(surfaces: dict, highlight: tuple = (0.0, 1.0)) -> list:
    """(colour image, scene) for every training surface: painted with each paint and plain, noisy,
    with a Blinn-Phong lobe of (strength, shininess) ``highlight``, clipped at 1."""
    rng = np.random.default_rng(PAINT_SEED)
    renders = []
    for scenes in surfaces.values():
        for index, scene in enumerate(scenes.values()):
            # A highlight is the light's colour (white), added to the paint's diffuse shading.
            lobe = with_highlight(scene, scene.light, 0.0, *highlight)[..., None]
            for kind in (*synthetic.PAINTS, None):
                albedo = synthetic.paint(kind, scene.image.shape[0], PAINT_SEED + index) if kind else np.ones((*scene.mask.shape, 3))
                lit = albedo * scene.image[..., None] + lobe
                noisy = lit + rng.normal(size=lit.shape) * (NOISE[0] * np.sqrt(np.maximum(lit, 0)) + NOISE[1])
                renders.append((np.clip(noisy, 0.0, 1.0).astype(np.float32), scene))
    return renders


def tune_retinex(surfaces: dict) -> None:
    def errors(renders, **options) -> np.ndarray:
        return np.array([scene.mean_error(shadecut.reconstruct(image, scene.light, scene.mask, **options).normals)
                         for image, scene in renders])

    def score(renders, **options) -> float:
        return float(np.mean(errors(renders, **options)))

    renders = painted_renders(surfaces)
    chosen = {"albedo_method": "retinex", "retinex_rim": 4, "retinex_highlight": 0.0, "retinex_shadow": 0.05,
              "highlight_threshold": 0.0, "retinex_passes": 1}
    print(f"retinex: graphcut's mean error over {len(renders)} painted and plain noisy training renders")
    scored = []
    for chroma, intensity in RETINEX_EDGES:
        scored.append((score(renders, **chosen, retinex_chroma_edge=chroma, retinex_intensity_edge=intensity), chroma, intensity))
        print(f"  chroma_edge {chroma}, intensity_edge {intensity}: {scored[-1][0]:.2f} deg", flush=True)
    _, chosen["retinex_chroma_edge"], chosen["retinex_intensity_edge"] = min(scored)
    by_shadow = []
    for shadow in RETINEX_SHADOWS:
        by_shadow.append((score(renders, **{**chosen, "retinex_shadow": shadow}), shadow))
        print(f"  shadow {shadow}: {by_shadow[-1][0]:.2f} deg", flush=True)
    chosen["retinex_shadow"] = min(by_shadow)[1]
    by_rim = []
    for rim in RETINEX_RIMS:
        by_rim.append((score(renders, **{**chosen, "retinex_rim": rim}), rim))
        print(f"  rim {rim}: {by_rim[-1][0]:.2f} deg", flush=True)
    chosen["retinex_rim"] = min(by_rim)[1]
    shiny = [render for highlight in TRAINING_HIGHLIGHTS[1:] for render in painted_renders(surfaces, highlight)] + renders
    # The two highlight rules together: the fill of the shading image changes what the paint edges in a
    # highlight's glow do to the shape, so neither is chosen as if the other were off.
    by_highlight = []
    for factor, threshold in RETINEX_HIGHLIGHT_GRID:
        by_highlight.append((score(shiny, **{**chosen, "retinex_highlight": factor, "highlight_threshold": threshold}),
                             factor, threshold))
        print(f"  highlight {factor}, highlight_threshold {threshold} (with highlight renders too): "
              f"{by_highlight[-1][0]:.2f} deg", flush=True)
    retinex, chosen["retinex_highlight"], chosen["highlight_threshold"] = min(by_highlight)
    # Each pass costs about one reconstruction: one more is taken only while it helps beyond the renders'
    # own scatter, its mean gain over them above PASS_GAIN_SIGMAS standard errors of the paired gains.
    passes, kept = 1, errors(shiny, **chosen)
    while True:
        more = errors(shiny, **{**chosen, "retinex_passes": passes + 1})
        gain = kept - more
        standard_error = gain.std(ddof=1) / np.sqrt(len(gain))
        print(f"  passes {passes + 1} (with highlight renders too): {more.mean():.2f} deg, gain {gain.mean():.2f} "
              f"(standard error {standard_error:.2f})", flush=True)
        if gain.mean() <= PASS_GAIN_SIGMAS * standard_error:
            break
        passes, kept = passes + 1, more
    retinex, chosen["retinex_passes"] = float(kept.mean()), passes
    top_fit = score(shiny, albedo_method="top_fit")
    print(f"  top_fit on the same renders: {top_fit:.2f} deg; retinex {retinex:.2f} deg")
    print(f"  chosen: {chosen}; albedo_method default: {'retinex' if retinex < top_fit else 'top_fit'}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", nargs="+", choices=list(GRID), default=list(GRID))
    parser.add_argument("--sizes", nargs="+", type=int, default=[128, 256],
                        help="image sizes (pixels) at which every training surface is rendered")
    parser.add_argument("--albedo", action="store_true", help="tune only the albedo estimate (top_fit's window)")
    parser.add_argument("--band-radius", action="store_true", help="choose only graphcut's coarse_to_fine_radius")
    parser.add_argument("--fit-smoothness", action="store_true", help="tune only graphcut's fit_smoothness (fit_shading)")
    parser.add_argument("--fit-max-slant", action="store_true", help="tune only graphcut's fit_max_slant (fit_shading)")
    parser.add_argument("--viscosity-weight", action="store_true", help="tune only graphcut's viscosity_weight")
    parser.add_argument("--light-method", action="store_true",
                        help="choose only the object light estimator (and the contour estimator's ring)")
    parser.add_argument("--retinex", action="store_true", help="tune only the paint separation (albedo_method retinex)")
    parser.add_argument("--detail-size", action="store_true",
                        help="choose only the reliefs' detail_scale_factor, on training reliefs (tune_reliefs.py)")
    args = parser.parse_args()
    if args.detail_size:
        from tune_reliefs import tune_detail_size

        tune_detail_size()
        return 0
    if args.light_method:
        tune_light_method({size: training_surfaces(size) for size in args.sizes})
        return 0
    if args.retinex:
        tune_retinex({size: training_surfaces(size) for size in (args.sizes if "--sizes" in sys.argv else [128])})
        return 0
    if args.fit_smoothness:
        tune_graphcut_option({size: training_surfaces(size) for size in args.sizes}, "fit_smoothness",
                             FIT_SMOOTHNESSES, reference={"fit_shading": False}, fit_shading=True)
        return 0
    if args.fit_max_slant:
        tune_graphcut_option({size: training_surfaces(size) for size in args.sizes}, "fit_max_slant",
                             FIT_MAX_SLANTS, reference={"fit_shading": False}, fit_shading=True)
        return 0
    if args.viscosity_weight:
        tune_graphcut_option({size: training_surfaces(size) for size in args.sizes}, "viscosity_weight",
                             VISCOSITY_WEIGHTS)
        return 0
    if args.band_radius:
        sizes = args.sizes if "--sizes" in sys.argv else [256, 512]
        tune_band_radius({size: training_surfaces(size) for size in sizes})
        return 0
    surfaces = {size: training_surfaces(size) for size in args.sizes}
    if args.albedo:
        tune_albedo(surfaces)
        return 0
    for method in args.methods:
        grid = GRID[method]
        names = list(grid)
        scored = []
        settings = list(itertools.product(*grid.values()))
        started = time.monotonic()
        for done, values in enumerate(settings):
            params = dict(zip(names, values))
            if done:
                left = (time.monotonic() - started) / done * (len(settings) - done)
                print(f"\r{method}: setting {done + 1}/{len(settings)}, about {left / 60:.0f} min left ",
                      end="", file=sys.stderr, flush=True)
            errors = {
                size: [scene.mean_error(shadecut.reconstruct(scene.image, scene.light, scene.mask, albedo=scene.albedo,
                                                             method=method, **params).normals)
                       for scene in scenes.values()]
                for size, scenes in surfaces.items()
            }
            scored.append((float(np.mean(list(errors.values()))), params, errors))
        scored.sort(key=lambda item: item[0])
        print(f"\n{method}: the five best of {len(scored)} settings (mean error in degrees over every size; "
              f"then per size, the mean and per surface: {', '.join(surfaces[args.sizes[0]])})")
        for score, params, errors in scored[:5]:
            per_size = "; ".join(f"{size} px {np.mean(e):.2f} [{', '.join(f'{v:.2f}' for v in e)}]"
                                 for size, e in errors.items())
            print(f"  {score:6.2f}  {params}  {per_size}")
        print(f"  chosen for {method}: {scored[0][1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
