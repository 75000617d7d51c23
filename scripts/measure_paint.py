"""Painted objects: graphcut with one albedo (top_fit) and with the paint separated (retinex) on the
painted test set of tests/python/test_paint.py and on DiLiGenT's colour photographs (calibrated and
estimated light), beside the flat plane: the figures of docs/results.md#painted-objects-retinex.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/measure_paint.py [DILIGENT_FOLDER]
(DILIGENT_FOLDER defaults to ../shared/data/diligent; objects absent there are skipped), or with
--speed: the paint steps' own seconds (stats.seconds["albedo"], every pass) beside the whole call's,
median of five calls, on the painted bump field at 512 and 1024 pixels (docs/benchmarks.md), or with --oracle
[DILIGENT_FOLDER]: graphcut on DiLiGenT's photographs divided by the best relative albedo there is,
the least-squares one of all 19 photographs under the true normals, 1 at its 90th percentile, or
with --limits: on the painted test set, the albedo map's log-correlation with the paint by where each
paint edge's shading step comes from (the image beside the edge, the surface a pass found, the true
surface), and graphcut with fit_shading given the estimated paint, the true paint and no paint.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import shadecut

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "python"))
import test_paint  # noqa: E402  (the test set and the DiLiGenT reader the tests use)

METHODS = ("top_fit", "retinex")
LUMINANCE = (0.2126, 0.7152, 0.0722)  # Rec. 709, as reconstruct() reads a colour image


def painted_set() -> None:
    errors = {method: [] for method in (*METHODS, "unpainted")}
    for image, uniform, _, scene in test_paint.painted_test_set():
        for method in METHODS:
            errors[method].append(scene.mean_error(shadecut.reconstruct(image, scene.light, scene.mask,
                                                                        albedo_method=method).normals))
        errors["unpainted"].append(scene.mean_error(shadecut.reconstruct(uniform, scene.light, scene.mask).normals))
    print("| painted test set (12 renders) | " + " | ".join(f"{np.mean(e):.2f}" for e in errors.values()) + " |")


def diligent_objects(folder: Path):
    """(name, photographs, mask, true normals, the mask eroded as every evaluation measures) of each
    DiLiGenT object present in ``folder``, read as the tests read them."""
    test_paint.DILIGENT = folder
    for name in ("ball", "cat", "reading"):
        if (folder / f"{name}PNG").is_dir():
            photos, mask, normals = test_paint.diligent_photos(name)
            yield name, photos, mask, normals, shadecut.erode_mask(mask, 2)


def diligent(folder: Path) -> None:
    for name, photos, mask, normals, inner in diligent_objects(folder):
        flat = np.zeros_like(normals)
        flat[..., 2] = 1.0
        row = []
        for light_given in (True, False):
            for method in METHODS:
                row.append(np.mean([shadecut.angular_error(
                    shadecut.reconstruct(rgb, light if light_given else None, mask, albedo_method=method).normals,
                    normals, inner) for rgb, light in photos]))
        print(f"| {name} | " + " | ".join(f"{v:.2f}" for v in row) + f" | {shadecut.angular_error(flat, normals, inner):.2f} |",
              flush=True)


def oracle(folder: Path) -> None:
    for name, photos, mask, normals, inner in diligent_objects(folder):
        grey = np.stack([rgb @ np.array(LUMINANCE) for rgb, _ in photos], axis=-1)
        lights = np.array([light for _, light in photos])
        shading = np.maximum(np.einsum("hwc,kc->hwk", normals, lights), 0.0)
        albedo = (grey * shading).sum(axis=-1) / np.maximum((shading ** 2).sum(axis=-1), 1e-9)
        relative = np.maximum(albedo / np.percentile(albedo[mask], 90), 0.05)
        errors = [shadecut.angular_error(shadecut.reconstruct(np.where(mask, grey[..., k] / relative, 0).astype(np.float32),
                                                              light, mask).normals, normals, inner)
                  for k, (_, light) in enumerate(photos)]
        print(f"| {name} | {np.mean(errors):.2f} |", flush=True)


def limits() -> None:
    cases = test_paint.painted_test_set()
    steps = {
        "the image's steps beside it (the first pass)":
            lambda image, scene: shadecut.estimate_reflectance(image, scene.mask),
        "the surface the first pass found (reconstruct's default passes)":
            lambda image, scene: shadecut.reconstruct(image, scene.light, scene.mask, albedo_method="retinex").albedo_map,
        "the same with fit_shading":
            lambda image, scene: shadecut.reconstruct(image, scene.light, scene.mask, albedo_method="retinex",
                                                      fit_shading=True).albedo_map,
        "the true surface": lambda image, scene: shadecut.estimate_reflectance(
            image, scene.mask, shadecut.render(scene.normals, scene.light, 1.0, scene.mask)),
    }
    print("| a paint edge's shading step read from | log-correlation, mean | min |\n|---|---|---|")
    for name, albedo_map in steps.items():
        correlations = [test_paint.log_correlation(albedo_map(image, scene), paint, scene) for image, _, paint, scene in cases]
        print(f"| {name} | {np.mean(correlations):.3f} | {np.min(correlations):.3f} |", flush=True)
    errors = {"the paint estimated (retinex)": [], "the true paint divided out": [], "unpainted": []}
    for image, uniform, paint, scene in cases:
        fit = {"fit_shading": True}
        errors["the paint estimated (retinex)"].append(scene.mean_error(
            shadecut.reconstruct(image, scene.light, scene.mask, albedo_method="retinex", **fit).normals))
        shading = (image @ np.array(LUMINANCE)) / (paint @ np.array(LUMINANCE))
        errors["the true paint divided out"].append(scene.mean_error(
            shadecut.reconstruct(shading.astype(np.float32), scene.light, scene.mask, **fit).normals))
        errors["unpainted"].append(scene.mean_error(shadecut.reconstruct(uniform, scene.light, scene.mask, **fit).normals))
    print("\n| graphcut with fit_shading | " + " | ".join(errors) + " |\n|---|---|---|---|")
    print("| painted test set, mean error (degrees) | " + " | ".join(f"{np.mean(e):.2f}" for e in errors.values()) + " |")


def speed() -> None:
    from shadecut import synthetic

    calls = {"retinex": {"albedo_method": "retinex"}, "top_fit": {"albedo_method": "top_fit"},
             "retinex without the highlight fill": {"albedo_method": "retinex", "highlight_threshold": 0.0},
             "retinex, one pass": {"albedo_method": "retinex", "retinex_passes": 1}}
    print("| size | retinex steps, s | " + " | ".join(f"whole call with {name}, s" for name in calls) + " |\n|"
          + "---|" * (len(calls) + 2))
    for size in (512, 1024):
        scene = synthetic.bumps((0.7, 0.2, 1.0), size)
        colour, _ = synthetic.painted(scene, "patches", 1)
        runs = {name: [] for name in calls}
        for _ in range(5):  # alternating, so that a busier moment costs every call alike
            for name, options in calls.items():
                runs[name].append(shadecut.reconstruct(colour, scene.light, scene.mask, **options).stats.seconds)
        step = np.median([seconds["albedo"] for seconds in runs["retinex"]])
        print(f"| {size} | {step:.3f} | " + " | ".join(f"{np.median([s['total'] for s in runs[name]]):.2f}" for name in calls)
              + " |", flush=True)


def main() -> int:
    if "--speed" in sys.argv:
        speed()
        return 0
    if "--limits" in sys.argv:
        limits()
        return 0
    folders = [Path(arg) for arg in sys.argv[1:] if not arg.startswith("--")]
    folder = folders[0] if folders else REPO.parent / "shared" / "data" / "diligent"
    if "--oracle" in sys.argv:
        print("| DiLiGenT | calibrated, the photographs' own albedo |\n|---|---|")
        oracle(folder)
        return 0
    print("| | one albedo | retinex | unpainted |\n|---|---|---|---|")
    painted_set()
    print("\n| DiLiGenT | calibrated, one albedo | calibrated, retinex | estimated, one albedo | estimated, retinex "
          "| flat plane |\n|---|---|---|---|---|---|")
    diligent(folder)
    return 0


if __name__ == "__main__":
    sys.exit(main())
