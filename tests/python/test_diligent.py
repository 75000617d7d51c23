"""Importing DiLiGenT's real photographs (shadecut.dataset.import_diligent) and evaluating them.

A tiny object folder in the benchmark's layout is written by the tests themselves; the real
benchmark (research-use data, never in the repository) is read from ../shared/data/diligent when
present.
"""

import json
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest
import scipy.io

import shadecut
from shadecut import dataset, diligent, evaluation

DILIGENT = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "diligent"
NAMES = ("001.png", "002.png", "003.png", "004.png")
PRESENT = ("001.png", "002.png", "004.png")  # 003 is listed but absent, as in the benchmark's subset
LIGHTS = np.array([[0.3, -0.2, 0.9], [-0.5, 0.1, 0.8], [0.0, 0.6, 0.8], [0.4, 0.4, 0.82]])
INTENSITIES = np.array([[1.2, 1.5, 2.0], [0.9, 1.1, 1.4], [1.0, 1.0, 1.0], [1.6, 2.1, 2.9]])


def _write_png(path: Path, pixels: np.ndarray, kind) -> None:
    out = oiio.ImageOutput.create(str(path))
    height, width, channels = pixels.shape
    assert out.open(str(path), oiio.ImageSpec(width, height, channels, kind)), oiio.geterror()
    assert out.write_image(pixels)
    out.close()


def write_fixture(folder: Path, width: int = 8, height: int = 6, seed: int = 0, present=PRESENT) -> dict:
    """An object folder in DiLiGenT's layout: a Lambertian sphere photographed under LIGHTS, 16-bit
    RGB codes (plus noise), with Normal_gt non-zero outside the mask (the importer zeroes it there);
    only the photographs ``present`` are written. Returns the codes, normals and mask written."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True)
    rows, cols = np.mgrid[0:height, 0:width]
    x = (cols - (width - 1) / 2) / (0.48 * min(width, height))
    y = ((height - 1) / 2 - rows) / (0.48 * min(width, height))
    mask = x**2 + y**2 < 1
    normals = np.dstack([x, y, np.sqrt(np.clip(1 - x**2 - y**2, 0, None))])
    normals[~mask] = (0.0, 0.0, 1.0)
    codes = {}
    for index, name in enumerate(NAMES):
        light = LIGHTS[index] / np.linalg.norm(LIGHTS[index])
        # One albedo for every photograph, each channel scaled by its light's intensity, as in the benchmark.
        shading = np.clip(normals @ light, 0, None)[..., None] * 0.7 * INTENSITIES[index] / INTENSITIES.max()
        values = np.clip(shading * 65535 + rng.integers(0, 400, (height, width, 3)), 0, 65535)
        codes[name] = values.astype(np.uint16)
        if name in present:
            _write_png(folder / name, codes[name], oiio.UINT16)
    _write_png(folder / "mask.png", np.where(mask, 255, 0).astype(np.uint8)[..., None], oiio.UINT8)
    scipy.io.savemat(folder / "Normal_gt.mat", {"Normal_gt": normals})
    (folder / "filenames.txt").write_text("\n".join(NAMES) + "\n")
    np.savetxt(folder / "light_directions.txt", LIGHTS, fmt="%.4f")
    np.savetxt(folder / "light_intensities.txt", INTENSITIES, fmt="%.4f")
    return {"codes": codes, "normals": normals, "mask": mask}


@pytest.fixture
def tiny(tmp_path):
    return tmp_path / "tinyPNG", write_fixture(tmp_path / "tinyPNG")


def test_every_present_image_becomes_a_sample(tiny, tmp_path):
    source, written = tiny
    entries = dataset.import_diligent(source, tmp_path / "out")
    assert [e["id"] for e in entries] == ["tiny_001", "tiny_002", "tiny_004"]
    assert [e["id"] for e in evaluation.read_manifest(tmp_path / "out")] == ["tiny_001", "tiny_002", "tiny_004"]
    mask = written["mask"]
    for entry in entries:
        name = f"{entry['id'][-3:]}.png"
        index = NAMES.index(name)
        sample = dataset.load_sample(tmp_path / "out" / entry["folder"])
        # The channel mean after dividing each channel by the light's intensity, from the 16-bit codes.
        expected = (written["codes"][name] / 65535.0 / INTENSITIES[index]).mean(axis=-1)
        np.testing.assert_allclose(sample.image, expected, rtol=1e-6, atol=1e-7)
        np.testing.assert_array_equal(sample.mask, mask)
        np.testing.assert_allclose(sample.light, LIGHTS[index] / np.linalg.norm(LIGHTS[index]), atol=1e-12)
        np.testing.assert_allclose(sample.normals[mask], written["normals"][mask], atol=1e-7)
        assert not sample.normals[~mask].any()
        assert sample.albedo is None and sample.depth is None
        meta = json.loads((tmp_path / "out" / entry["folder"] / "meta.json").read_text())
        assert meta["albedo"] is None and meta["shape"] == "tiny" and meta["source_image"] == name
        assert "depth.exr" not in meta["files"]
    assert json.loads((tmp_path / "out" / dataset.MANIFEST_JSON).read_text())["samples"][0]["albedo"] is None


def test_images_selects_by_number_or_name(tiny, tmp_path):
    source, _ = tiny
    entries = dataset.import_diligent(source, tmp_path / "a", images=[4, "001"])
    assert [e["id"] for e in entries] == ["tiny_004", "tiny_001"]
    assert sorted(p.name for p in (tmp_path / "a").iterdir() if p.is_dir()) == ["tiny_001", "tiny_004"]
    assert [e["id"] for e in dataset.import_diligent(source, tmp_path / "b", images="002.png")] == ["tiny_002"]
    with pytest.raises(OSError, match="003.png is listed but not present"):
        dataset.import_diligent(source, tmp_path / "c", images=[3])
    with pytest.raises(ValueError, match="no image 9"):
        dataset.import_diligent(source, tmp_path / "c", images=[9])


@pytest.mark.parametrize("missing", ["filenames.txt", "light_directions.txt", "light_intensities.txt",
                                     "mask.png", "Normal_gt.mat"])
def test_a_folder_missing_a_file_is_refused(tiny, tmp_path, missing):
    source, _ = tiny
    (source / missing).unlink()
    with pytest.raises(OSError, match=f"{source}.*lacks {missing}"):
        dataset.import_diligent(source, tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_malformed_layouts_are_refused(tiny, tmp_path):
    source, _ = tiny
    with pytest.raises(OSError, match="nowhere does not exist"):
        dataset.import_diligent(tmp_path / "nowhere", tmp_path / "out")
    (source / "light_directions.txt").write_text("0 0 1\n")
    with pytest.raises(ValueError, match="light_directions.txt must hold 4 lines of 3 numbers"):
        dataset.import_diligent(source, tmp_path / "out")
    np.savetxt(source / "light_directions.txt", LIGHTS)
    scipy.io.savemat(source / "Normal_gt.mat", {"Normal_gt": np.zeros((3, 3, 3))})
    with pytest.raises(ValueError, match="Normal_gt.mat holds Normal_gt of shape"):
        dataset.import_diligent(source, tmp_path / "out")
    for name in PRESENT:
        (source / name).unlink()
    with pytest.raises(OSError, match="holds none of the images"):
        dataset.import_diligent(source, tmp_path / "out")


def test_a_name_listed_twice_is_refused_before_anything_is_written(tiny, tmp_path):
    """Two lines of filenames.txt for one image pair it with two lights: which one is meant is unknown,
    and importing both wrote two manifest entries for one sample folder."""
    source, _ = tiny
    (source / "filenames.txt").write_text("\n".join([*NAMES, "002.png"]) + "\n")
    np.savetxt(source / "light_directions.txt", np.vstack([LIGHTS, LIGHTS[:1]]))
    np.savetxt(source / "light_intensities.txt", np.vstack([INTENSITIES, INTENSITIES[:1]]))
    with pytest.raises(ValueError, match=r"filenames.txt lists 002.png twice \(lines 2 and 5\)"):
        dataset.import_diligent(source, tmp_path / "out")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("kept_bytes", [10, 100, 300])
def test_a_damaged_normal_gt_mat_is_a_message_naming_it(tiny, tmp_path, kept_bytes):
    """A Normal_gt.mat cut short (a copy or download interrupted) made scipy raise IndexError, which
    eval.py --diligent showed as a traceback with exit code 1 instead of its message and exit 2."""
    source, _ = tiny
    mat = source / "Normal_gt.mat"
    mat.write_bytes(mat.read_bytes()[:kept_bytes])
    with pytest.raises(ValueError, match=f"cannot read {mat}"):
        dataset.import_diligent(source, tmp_path / "out")
    with pytest.raises(evaluation.EvaluationError, match="Normal_gt.mat"):
        evaluation.import_objects([source], tmp_path / "eval")


def test_a_normal_gt_that_is_not_an_array_of_numbers_is_refused(tiny, tmp_path):
    source, _ = tiny
    scipy.io.savemat(source / "Normal_gt.mat", {"Normal_gt": "not normals"})
    with pytest.raises(ValueError, match="Normal_gt.mat holds Normal_gt of shape"):
        dataset.import_diligent(source, tmp_path / "out")


def test_a_nan_in_a_light_file_is_named_as_such_not_as_a_shape(tiny, tmp_path):
    source, _ = tiny
    intensities = INTENSITIES.copy()
    intensities[2, 1] = np.nan
    np.savetxt(source / "light_intensities.txt", intensities)
    with pytest.raises(ValueError, match=r"light_intensities.txt line 3 holds a value that is not a finite number"):
        dataset.import_diligent(source, tmp_path / "out")


def test_a_failed_import_leaves_no_sample_that_no_manifest_lists(tiny, tmp_path):
    """The last photograph is the wrong size: the first two samples were kept without a manifest."""
    source, _ = tiny
    _write_png(source / "004.png", np.zeros((2, 2, 3), np.uint16), oiio.UINT16)
    with pytest.raises(ValueError, match="004.png is 2 x 2 pixels"):
        dataset.import_diligent(source, tmp_path / "new")
    assert not (tmp_path / "new").exists()
    # Into a dataset imported before: the samples it had stay, listed by its manifest.
    dataset.import_diligent(source, tmp_path / "earlier", images=[1])
    with pytest.raises(ValueError, match="004.png is 2 x 2 pixels"):
        dataset.import_diligent(source, tmp_path / "earlier")
    assert sorted(p.name for p in (tmp_path / "earlier").iterdir()) == ["manifest.csv", "manifest.json", "tiny_001"]
    assert dataset.check_sample(tmp_path / "earlier" / "tiny_001") is None


def test_find_objects_accepts_an_object_or_a_folder_of_them(tiny, tmp_path):
    source, _ = tiny
    assert evaluation.find_objects(source) == [source]
    assert evaluation.find_objects(tmp_path) == [source]
    (tmp_path / "empty").mkdir()
    with pytest.raises(evaluation.EvaluationError, match="empty is neither a DiLiGenT object folder"):
        evaluation.find_objects(tmp_path / "empty")
    with pytest.raises(evaluation.EvaluationError, match="nowhere does not exist"):
        evaluation.find_objects(tmp_path / "nowhere")
    (source / "mask.png").unlink()
    with pytest.raises(evaluation.EvaluationError, match="lacks mask.png"):
        evaluation.find_objects(tmp_path)


def test_the_evaluation_measures_the_flat_plane_and_both_lights(tmp_path):
    source = tmp_path / "spherePNG"
    written = write_fixture(source, width=40, height=32)
    imported = evaluation.import_objects([source], tmp_path / "out", log=lambda line: None)
    lines = []
    assert evaluation.import_objects([source], tmp_path / "out", log=lines.append) == imported
    assert lines[0].startswith("reusing the imported DiLiGenT object")
    real = evaluation.evaluate_real(imported, ("lee_rosenfeld",), figures_dir=tmp_path, log=lambda line: None)
    part = real["objects"]["sphere"]
    assert [(r["sample"], r["method"], r["light"]) for r in part["records"][:3]] == [
        ("sphere_001", "flat plane", None), ("sphere_001", "lee_rosenfeld", "calibrated"),
        ("sphere_001", "lee_rosenfeld", "estimated")]
    assert len(part["records"]) == 3 * 3 and all(r["status"] == "ok" for r in part["records"])
    inside = shadecut.erode_mask(written["mask"], evaluation.ERODE_PIXELS)
    flat_angles = np.degrees(np.arccos(np.clip(written["normals"][inside][:, 2], -1, 1)))
    assert part["records"][0]["mean_deg"] == pytest.approx(flat_angles.mean(), rel=1e-5)
    assert part["summary"]["flat"]["mean_deg"] == pytest.approx(flat_angles.mean(), rel=1e-5)
    assert part["records"][1]["light_error_deg"] is None and part["records"][2]["light_error_deg"] is not None
    assert part["records"][1]["depth_rmse"] is None  # no measured depth on a photograph
    calibrated = part["samples"][0]
    assert calibrated["albedo"] is None
    sample = dataset.load_sample(imported["sphere"] / "sphere_001")
    result = shadecut.reconstruct(sample.image, sample.light, sample.mask, None, method="lee_rosenfeld")
    assert calibrated["used_albedo"] == pytest.approx(result.albedo)  # estimated by reconstruct()
    assert part["records"][1]["mean_deg"] == pytest.approx(evaluation.normal_errors(
        result.normals, sample.normals, sample.mask)["mean_deg"])
    assert [Path(f).name for f in part["figures"]] == ["diligent_sphere_calibrated.png",
                                                      "diligent_sphere_estimated.png"]
    table = evaluation.real_table(part)
    assert "| any | **flat plane** |" in table and "| calibrated | lee_rosenfeld |" in table
    assert "| estimated | lee_rosenfeld |" in table


def test_several_photographs_at_once_beside_plain_least_squares(tmp_path):
    """The sets of evaluation.PHOTOGRAPH_SETS whose photographs are present (here only "all": three
    photographs), after the set "one" taken from the single-photograph records."""
    source = tmp_path / "spherePNG"
    write_fixture(source, width=40, height=32)
    imported = evaluation.import_objects([source], tmp_path / "out", log=lambda line: None)
    lines = []
    part = evaluation.evaluate_real(imported, ("graphcut",), log=lines.append)["objects"]["sphere"]
    records = part["photographs"]
    assert [(r["set"], r["count"], r["method"]) for r in records] == [
        ("one", 1, "ShadeCut"), ("all", 3, "ShadeCut"), ("all", 3, "plain least squares")]
    assert all(r["status"] == "ok" for r in records)
    assert records[0]["mean_deg"] == part["summary"]["calibrated"]["methods"]["graphcut"]["mean_deg"]  # reused
    assert records[1]["images"] == list(PRESENT) and 0 <= records[1]["two_lit_share"] <= 1
    for name in ("two", "four", "eight"):
        assert any(f"the set {name} skipped" in line and "not present" in line for line in lines), name
    # Three photographs of a clean Lambertian sphere fix its normals: both far below the flat plane.
    for record in records[1:]:
        assert record["mean_deg"] < 0.3 * part["summary"]["flat"]["mean_deg"], record
        assert record["median_deg"] <= record["mean_deg"] + 5 and record["seconds"] >= 0
    assert [r["light"] for r in records] == ["calibrated"] * 3
    # Three photographs: the library refuses to estimate their lights by design, so the set has no
    # estimated record, and the log and the table say why.
    loaded = diligent.load_object(source)
    with pytest.raises(ValueError, match=f"needs {shadecut.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS} or more"):
        shadecut.reconstruct(loaded.photos, None, loaded.mask)
    assert any(line.startswith("several photographs of sphere, all 3:") and "lights not estimated (fewer than 4 "
               "photographs)" in line for line in lines)
    table = evaluation.photographs_table(part)
    assert "| one (each alone, graphcut, mean) | " in table and "| all 3 |" in table
    assert "ShadeCut, lights estimated mean ° | light error (median) ° |" in table.splitlines()[0]
    row = next(line for line in table.splitlines() if line.startswith("| all 3 |"))
    assert "| — (fewer than 4) | — |" in row


def median_angle(estimated: np.ndarray, calibrated: np.ndarray) -> float:
    """The test's own median angle, in degrees, between two sets of K light directions."""
    estimated = estimated / np.linalg.norm(estimated, axis=1, keepdims=True)
    calibrated = calibrated / np.linalg.norm(calibrated, axis=1, keepdims=True)
    return float(np.median(np.degrees(np.arccos(np.clip(np.sum(estimated * calibrated, axis=1), -1, 1)))))


def test_four_photographs_are_also_read_with_their_lights_estimated(tmp_path):
    """With four photographs the set "all" gets a third record: ShadeCut given no lights (the
    default hint), scored against the measured normals, its lights against the calibrated ones.
    The fixture's lights are not where the default hint puts them (the first from the top, all at
    one slant): the record measures whatever the estimator makes of them, nothing is asserted of
    its accuracy."""
    source = tmp_path / "spherePNG"
    write_fixture(source, width=40, height=32, present=NAMES)
    imported = evaluation.import_objects([source], tmp_path / "out", log=lambda line: None)
    part = evaluation.evaluate_real(imported, ("graphcut",), log=lambda line: None)["objects"]["sphere"]
    records = part["photographs"]
    assert [(r["set"], r["count"], r["method"], r["light"]) for r in records] == [
        ("one", 1, "ShadeCut", "calibrated"), ("all", 4, "ShadeCut", "calibrated"),
        ("all", 4, "plain least squares", "calibrated"), ("all", 4, evaluation.ESTIMATED, "estimated")]
    estimated = records[-1]
    assert estimated["status"] == "ok" and estimated["images"] == list(NAMES)
    loaded = diligent.load_object(source)
    result = shadecut.reconstruct(loaded.photos, None, loaded.mask)
    assert result.stats.light_estimated
    assert estimated["mean_deg"] == pytest.approx(
        evaluation.normal_errors(result.normals, loaded.normals, loaded.mask)["mean_deg"])
    assert estimated["light_error_deg"] == pytest.approx(median_angle(result.lights, LIGHTS), abs=1e-6)
    assert estimated["light_uncertainty_deg"] == pytest.approx(result.stats.light_uncertainty)
    assert evaluation.median_light_error(LIGHTS * [[2.0], [1.0], [0.5], [3.0]], LIGHTS) == pytest.approx(0, abs=1e-6)
    row = next(line for line in evaluation.photographs_table(part).splitlines() if line.startswith("| all 4 |"))
    assert f"| {estimated['mean_deg']:.2f} | {estimated['light_error_deg']:.2f} |" in row


def test_plain_least_squares_inverts_lambertian_shading():
    rng = np.random.default_rng(1)
    normals = rng.normal(size=(6, 5, 3)) + [0, 0, 4]
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    lights = LIGHTS / np.linalg.norm(LIGHTS, axis=-1, keepdims=True)
    photographs = [0.6 * np.clip(normals @ light, 0, None) for light in lights]
    assert all((p > 0).all() for p in photographs)  # every pixel lit: the least squares are exact
    np.testing.assert_allclose(evaluation.plain_least_squares(photographs, lights), normals, atol=1e-9)
    colour = [np.repeat(p[..., None], 3, axis=-1) for p in photographs]  # grey RGB: its luminance
    np.testing.assert_allclose(evaluation.plain_least_squares(colour, lights), normals, atol=1e-9)


def test_several_photographs_whose_source_is_gone_are_left_out_with_a_line(tmp_path):
    source = tmp_path / "spherePNG"
    write_fixture(source)
    imported = evaluation.import_objects([source], tmp_path / "out", log=lambda line: None)
    (source / "mask.png").unlink()
    lines = []
    assert evaluation.evaluate_sets(imported["sphere"], {}, log=lines.append) == []
    assert "cannot read the source object" in lines[0] and "mask.png" in lines[0]


@pytest.mark.skipif(not (DILIGENT / "ballPNG").is_dir(),
                    reason=f"DiLiGenT is not at {DILIGENT} (expects ballPNG/ there in the benchmark's layout)")
def test_the_ball_of_the_benchmark(tmp_path):
    source = DILIGENT / "ballPNG"
    entries = dataset.import_diligent(source, tmp_path)
    assert len(entries) == 19 and entries[0]["id"] == "ball_001" and entries[-1]["id"] == "ball_092"
    truth = scipy.io.loadmat(source / "Normal_gt.mat")["Normal_gt"]
    for entry in entries:
        sample = dataset.load_sample(tmp_path / entry["folder"])
        assert sample.image.shape == (512, 612)
        np.testing.assert_allclose(sample.normals[sample.mask], truth[sample.mask], atol=1e-6)
        assert not sample.normals[~sample.mask].any()
        # The frame: the measured normals lit by the calibrated light explain the photograph (the
        # unsaturated pixels), which a mirrored x or y would not.
        lit = sample.mask & (sample.image < 0.9 * sample.image[sample.mask].max())
        shading = np.clip(sample.normals[lit] @ sample.light, 0, None)
        assert np.corrcoef(shading, sample.image[lit])[0, 1] > 0.8, entry["id"]


@pytest.mark.parametrize("module", ["shadecut.diligent", "shadecut.dataset_files", "shadecut.dataset"])
def test_each_module_imports_first(module):
    """No import cycle: a fresh interpreter can start from any of the modules that write samples."""
    import subprocess
    import sys

    addon = Path(shadecut.__file__).resolve().parents[1]
    completed = subprocess.run([sys.executable, "-c", f"import {module}; import shadecut.dataset as d; "
                                "assert d.import_diligent.__module__ == 'shadecut.diligent'"],
                               capture_output=True, text=True, env={"PYTHONPATH": str(addon)}, timeout=60)
    assert completed.returncode == 0, completed.stderr


def test_load_object_reads_the_chosen_photographs_with_their_lights():
    """One loader serves the tests and the measurements: photographs by number, cropped to the mask."""
    folder = Path(__file__).resolve().parents[3] / "shared" / "data" / "diligent" / "ballPNG"
    if not folder.is_dir():
        pytest.skip(f"DiLiGenT is not at {folder.parent}")
    ball = diligent.load_object(folder, images=[85, 7])
    layout = diligent.read_layout(folder)
    assert ball.names == ["085.png", "007.png"]
    np.testing.assert_array_equal(ball.lights, [layout["lights"][layout["names"].index(n)] for n in ball.names])
    assert ball.photos[0].shape == (*ball.mask.shape, 3) and ball.normals.shape == (*ball.mask.shape, 3)
    rows, cols = np.nonzero(ball.mask)
    assert rows.min() == 8 and cols.min() == 8  # the margin around the mask
    with pytest.raises(ValueError, match="no image 999"):
        diligent.load_object(folder, images=[999])
