"""shadecut.evaluation: the metrics against independent computations, aggregation, files, failures."""

import csv
import json
from collections import deque

import matplotlib.image
import numpy as np
import pytest

import shadecut
from shadecut import dataset, evaluation, synthetic

SIZE = 48


def independent_eroded(mask, pixels=2):
    """4-neighbour erosion by array shifts, the image border counting as outside (as the metrics say)."""
    inside = mask.copy()
    for _ in range(pixels):
        padded = np.pad(inside, 1, constant_values=False)
        inside = inside & padded[:-2, 1:-1] & padded[2:, 1:-1] & padded[1:-1, :-2] & padded[1:-1, 2:]
    return inside


def independent_angles(normals, truth, mask):
    n1 = normals[mask].astype(np.float64)
    n2 = truth[mask].astype(np.float64)
    cosine = np.sum(n1 * n2, axis=1) / (np.linalg.norm(n1, axis=1) * np.linalg.norm(n2, axis=1))
    return np.degrees(np.arccos(np.clip(cosine, -1, 1)))


def tilted(normals, degrees):
    """Every normal turned by exactly ``degrees``, toward a direction perpendicular to it."""
    side = np.cross(normals, [0.0, 0.6, 0.8])  # the true normals are never parallel to (0, 0.6, 0.8) here
    length = np.linalg.norm(side, axis=2, keepdims=True)
    side = np.divide(side, length, out=np.zeros_like(side), where=length > 0)  # 0 outside the mask
    angle = np.radians(degrees)
    return (np.cos(angle) * normals + np.sin(angle) * side).astype(np.float32)


@pytest.fixture(scope="module")
def sphere():
    return synthetic.sphere((1.0, 0.0, 1.0), size=SIZE)


@pytest.fixture(scope="module")
def small_dataset(tmp_path_factory):
    folder = tmp_path_factory.mktemp("dataset")
    return evaluation.write_synthetic_dataset(folder, {
        "sphere_0": ("sphere", synthetic.sphere((0.5, 0.3, 1.0), size=SIZE)),
        "bowl_0": ("bowl", synthetic.sphere((-0.4, 0.6, 1.0), size=SIZE, bowl=True)),
    })


def test_a_constant_rotation_is_measured_exactly(sphere):
    metrics = evaluation.normal_errors(tilted(sphere.normals, 15.0), sphere.normals, sphere.mask)
    assert metrics["mean_deg"] == pytest.approx(15.0, abs=1e-3)
    assert metrics["median_deg"] == pytest.approx(15.0, abs=1e-3)
    assert metrics["under_11.25_pct"] == 0.0
    assert metrics["under_22.5_pct"] == metrics["under_30_pct"] == 100.0


def test_normal_metrics_equal_an_independent_computation_on_the_eroded_mask(sphere):
    rng = np.random.default_rng(4)
    noisy = sphere.normals + rng.normal(0, 0.3, sphere.normals.shape).astype(np.float32)
    noisy /= np.linalg.norm(noisy, axis=2, keepdims=True)
    angles = independent_angles(noisy, sphere.normals, independent_eroded(sphere.mask))
    metrics = evaluation.normal_errors(noisy, sphere.normals, sphere.mask)
    assert metrics["mean_deg"] == pytest.approx(angles.mean(), rel=1e-5)
    assert metrics["median_deg"] == pytest.approx(np.median(angles), rel=1e-5)
    for threshold in evaluation.THRESHOLDS:
        assert metrics[f"under_{threshold:g}_pct"] == pytest.approx(100 * np.mean(angles < threshold), abs=0.2)


def test_errors_on_the_two_pixel_rim_do_not_count(sphere):
    rim = sphere.mask & ~independent_eroded(sphere.mask)
    wrong = np.where(rim[..., None], -sphere.normals, sphere.normals)
    assert evaluation.normal_errors(wrong, sphere.normals, sphere.mask)["mean_deg"] == pytest.approx(0, abs=1e-3)


def test_non_finite_normals_and_empty_masks_are_errors(sphere):
    with pytest.raises(ValueError, match="not finite"):
        evaluation.normal_errors(np.full_like(sphere.normals, np.nan), sphere.normals, sphere.mask)
    tiny = np.zeros_like(sphere.mask)
    tiny[10:13, 10:13] = True
    with pytest.raises(ValueError, match="empty"):
        evaluation.normal_errors(sphere.normals, sphere.normals, tiny)


def test_depth_rmse_ignores_the_offset_and_the_scaled_one_the_scale_too(sphere):
    shifted = evaluation.depth_errors(sphere.depth + 7.0, sphere.depth, sphere.mask)
    assert shifted["depth_rmse"] == pytest.approx(0, abs=1e-4)
    assert shifted["depth_scale"] == pytest.approx(1, abs=1e-6)
    halved = evaluation.depth_errors(0.5 * sphere.depth - 3.0, sphere.depth, sphere.mask)
    inside = independent_eroded(sphere.mask)
    truth = sphere.depth[inside].astype(np.float64)
    expected = np.sqrt(np.mean((0.5 * truth - 0.5 * truth.mean() - truth + truth.mean()) ** 2))
    assert halved["depth_rmse"] == pytest.approx(expected, rel=1e-5)
    assert halved["depth_rmse_scaled"] == pytest.approx(0, abs=1e-4)
    assert halved["depth_scale"] == pytest.approx(2.0, rel=1e-5)


def test_each_part_of_the_mask_gets_its_own_offset():
    truth = np.tile(np.arange(20, dtype=np.float32), (20, 1))
    mask = np.zeros((20, 20), bool)
    mask[:, 1:9] = mask[:, 11:19] = True
    estimate = np.where(np.arange(20) < 10, truth - 5.0, truth + 40.0).astype(np.float32)
    assert evaluation.depth_errors(estimate, truth, mask)["depth_rmse"] == pytest.approx(0, abs=1e-5)


def test_mask_parts_equal_a_flood_fill():
    mask = np.random.default_rng(7).random((40, 50)) < 0.6  # many parts of every shape
    expected = np.full(mask.shape, mask.size)
    for start in zip(*np.nonzero(mask)):  # row-major: a part is first met at its smallest index
        if expected[start] < mask.size:
            continue
        label, queue = np.ravel_multi_index(start, mask.shape), deque([start])
        expected[start] = label
        while queue:
            r, c = queue.popleft()
            for rr, cc in ((r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)):
                if 0 <= rr < 40 and 0 <= cc < 50 and mask[rr, cc] and expected[rr, cc] == mask.size:
                    expected[rr, cc] = label
                    queue.append((rr, cc))
    assert np.array_equal(evaluation.mask_parts(mask), expected)


def test_light_error_is_the_angle_between_the_directions():
    assert evaluation.light_error((2, 0, 0), (0, 0, 0.5)) == pytest.approx(90)
    assert evaluation.light_error((1, 0, 1), (1, 0, 1)) == pytest.approx(0, abs=1e-6)
    assert evaluation.light_error((1, 0, 1), (0, 0, 1)) == pytest.approx(45)


def test_methods_are_checked_against_the_library():
    assert evaluation.check_methods(None) == tuple(shadecut.METHODS)
    assert evaluation.check_methods(["lee_rosenfeld", " graphcut", "lee_rosenfeld"]) == ("lee_rosenfeld", "graphcut")
    with pytest.raises(evaluation.EvaluationError, match="unknown method 'nope'.*choose among graphcut"):
        evaluation.check_methods(["graphcut", "nope"])
    with pytest.raises(evaluation.EvaluationError, match="none given"):
        evaluation.check_methods([""])


def test_bad_datasets_and_outputs_are_evaluation_errors(tmp_path):
    with pytest.raises(evaluation.EvaluationError, match="does not exist"):
        evaluation.read_manifest(tmp_path / "missing")
    with pytest.raises(evaluation.EvaluationError, match="no readable manifest"):
        evaluation.read_manifest(tmp_path)
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(evaluation.EvaluationError, match="is not a folder"):
        evaluation.read_manifest(blocker)
    for text in ("{ not json", "[1, 2]", '"text"', "null", "\xff\xfe",
                 json.dumps({"format": "other", "samples": []}),
                 json.dumps({"format": dataset.FORMAT, "samples": {"a": 1}}),
                 json.dumps({"format": dataset.FORMAT, "samples": [1, 2]})):
        (tmp_path / dataset.MANIFEST_JSON).write_text(text)
        with pytest.raises(evaluation.EvaluationError, match="malformed manifest"):
            evaluation.read_manifest(tmp_path)
    (tmp_path / dataset.MANIFEST_JSON).write_text(json.dumps({"format": dataset.FORMAT, "samples": [{"id": "a"}]}))
    with pytest.raises(evaluation.EvaluationError, match="without shape, folder"):
        evaluation.read_manifest(tmp_path)
    with pytest.raises(evaluation.EvaluationError, match="cannot write to the output folder"):
        evaluation.prepare_output(blocker / "out")


def test_evaluate_dataset_matches_an_independent_computation(small_dataset, tmp_path):
    lines = []
    run = evaluation.evaluate_dataset(small_dataset, ("lee_rosenfeld", "graphcut_two"), figures_dir=tmp_path,
                                      log=lines.append)
    assert [line.split()[0] for line in lines] == ["[1/2]", "[2/2]"]
    assert [(r["sample"], r["method"]) for r in run.records] == [
        ("sphere_0", "lee_rosenfeld"), ("sphere_0", "graphcut_two"),
        ("bowl_0", "lee_rosenfeld"), ("bowl_0", "graphcut_two")]
    assert not run.failed

    sample = dataset.load_sample(small_dataset / "bowl_0")
    result = shadecut.reconstruct(sample.image, sample.light, sample.mask, sample.albedo, method="graphcut_two")
    angles = independent_angles(result.normals, sample.normals, independent_eroded(sample.mask))
    record = run.records[3]
    assert record["mean_deg"] == pytest.approx(angles.mean(), rel=1e-6)
    assert record["median_deg"] == pytest.approx(np.median(angles), rel=1e-6)
    assert record["seconds"] > 0 and record["light_error_deg"] is None
    # The bowl: the convex assumption of the local method fails there, the graph cut does not.
    assert run.records[2]["mean_deg"] > 60 > 10 > record["mean_deg"]

    again = evaluation.evaluate_dataset(small_dataset, ("lee_rosenfeld", "graphcut_two"), log=lambda line: None)
    strip = lambda records: [{k: v for k, v in r.items() if k != "seconds"} for r in records]  # noqa: E731
    assert strip(again.records) == strip(run.records)

    picture = matplotlib.image.imread(tmp_path / "bowl_0.png")
    assert picture.shape[1] > picture.shape[0] and picture[..., :3].std() > 0.1


def test_estimated_light_is_used_and_its_error_recorded(small_dataset):
    run = evaluation.evaluate_dataset(small_dataset, ("lee_rosenfeld",), light_method="zheng_chellappa",
                                      log=lambda line: None)
    sample = dataset.load_sample(small_dataset / "sphere_0")
    light, albedo = shadecut.estimate_light(sample.image, sample.mask, "zheng_chellappa")
    expected = np.degrees(np.arccos(np.dot(light, sample.light) / np.linalg.norm(light)))
    assert run.samples[0]["light_error_deg"] == pytest.approx(expected, abs=1e-6)
    assert run.records[0]["light_error_deg"] == run.samples[0]["light_error_deg"]
    assert run.samples[0]["used_albedo"] == pytest.approx(albedo)


def test_a_method_failure_is_recorded_and_the_run_goes_on(tmp_path):
    good = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    dark = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    dark.image = np.zeros_like(dark.image)  # an all-dark image: every method refuses it
    folder = evaluation.write_synthetic_dataset(tmp_path / "data", {"dark": ("sphere", dark), "good": ("sphere", good)})
    (folder / "broken").mkdir()
    manifest = json.loads((folder / dataset.MANIFEST_JSON).read_text())
    manifest["samples"].append({"id": "broken", "shape": "sphere", "folder": "broken"})
    (folder / dataset.MANIFEST_JSON).write_text(json.dumps(manifest))

    run = evaluation.evaluate_dataset(folder, ("lee_rosenfeld",), figures_dir=tmp_path, log=lambda line: None)
    status = {r["sample"]: r["status"] for r in run.records}
    assert status == {"dark": "failed", "good": "ok", "broken": "failed"}
    assert "ValueError" in run.records[0]["error"] and "dark" in run.records[0]["error"]
    assert "cannot read the sample broken" in run.records[2]["error"]
    assert len(run.failed) == 2
    assert run.summary["methods"]["lee_rosenfeld"]["samples"] == 1
    assert (tmp_path / "dark.png").is_file()  # the strip says "failed" instead of missing


def test_summary_means_and_ranking():
    def record(sample, shape, method, mean, status="ok"):
        base = {"sample": sample, "shape": shape, "method": method, "status": status, "error": None,
                **{name: None for name in evaluation.METRICS}}
        if status == "ok":
            base.update(mean_deg=mean, seconds=1.0)
        return base

    records = [record("a", "sphere", "slow", 10), record("a", "sphere", "fast", 30), record("a", "sphere", "flaky", 1),
               record("b", "vase", "slow", 20), record("b", "vase", "fast", 10),
               record("b", "vase", "flaky", None, "failed")]
    summary = evaluation.summarize(records)
    assert summary["methods"]["slow"]["mean_deg"] == 15 and summary["methods"]["fast"]["mean_deg"] == 20
    assert summary["shapes"]["vase"]["fast"]["mean_deg"] == 10
    assert summary["ranking"] == ["slow", "fast", "flaky"]  # flaky failed once: last despite 1°
    table = evaluation.method_table(summary)
    assert "| 1 | slow | 15.00 |" in table and "| 1/2 |" in table
    assert "| sphere | 10.00 | 30.00 | 1.00 |" in evaluation.shape_table(summary)


def test_results_files(small_dataset, tmp_path):
    run = evaluation.evaluate_dataset(small_dataset, ("lee_rosenfeld",), log=lambda line: None)
    run.records[0]["depth_scale"] = float("nan")  # as a diverged method could give
    paths = evaluation.write_results(tmp_path, run, ["figures/sphere_0.png"])
    document = json.loads(paths["json"].read_text())
    assert document["records"][0]["depth_scale"] is None
    assert document["records"][1]["mean_deg"] == run.records[1]["mean_deg"]
    assert document["summary"]["ranking"] == ["lee_rosenfeld"]
    with open(paths["csv"]) as stream:
        rows = list(csv.DictReader(stream))
    assert [row["sample"] for row in rows] == ["sphere_0", "bowl_0"]
    assert float(rows[1]["mean_deg"]) == run.records[1]["mean_deg"]
    report = paths["report"].read_text()
    assert "## Ranking" in report and "| 1 | lee_rosenfeld |" in report
    assert "![sphere_0](figures/sphere_0.png)" in report
