"""blender_scripts/eval.py --diligent: real photographs in DiLiGenT's layout, run as a user runs it.

The object folder is the tiny fixture of tests/python/test_diligent.py (a Lambertian sphere written
in the benchmark's layout), so no test here needs the benchmark itself.
"""

import csv
import importlib.util
import json

import pytest

from test_eval import assert_clean_failure, run_eval

METHODS = ("graphcut", "lee_rosenfeld")


def fixture_module(repo):
    path = repo / "tests" / "python" / "test_diligent.py"
    spec = importlib.util.spec_from_file_location("shadecut_test_diligent", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_fixture(repo, folder, **size):
    return fixture_module(repo).write_fixture(folder, **size)


@pytest.fixture(scope="module")
def photographs(repo, tmp_path_factory):
    """A folder of one object folder, ``spherePNG``, 40 x 32 pixels, four photographs (enough for the
    lights to be estimated from them at once)."""
    folder = tmp_path_factory.mktemp("diligent")
    module = fixture_module(repo)
    module.write_fixture(folder / "spherePNG", width=40, height=32, present=module.NAMES)
    return folder


@pytest.fixture(scope="module")
def real_run(repo, photographs, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    completed = run_eval(repo, "--diligent", photographs, "--methods", ",".join(METHODS), "--out", out)
    return completed, out


def test_the_real_photograph_section_is_written(real_run):
    completed, out = real_run
    assert completed.returncode == 0, completed.stdout + completed.stderr
    assert "importing the DiLiGenT object" in completed.stdout
    assert "[1/4] sphere_001 (sphere), calibrated light: flat plane" in completed.stdout
    assert "Real photographs, sphere:" in completed.stdout
    report = (out / "report.md").read_text()
    assert "## Real photographs" in report and "### sphere (4 photographs)" in report
    assert "| any | **flat plane** |" in report
    for light in ("calibrated", "estimated"):
        for method in METHODS:
            assert f"| {light} | {method} |" in report
        assert (out / "figures" / f"diligent_sphere_{light}.png").is_file()
        assert f"![diligent_sphere_{light}](figures/diligent_sphere_{light}.png)" in report
    assert "## Ranking" not in report and "paper's experiment" not in report  # --diligent alone
    assert (out / "diligent" / "sphere" / "sphere_004" / "meta.json").is_file()

    results = json.loads((out / "results.json").read_text())
    part = results["real"]["objects"]["sphere"]
    assert len(part["records"]) == 4 * (1 + 2 * len(METHODS))
    flat = part["summary"]["flat"]
    assert flat["samples"] == 4 and flat["mean_deg"] > 10
    # On a clean Lambertian sphere with its calibrated light, the graph cut beats the flat plane.
    assert part["summary"]["calibrated"]["methods"]["graphcut"]["mean_deg"] < flat["mean_deg"]
    # Several photographs at once: only "all" (four photographs) is present in the fixture; with the
    # calibrated lights, and with the lights estimated from the four.
    assert [(r["set"], r["count"], r["method"], r["light"]) for r in part["photographs"]] == [
        ("one", 1, "ShadeCut", "calibrated"), ("all", 4, "ShadeCut", "calibrated"),
        ("all", 4, "plain least squares", "calibrated"), ("all", 4, "ShadeCut, lights estimated", "estimated")]
    estimated = part["photographs"][-1]
    assert estimated["status"] == "ok" and estimated["light_error_deg"] is not None
    assert "several photographs of sphere: the set four skipped (085, 007, 037, 049 not present)" in completed.stdout
    assert "Several photographs, sphere, calibrated and estimated lights:" in completed.stdout
    assert "| one (each alone, graphcut, mean) |" in report
    row = next(line for line in report.splitlines() if line.startswith("| all 4 |"))
    assert f"| {estimated['mean_deg']:.2f} | {estimated['light_error_deg']:.2f} |" in row
    with open(out / "results.csv") as stream:
        rows = list(csv.DictReader(stream))
    single = [row for row in rows if not row["photographs"]]
    assert {(row["method"], row["light"]) for row in single} == {
        ("flat plane", ""), *((m, light) for m in METHODS for light in ("calibrated", "estimated"))}
    sets = [(row["sample"], row["photographs"], row["method"], row["light"]) for row in rows if row["photographs"]]
    assert sets == [("sphere_one", "1", "ShadeCut", "calibrated"), ("sphere_all", "4", "ShadeCut", "calibrated"),
                    ("sphere_all", "4", "plain least squares", "calibrated"),
                    ("sphere_all", "4", "ShadeCut, lights estimated", "estimated")]
    by_set = {(record["set"], record["method"]): record for record in part["photographs"]}
    for row in rows:
        if row["photographs"]:
            record = by_set[row["sample"].split("_")[-1], row["method"]]
            assert float(row["mean_deg"]) == pytest.approx(record["mean_deg"])
            for key in ("light_error_deg", "light_uncertainty_deg"):
                assert (float(row[key]) if row[key] else None) == pytest.approx(record.get(key))


def test_the_import_is_reused(repo, photographs, real_run):
    _, out = real_run
    again = run_eval(repo, "--diligent", photographs / "spherePNG", "--methods", "lee_rosenfeld", "--out", out)
    assert again.returncode == 0, again.stdout + again.stderr
    assert "reusing the imported DiLiGenT object" in again.stdout and "importing" not in again.stdout


def test_a_bad_diligent_folder_is_refused(repo, tmp_path):
    assert_clean_failure(run_eval(repo, "--diligent", tmp_path / "nowhere", "--out", tmp_path / "out"),
                         "does not exist")
    (tmp_path / "empty").mkdir()
    assert_clean_failure(run_eval(repo, "--diligent", tmp_path / "empty", "--out", tmp_path / "out"),
                         "neither a DiLiGenT object folder")
    write_fixture(repo, tmp_path / "brokenPNG")
    (tmp_path / "brokenPNG" / "Normal_gt.mat").unlink()
    assert_clean_failure(run_eval(repo, "--diligent", tmp_path, "--out", tmp_path / "out"), "lacks Normal_gt.mat")
    assert not (tmp_path / "out" / "results.json").exists()
    (tmp_path / "brokenPNG" / "Normal_gt.mat").write_bytes(b"MATLAB 5.0 MAT-file, cut short")
    assert_clean_failure(run_eval(repo, "--diligent", tmp_path / "brokenPNG", "--out", tmp_path / "out"),
                         "Normal_gt.mat: it is not a readable MATLAB file")
    assert not (tmp_path / "out").exists()  # refused after the output folder was made: it goes again


def test_synthetic_options_need_a_dataset_beside_diligent(repo, photographs, tmp_path):
    assert_clean_failure(run_eval(repo, "--diligent", photographs, "--estimate-light", "--out", tmp_path),
                         "--estimate-light apply to a synthetic dataset")
