"""shadecut.evaluation.materials (issue 46, item 5): one photograph of a scanned material beside the
artist's baselines, flat and the image as height, and eval.py --materials that writes them."""

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import materials
from shadecut.evaluation import materials as baselines
from test_materials import MATERIALS, needs_materials, write_codes

REPO = Path(__file__).resolve().parents[2]
LIGHT = np.array([0.0, 0.64, 0.77])


def terrazzo(size: int = 32, seed: int = 0) -> materials.Material:
    """A flat painted material: chips of colour, no relief at all."""
    rng = np.random.default_rng(seed)
    chips = rng.uniform(0.1, 0.9, (size // 4, size // 4, 3)).repeat(4, axis=0).repeat(4, axis=1)
    return materials.Material(name="terrazzo", albedo=chips.astype(np.float32),
                              normals=baselines.flat_normals((size, size)), height=np.zeros((size, size), np.float32))


def bump(size: int = 64) -> np.ndarray:
    """A Gaussian bump 8 pixels high, in pixel units."""
    rows, cols = np.mgrid[:size, :size] - size / 2
    return 8.0 * np.exp(-(rows**2 + cols**2) / (2 * 9.0**2))


def write_material(folder: Path, size=(20, 24), seed: int = 0) -> None:
    """A tiny flat material in the scanned sets' layout: random colour, a flat normal map, no height."""
    folder.mkdir(parents=True)
    rng = np.random.default_rng(seed)
    shadecut.save_image(folder / "color.png", rng.uniform(0.2, 0.8, (*size, 3)).astype(np.float32))
    write_codes(folder / "normal_gl.png", np.broadcast_to(np.array([128, 128, 255], np.uint8), (*size, 3)).copy())
    shadecut.save_image(folder / "displacement.png", np.zeros(size, np.float32))


def test_flat_on_a_flat_painted_material_is_exact_and_one_row_per_method():
    material = terrazzo()
    (photograph,) = materials.lambertian_photographs(material, [LIGHT])
    rows = baselines.render_rows(material, LIGHT, photograph, baselines.STRENGTHS[0])
    assert [row["method"] for row in rows] == list(baselines.METHODS)
    flat = rows[0]
    assert flat["mean_deg"] == pytest.approx(0.0, abs=1e-4) and flat["below_flat"] is None
    assert (flat["light_azimuth_deg"], flat["light_slant_deg"]) == pytest.approx((90.0, np.degrees(np.arctan2(0.64, 0.77))))
    # The paint read as height gives slopes where there are none: every strength is worse than flat,
    # the weakest least.
    errors = baselines.height_errors(photograph, material.normals)
    assert np.all(np.diff(errors) > 0) and errors[0] > 0
    assert rows[2]["strength"] == baselines.STRENGTHS[0] and rows[2]["below_flat"] is False


def test_image_as_height_is_the_bump_node_brighter_higher():
    """A photograph whose luminance is the height over 10: at strength 10 the image as height is the
    surface itself, and the best strength knowing the truth is that one."""
    height = bump()
    strength = baselines.STRENGTHS[24]
    assert strength == pytest.approx(10.0)
    photograph = np.repeat((height / strength)[..., None], 3, axis=-1)  # grey: luminance = the value
    truth = shadecut.normals_from_depth(height)
    np.testing.assert_allclose(baselines.image_as_height(photograph, strength), truth, atol=1e-5)
    errors = baselines.height_errors(photograph, truth)
    assert int(np.argmin(errors)) == 24 and errors[24] < 1e-3
    # Brighter is higher: left of the bump's top the surface rises to the right, its normal leans left.
    assert baselines.image_as_height(photograph, strength)[32, 25, 0] < -0.1


def test_the_training_strength_reads_the_training_half_only(tmp_path, monkeypatch):
    for index, name in enumerate(materials.TRAINING):
        write_material(tmp_path / name, seed=index)
    for name in materials.TEST:  # present but unreadable: reading one would fail the call
        (tmp_path / name).mkdir()
    read = []
    monkeypatch.setattr(baselines, "load_material", lambda folder: read.append(Path(folder).name)
                        or materials.load_material(folder))
    # Flat materials painted at random: any strength adds slopes that are not there, the weakest fewest.
    errors = baselines.training_errors(tmp_path)
    assert read == list(materials.TRAINING)
    assert errors.shape == baselines.STRENGTHS.shape and np.all(np.diff(errors) > 0)
    assert baselines.training_strength(errors) == baselines.STRENGTHS[0]
    with pytest.raises(ValueError, match="Bricks061 belong to the test half"):
        baselines.training_errors(tmp_path, names=("Bark014", "Bricks061"))


def test_a_folder_without_the_material_files_is_refused_naming_what_is_missing(tmp_path):
    (tmp_path / "Bricks061").mkdir()
    with pytest.raises(ValueError, match="Bricks061 has no color.png"):
        baselines.evaluate_materials(tmp_path, ["Bricks061"], baselines.default_lights(), 1.0)
    with pytest.raises(ValueError, match="the materials folder .*nowhere does not exist"):
        baselines.evaluate_materials(tmp_path / "nowhere", ["Bricks061"], baselines.default_lights(), 1.0)


def test_the_summary_counts_renders_below_flat_and_the_median_light_error():
    rows = []
    for light, flat, ours, light_error in ((0, 10.0, 8.0, 5.0), (90, 10.0, 12.0, 20.0), (180, 4.0, 3.0, 8.0)):
        rows += [{"material": "m", "light_azimuth_deg": light, "method": baselines.FLAT, "mean_deg": flat,
                  "below_flat": None},
                 {"material": "m", "light_azimuth_deg": light, "method": baselines.SHADECUT_ESTIMATED,
                  "mean_deg": ours, "below_flat": ours < flat, "light_error_deg": light_error}]
    summary = baselines.summarize_materials(rows)
    assert summary[baselines.FLAT]["mean_deg"] == pytest.approx(8.0)
    assert summary[baselines.SHADECUT_ESTIMATED] == {"mean_deg": pytest.approx(23.0 / 3), "below_flat": 2,
                                                     "renders": 3, "failed": 0, "median_light_error_deg": 8.0}
    assert summary[baselines.SHADECUT_TRUE]["renders"] == 0 and summary[baselines.SHADECUT_TRUE]["mean_deg"] is None


def results_section() -> str:
    text = (REPO / "docs" / "results.md").read_text()
    return text.split("## Materials: the artist's baselines", 1)[1].split("\n## ", 1)[0]


@needs_materials
def test_the_docs_row_of_leather_is_what_the_module_measures():
    """docs/results.md's table is eval.py --materials's; one material of it measured again (all four
    lights, every method) at the strength the docs name."""
    section = results_section()
    strength = float(re.search(r"strength chosen on the training half: ([0-9.e+-]*[0-9])", section).group(1))
    rows = baselines.evaluate_materials(MATERIALS, ["Leather037"], baselines.default_lights(), strength)
    measured = baselines.material_table(rows).splitlines()[-1]
    documented = next(line for line in section.splitlines() if line.startswith("| Leather037 |"))
    assert measured == documented


@pytest.mark.skipif(shutil.which("blender") is None, reason="Blender is not installed")
def test_eval_py_materials_writes_its_files_and_refuses_a_folder_without_them(tmp_path):
    folder = tmp_path / "materials"
    for index, name in enumerate(materials.TRAINING + materials.TEST):
        write_material(folder / name, seed=index)
    eval_py = REPO / "blender_scripts" / "eval.py"

    def run(*args):
        return subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "-P", str(eval_py),
                               "--", *map(str, args)], capture_output=True, text=True, timeout=600)

    out = tmp_path / "out"
    completed = run("--materials", folder, "--out", out)
    assert completed.returncode == 0, completed.stdout[-2000:] + completed.stderr[-2000:]
    assert sorted(path.name for path in out.iterdir() if path.is_file()) == sorted(baselines.FILES)
    rows = (out / "materials.csv").read_text().splitlines()
    assert len(rows) == 1 + len(materials.TEST) * baselines.LIGHT_COUNT * len(baselines.METHODS)
    assert "| flat | 0.32 |" in (out / "materials.md").read_text()  # the 8-bit flat normal map's own tilt

    shadowed = run("--materials", folder, "--cast-shadows", "--out", tmp_path / "shadowed")
    assert shadowed.returncode == 0, shadowed.stdout[-2000:] + shadowed.stderr[-2000:]
    assert "Lambertian renders with cast shadows of" in (tmp_path / "shadowed" / "materials.md").read_text()
    alone = run("--cast-shadows", "--out", tmp_path / "alone")
    assert alone.returncode == 2 and "give --materials DIR" in alone.stderr, alone.stderr

    shutil.rmtree(folder / "Rock029")
    refused = run("--materials", folder, "--out", tmp_path / "refused")
    assert refused.returncode == 2 and "Rock029 has no color.png" in refused.stderr, refused.stderr
    assert "Traceback" not in refused.stdout + refused.stderr and not (tmp_path / "refused").exists()
