"""blender_scripts/eval.py: the headless evaluation command, run as a user runs it.

Each run is a separate `blender -b` process, so the exit code and the console output are the ones a
user sees. The small datasets are the core's own renders (shadecut.evaluation.write_synthetic_dataset),
so no test here waits for Cycles to render a dataset; the generated-dataset path has its own test.
"""

import importlib.util
import json
import os
import subprocess

import bpy
import matplotlib.image
import numpy as np
import pytest

import shadecut
from shadecut import dataset, evaluation, synthetic

SIZE = 64
METHODS = ("graphcut", "lee_rosenfeld")


def run_eval(repo, *args, env=None):
    command = [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
               "-P", str(repo / "blender_scripts" / "eval.py"), "--", *map(str, args)]
    return subprocess.run(command, capture_output=True, text=True, timeout=600, env=env)


def assert_clean_failure(completed, message):
    output = completed.stdout + completed.stderr
    assert completed.returncode == 2, output
    assert message in completed.stderr, output
    assert "Traceback" not in output


@pytest.fixture(scope="module")
def two_shapes(tmp_path_factory):
    """Two shapes, one light each, 64 x 64: the CI dataset of issue 6."""
    return evaluation.write_synthetic_dataset(tmp_path_factory.mktemp("dataset"), {
        "sphere_0": ("sphere", synthetic.sphere((0.5, 0.3, 1.0), size=SIZE)),
        "bumps_0": ("bumps", synthetic.bumps((-0.4, 0.6, 1.0), size=SIZE)),
    })


@pytest.fixture(scope="module")
def ci_run(repo, two_shapes, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    completed = run_eval(repo, "--dataset", two_shapes, "--methods", ",".join(METHODS), "--out", out)
    return completed, out


def test_small_run_writes_every_file_and_exits_0(ci_run):
    completed, out = ci_run
    assert completed.returncode == 0, completed.stdout + completed.stderr
    for name in ("results.json", "results.csv", "report.md", "figures/sphere_0.png", "figures/bumps_0.png",
                 "figures/mozart_paper.png", "figures/mozart_paper_3d.png"):
        assert (out / name).is_file(), name
    assert "[1/2] sphere_0 (sphere): graphcut" in completed.stdout
    assert "[2/2] bumps_0 (bumps): graphcut" in completed.stdout
    assert "| rank | method | mean °" in completed.stdout  # the summary table at the end
    assert str(out) in completed.stdout
    report = (out / "report.md").read_text()
    assert "## Ranking" in report and "The paper's experiment" in report
    assert "![mozart_paper_3d](figures/mozart_paper_3d.png)" in report


def test_results_equal_an_independent_angular_error(ci_run, two_shapes):
    completed, out = ci_run
    results = json.loads((out / "results.json").read_text())
    assert [(r["sample"], r["method"]) for r in results["records"]] == [
        (s, m) for s in ("sphere_0", "bumps_0") for m in METHODS]

    sample = dataset.load_sample(two_shapes / "bumps_0")
    result = shadecut.reconstruct(sample.image, sample.light, sample.mask, sample.albedo, method="graphcut")
    # The whole image is the mask here; eroding by 2 pixels keeps all but a 2-pixel frame.
    assert sample.mask.all()
    inside = np.zeros_like(sample.mask)
    inside[2:-2, 2:-2] = True
    cosine = np.sum(result.normals[inside].astype(float) * sample.normals[inside], axis=1)
    angles = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
    record = results["records"][2]
    assert record["mean_deg"] == pytest.approx(angles.mean(), rel=1e-5)
    assert record["median_deg"] == pytest.approx(np.median(angles), rel=1e-5)
    assert record["under_30_pct"] == pytest.approx(100 * np.mean(angles < 30), abs=0.05)
    summary = results["summary"]["methods"]["graphcut"]
    assert summary["mean_deg"] == pytest.approx((results["records"][0]["mean_deg"] + record["mean_deg"]) / 2)
    paper = results["paper"]["records"]
    assert [r["method"] for r in paper] == list(METHODS) and paper[0]["mean_deg"] < paper[1]["mean_deg"]


def test_the_paper_figure_shows_every_surface(ci_run):
    _, out = ci_run
    for name in ("truth", *METHODS):
        render = matplotlib.image.imread(out / "figures" / "mozart_surfaces" / f"{name}.png")
        covered = render[..., 3] > 0.5
        assert 0.05 < covered.mean() < 0.95, name  # a surface in the frame, not empty, not all of it
        assert render[covered][:, 0].std() > 0.02, name  # shaded, not one flat grey


def test_an_unknown_method_is_refused(repo, two_shapes, tmp_path):
    completed = run_eval(repo, "--dataset", two_shapes, "--methods", "graphcut,nope", "--out", tmp_path / "out")
    assert_clean_failure(completed, "unknown method 'nope'; choose among graphcut")
    assert not (tmp_path / "out" / "results.json").exists()


@pytest.mark.parametrize("make, message", [
    (lambda path: None, "does not exist"),
    (lambda path: path.write_text("{}"), "is not a folder"),
    (lambda path: path.mkdir(), "has no readable manifest"),
    (lambda path: (path.mkdir(), (path / dataset.MANIFEST_JSON).write_text("[1, 2")), "malformed manifest"),
    (lambda path: (path.mkdir(), (path / dataset.MANIFEST_JSON).write_text("[1, 2]")), "malformed manifest"),
    (lambda path: (path.mkdir(), (path / dataset.MANIFEST_JSON).write_text(
        json.dumps({"format": dataset.FORMAT, "samples": {"id": "a"}}))), "malformed manifest"),
])
def test_a_missing_or_malformed_dataset_is_refused(repo, tmp_path, make, message):
    make(tmp_path / "data")
    completed = run_eval(repo, "--dataset", tmp_path / "data", "--out", tmp_path / "out")
    assert_clean_failure(completed, message)
    assert "has no attribute" not in completed.stderr


def test_estimated_lights_are_measured(repo, two_shapes, tmp_path):
    completed = run_eval(repo, "--dataset", two_shapes, "--methods", "lee_rosenfeld", "--estimate-light",
                         "--no-paper", "--out", tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    assert "light and albedo estimated by lee_rosenfeld" in completed.stdout
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["settings"]["light_method"] == "lee_rosenfeld"
    sample = dataset.load_sample(two_shapes / "sphere_0")
    light, _ = shadecut.estimate_light(sample.image, sample.mask, "lee_rosenfeld")
    expected = np.degrees(np.arccos(np.clip(np.dot(light, sample.light) / np.linalg.norm(light), -1, 1)))
    assert results["records"][0]["light_error_deg"] == pytest.approx(expected, abs=1e-4)
    assert "light error °" in (tmp_path / "report.md").read_text()

    unknown = run_eval(repo, "--dataset", two_shapes, "--estimate-light", "guess", "--out", tmp_path)
    assert unknown.returncode == 2 and "invalid choice: 'guess'" in unknown.stderr
    assert "Traceback" not in unknown.stdout + unknown.stderr


def test_an_unwritable_output_folder_is_refused(repo, two_shapes, tmp_path):
    (tmp_path / "file").write_text("")
    assert_clean_failure(run_eval(repo, "--dataset", two_shapes, "--out", tmp_path / "file" / "out"),
                         "cannot write to the output folder")


def test_generated_dataset_options_need_no_dataset(repo, two_shapes, tmp_path):
    assert_clean_failure(run_eval(repo, "--dataset", two_shapes, "--size", 64, "--out", tmp_path),
                         "--size apply to the generated dataset")


def test_a_failed_method_is_recorded_and_the_exit_code_is_1(repo, tmp_path):
    dark = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    dark.image = np.zeros_like(dark.image)  # every method refuses an all-dark image
    data = evaluation.write_synthetic_dataset(tmp_path / "data", {
        "dark_0": ("sphere", dark), "fine_0": ("sphere", synthetic.sphere((1.0, 0.0, 1.0), size=32))})
    completed = run_eval(repo, "--dataset", data, "--methods", "lee_rosenfeld", "--no-paper", "--out", tmp_path / "out")
    assert completed.returncode == 1, completed.stdout + completed.stderr
    assert "[1/2] dark_0 (sphere): lee_rosenfeld FAILED (ValueError" in completed.stdout
    assert "1 evaluation(s) failed" in completed.stdout and "Traceback" not in completed.stderr
    records = json.loads((tmp_path / "out" / "results.json").read_text())["records"]
    assert [r["status"] for r in records] == ["failed", "ok"] and "dark" in records[0]["error"]


def test_the_default_dataset_is_generated_once_then_reused(repo, tmp_path):
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"))
    args = ("--shapes", "sphere,torus", "--lights", 1, "--size", 64, "--methods", "graphcut,lee_rosenfeld",
            "--no-paper", "--out", tmp_path / "out")
    first = run_eval(repo, *args, env=env)
    assert first.returncode == 0, first.stdout + first.stderr
    assert "generating the dataset" in first.stdout
    results = json.loads((tmp_path / "out" / "results.json").read_text())
    assert sorted({r["shape"] for r in results["records"]}) == ["sphere", "torus"]
    assert len(results["samples"]) == 2 and all(s["size"] == [64, 64] for s in results["samples"])

    second = run_eval(repo, *args, env=env)
    assert second.returncode == 0, second.stdout + second.stderr
    assert "reusing the generated dataset" in second.stdout
    again = json.loads((tmp_path / "out" / "results.json").read_text())
    strip = lambda records: [{k: v for k, v in r.items() if k != "seconds"} for r in records]  # noqa: E731
    assert strip(again["records"]) == strip(results["records"])  # deterministic


def test_render_surfaces_leaves_the_file_as_it_was(repo, tmp_path):
    spec = importlib.util.spec_from_file_location("shadecut_eval_script", repo / "blender_scripts" / "eval.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    kinds = ("scenes", "objects", "meshes", "cameras", "lights", "worlds")
    before = {name: len(getattr(bpy.data, name)) for name in kinds}
    scene = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    paths = script.render_surfaces({"sphere": (scene.depth, scene.mask)}, tmp_path, resolution=48)
    assert matplotlib.image.imread(paths["sphere"]).shape == (48, 48, 4)
    after = {name: len(getattr(bpy.data, name)) for name in before}
    assert after == before
