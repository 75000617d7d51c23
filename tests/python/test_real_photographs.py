"""ShadeCut on real photographs: the DiLiGenT objects in ../shared (skipped where they are absent).

Nothing was tuned on these images: they measure. The floor every method must beat is a flat plane
facing the viewer.
"""

from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import dataset, diligent, evaluation

DILIGENT = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "diligent"


def imported(name: str, folder: Path) -> list:
    source = DILIGENT / name
    if not source.is_dir():
        pytest.skip(f"DiLiGenT is not at {DILIGENT} (expects {name}/ there in the benchmark's layout)")
    entries = dataset.import_diligent(source, folder)
    return [dataset.load_sample(folder / entry["folder"]) for entry in entries]


def errors_of(samples, **options) -> tuple[np.ndarray, float]:
    """graphcut's mean angular error per image (default settings, the albedo estimated), and the flat
    plane's, on the mask eroded by 2 pixels as every evaluation measures."""
    flat = np.zeros_like(samples[0].normals)
    flat[..., 2] = 1.0
    inner = shadecut.erode_mask(samples[0].mask, 2)
    errors = [shadecut.angular_error(shadecut.reconstruct(s.image, s.light, s.mask, **options).normals, s.normals, inner)
              for s in samples]
    return np.array(errors), shadecut.angular_error(flat, samples[0].normals, inner)


@pytest.fixture(scope="module")
def ball(tmp_path_factory):
    return imported("ballPNG", tmp_path_factory.mktemp("ball"))


def test_the_ball_beats_the_flat_plane_by_far_with_the_calibrated_light(ball):
    errors, flat = errors_of(ball)
    print(f"ball, graphcut, calibrated light: {', '.join(f'{e:.2f}' for e in errors)} deg "
          f"(mean {errors.mean():.2f}); flat plane {flat:.2f}")
    assert errors.mean() < 0.25 * flat
    # The brightest pixels are the highlight, 6 to 8 times the diffuse albedo: taken as the albedo
    # they wreck every image, which is what the robust estimate exists to prevent.
    brightest, _ = errors_of(ball[:3], albedo_method="brightest")
    assert brightest.min() > 2 * errors.max()


def test_every_ball_image_within_ten_degrees(ball):
    errors, _ = errors_of(ball)
    assert errors.max() <= 10.0


def test_the_cat_beats_the_flat_plane_with_the_calibrated_light(tmp_path):
    errors, flat = errors_of(imported("catPNG", tmp_path))
    print(f"cat, graphcut, calibrated light: mean {errors.mean():.2f} deg; flat plane {flat:.2f}")
    assert errors.mean() < flat


def oblique(samples, slant_degrees: float = 15.0) -> list:
    return [s for s in samples if np.degrees(np.arccos(s.light[2])) >= slant_degrees]


def test_the_ball_light_is_estimated_within_six_degrees(ball):
    # The estimator reads the image clipped at the albedo: the highlight would otherwise pull it.
    off = [np.degrees(np.arccos(np.clip(shadecut.reconstruct(s.image, None, s.mask).light @ s.light, -1, 1)))
           for s in oblique(ball)]
    print(f"ball, estimated light, degrees off the calibrated one: {', '.join(f'{o:.1f}' for o in off)}")
    assert max(off) <= 6.0


def test_the_ball_with_the_estimated_light_nearly_as_good_as_calibrated(ball):
    for s in oblique(ball):
        inner = shadecut.erode_mask(s.mask, 2)
        calibrated = shadecut.angular_error(shadecut.reconstruct(s.image, s.light, s.mask).normals, s.normals, inner)
        estimated = shadecut.angular_error(shadecut.reconstruct(s.image, None, s.mask).normals, s.normals, inner)
        assert estimated <= 1.3 * calibrated + 2.0, s.light


# Issue 27: right side out on real photographs. Every photograph here is used at its full
# resolution (612 x 512): the two near-frontal ones take about a second each.

def near_frontal(name: str, folder: Path, slant_degrees: float = 10.0) -> list:
    """The object's photographs whose calibrated light is within ``slant_degrees`` of the viewer."""
    source = DILIGENT / name
    if not source.is_dir():
        pytest.skip(f"DiLiGenT is not at {DILIGENT} (expects {name}/ there in the benchmark's layout)")
    layout = diligent.read_layout(source)
    chosen = [image for image, light in zip(layout["names"], layout["lights"])
              if image in layout["present"] and np.degrees(np.arccos(light[2] / np.linalg.norm(light))) <= slant_degrees]
    entries = dataset.import_diligent(source, folder, images=chosen)
    return [dataset.load_sample(folder / entry["folder"]) for entry in entries]


@pytest.mark.parametrize("given", [True, False], ids=["calibrated light", "light estimated"])
@pytest.mark.parametrize("name", ["ballPNG", "catPNG"])
def test_near_frontal_photographs_come_back_right_side_out(name, given, tmp_path):
    samples = near_frontal(name, tmp_path)
    assert samples  # 052, slant 4.4 degrees
    flat = np.zeros_like(samples[0].normals)
    flat[..., 2] = 1.0
    inner = shadecut.erode_mask(samples[0].mask, 2)
    for s in samples:
        result = shadecut.reconstruct(s.image, s.light if given else None, s.mask)
        error = shadecut.angular_error(result.normals, s.normals, inner)
        flipped = shadecut.angular_error(result.normals * np.array([-1, -1, 1], np.float32), s.normals, inner)
        plane = shadecut.angular_error(flat, s.normals, inner)
        print(f"{name} {s.id}: {error:.2f} deg (inverted {flipped:.2f}, flat plane {plane:.2f}), "
              f"light {np.round(result.light, 3)}, ambiguous {result.stats.orientation_ambiguous}")
        assert error < flipped and error < plane


def light_errors(name: str, folder: Path, method=None) -> tuple[np.ndarray, np.ndarray]:
    """Degrees between the estimated and the calibrated light over the object's photographs, and the
    calibrated light's slant (degrees) of each."""
    samples = imported(name, folder)
    off = [np.degrees(np.arccos(np.clip(shadecut.estimate_light(s.image, s.mask, method)[0] @ s.light, -1, 1)))
           for s in samples]
    return np.array(off), np.array([np.degrees(np.arccos(s.light[2])) for s in samples])


CAT_LIGHT = ("Measured over the 19 photographs: the cat's light is off by a median of 14.2 deg with "
             "zheng_chellappa (the default) and 15.1 with contour; the issue asks 6, which even the cat's "
             "true normals do not reach (12.3 median: the test after this one)")
READING_LIGHT = ("Measured over the 19 photographs: the reading figure's light is off by a median of 40.4 deg "
                 "with zheng_chellappa (the default) and 19.4 with contour; its albedo varies more than the "
                 "cat's; the issue asks 12")


@pytest.mark.parametrize("name, bound", [
    pytest.param("ballPNG", 6.0),  # the ball's median is within the bound for the cat already
    pytest.param("catPNG", 6.0, marks=pytest.mark.xfail(strict=True, raises=AssertionError, reason=CAT_LIGHT)),
    pytest.param("readingPNG", 12.0, marks=pytest.mark.xfail(strict=True, raises=AssertionError, reason=READING_LIGHT)),
])
def test_the_light_median(name, bound, tmp_path):
    errors = {method: light_errors(name, tmp_path / method, method) for method in ("zheng_chellappa", "contour")}
    print(f"{name} light off, median (largest at slant >= 15 deg): " + ", ".join(
        f"{m} {np.median(e):.1f} ({e[slant >= 15].max():.1f})" for m, (e, slant) in errors.items()))
    assert np.median(errors["zheng_chellappa"][0]) <= bound


def test_even_the_true_shape_does_not_read_the_cats_light_within_six_degrees(tmp_path):
    """Why the cat's bound above is out of reach for an estimator of one light and one albedo: given
    the cat's true normals, the light that fits each photograph best (least squares over the pixels
    brighter than 5% of the 90th percentile, the true light not used) is still 8.6-13.5 deg off,
    12.3 median; the same fit reads the ball's light to 1.6 deg at most and the reading figure's to a
    9.4 median. The cat's glaze, its grey paint and its shadows are not one Lambertian albedo."""
    def true_shape_light_off(sample) -> float:
        inner = shadecut.erode_mask(sample.mask, 2)
        lit = inner & (sample.image > 0.05 * np.percentile(sample.image[sample.mask], 90))
        fitted = np.linalg.lstsq(sample.normals[lit], sample.image[lit], rcond=None)[0]
        return float(np.degrees(np.arccos(np.clip(fitted @ sample.light / np.linalg.norm(fitted), -1, 1))))

    off = {name: np.array([true_shape_light_off(s) for s in imported(name, tmp_path / name)])
           for name in ("ballPNG", "catPNG", "readingPNG")}
    print("light fitted to the true normals, degrees off, median (largest): " + ", ".join(
        f"{name} {np.median(e):.1f} ({e.max():.1f})" for name, e in off.items()))
    assert off["ballPNG"].max() <= 2.0  # the fit itself reads a Lambertian photograph's light
    assert off["catPNG"].min() > 6.0


# Issue 45: several photographs at once, as blender_scripts/eval.py --diligent measures them. The
# dataset holds the four photographs lit from around, so the set "one" is the mean of graphcut on
# each of the same four alone (docs/results.md, "Several photographs").

@pytest.mark.parametrize("name", ["ballPNG", "catPNG", "readingPNG"])
def test_four_photographs_beat_plain_least_squares_and_one_photograph(name, tmp_path):
    source = DILIGENT / name
    if not source.is_dir():
        pytest.skip(f"DiLiGenT is not at {DILIGENT} (expects {name}/ there in the benchmark's layout)")
    folder = tmp_path / "dataset"
    dataset.import_diligent(source, folder, images=evaluation.PHOTOGRAPH_SETS["four"])
    real = evaluation.evaluate_real({name[:-3]: folder}, ("graphcut",), log=lambda line: None)
    records = real["objects"][name[:-3]]["photographs"]
    # The lights are estimated from four photographs or more: the set "two" has no such record.
    estimated = evaluation.ESTIMATED
    assert [(r["set"], r["method"]) for r in records] == [("one", "ShadeCut")] + [
        (s, m) for s in ("two", "four", "eight", "all") for m in ("ShadeCut", "plain least squares")
        + ((estimated,) if s != "two" else ())]
    assert all(r["status"] == "ok" for r in records)
    error = {(r["set"], r["method"]): r["mean_deg"] for r in records}
    by_set = {(r["set"], r["method"]): r for r in records}
    # The estimated record of the four: scored against the measured normals, its light error the
    # median angle between the lights the estimator found and the calibrated ones.
    loaded = diligent.load_object(source, images=evaluation.PHOTOGRAPH_SETS["four"])
    result = shadecut.reconstruct(loaded.photos, None, loaded.mask)
    four = by_set["four", estimated]
    assert four["light"] == "estimated" and four["images"] == loaded.names
    assert four["mean_deg"] == pytest.approx(
        evaluation.normal_errors(result.normals, loaded.normals, loaded.mask)["mean_deg"])
    unit = loaded.lights / np.linalg.norm(loaded.lights, axis=1, keepdims=True)
    angles = np.degrees(np.arccos(np.clip(np.sum(result.lights * unit, axis=1), -1, 1)))
    assert four["light_error_deg"] == pytest.approx(np.median(angles), abs=1e-4)
    assert four["light_uncertainty_deg"] == pytest.approx(result.stats.light_uncertainty)
    print(f"{name}, four photographs, lights estimated: {four['mean_deg']:.2f}, light error (median) "
          f"{four['light_error_deg']:.2f}, uncertainty {four['light_uncertainty_deg']:.2f}")
    print(f"{name}, four photographs: ShadeCut {error['four', 'ShadeCut']:.2f}, plain least squares "
          f"{error['four', 'plain least squares']:.2f}, one photograph (mean of the four) "
          f"{error['one', 'ShadeCut']:.2f}")
    assert error["four", "ShadeCut"] < error["four", "plain least squares"]
    assert error["four", "ShadeCut"] < error["one", "ShadeCut"]
    assert [r["count"] for r in records if r["set"] == "all"] == [19, 19, 19]

    run = evaluation.Evaluation({"dataset": None, "methods": ["graphcut"], "light_method": None, "options": {},
                                 "erode_pixels": evaluation.ERODE_PIXELS}, [], [])
    run.real = real
    report = Path(evaluation.write_results(tmp_path, run)["report"]).read_text()
    row = next(line for line in report.splitlines() if line.startswith("| four (085, 007, 037, 049) |"))
    assert (f"| {error['four', 'ShadeCut']:.2f} | {error['four', 'plain least squares']:.2f} | "
            f"{four['mean_deg']:.2f} | {four['light_error_deg']:.2f} |") in row
    two = next(line for line in report.splitlines() if line.startswith("| two (079, 031) |"))
    assert "| — (fewer than 4) | — |" in two
    assert "ShadeCut with the lights estimated from the photographs alone" in report
    assert "| one (each alone, graphcut, mean) |" in report and "| all 19 |" in report
