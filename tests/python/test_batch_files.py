"""batch.py and the files it must keep: any file of IN_DIR an output would replace, and another run's
temporary files in the same OUT_DIR (issue 48, findings 2 and 16)."""

import os
import subprocess
import sys
from pathlib import Path

import shadecut
from shadecut import synthetic
from shadecut.atomic_write import replacing, temporary_name

BATCH = Path(__file__).resolve().parents[2] / "blender_scripts" / "batch.py"


def batch(*args):
    return subprocess.run([sys.executable, str(BATCH), *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def sphere_png(path):
    scene = synthetic.sphere(light=(1.0, 0.0, 1.0), size=32)
    shadecut.save_image(path, scene.image, scene.mask)


def test_a_file_that_is_not_an_image_is_not_replaced_by_an_output(tmp_path):
    """scan.ply beside scan.png is skipped as an input, but batch.py D D would write scan.png's mesh
    over it: refused before any work, like an image named like an output."""
    sphere_png(tmp_path / "scan.png")
    (tmp_path / "scan.ply").write_bytes(b"ply\nthe user's own scan\n")
    run = batch(tmp_path, tmp_path)
    assert run.returncode == 2, run.stdout + run.stderr
    assert "scan.ply" in run.stderr and "would replace" in run.stderr and "Traceback" not in run.stderr
    assert (tmp_path / "scan.ply").read_bytes() == b"ply\nthe user's own scan\n"
    assert sorted(path.name for path in tmp_path.iterdir()) == ["scan.ply", "scan.png"]


def test_another_runs_temporary_files_are_left_alone(tmp_path):
    """Two runs into one folder: each writes under temporary names of its own. Before, both used
    .x_height.partial.exr, so one run renamed away (or overwrote) the other's half-written file."""
    in_dir, out_dir = tmp_path / "in", tmp_path / "out"
    in_dir.mkdir()
    out_dir.mkdir()
    sphere_png(in_dir / "x.png")
    others = {name: f"another run's {name}".encode() for name in
              (".x_height.partial.exr", ".x_normal.partial.png", ".x.partial.ply")}
    for name, data in others.items():
        (out_dir / name).write_bytes(data)
    run = batch(in_dir, out_dir)
    assert run.returncode == 0, run.stdout + run.stderr
    assert all((out_dir / name).read_bytes() == data for name, data in others.items())
    assert sorted(path.name for path in out_dir.iterdir() if not path.name.startswith(".")) == [
        "x.ply", "x_height.exr", "x_normal.png"]


def test_temporary_names_differ_between_calls_and_keep_the_extension(tmp_path):
    first, second = temporary_name(tmp_path / "a.exr"), temporary_name(tmp_path / "a.exr")
    assert first != second and first.suffix == second.suffix == ".exr" and first.name.startswith(".")
    assert str(os.getpid()) in first.name


def test_a_failed_write_leaves_the_previous_file_and_no_temporary(tmp_path):
    target = tmp_path / "results.json"
    target.write_text("the previous results")
    try:
        with replacing(target) as temporary:
            temporary.write_text("half of the new")
            raise OSError("No space left on device")
    except OSError:
        pass
    assert target.read_text() == "the previous results"
    assert [path.name for path in tmp_path.iterdir()] == ["results.json"]


def test_a_sets_outputs_that_would_replace_an_input_are_refused_before_any_work(tmp_path):
    """The set rug/ writes rug_albedo.png beside its other files: into IN_DIR itself it would replace
    the image of that name."""
    (tmp_path / "rug").mkdir()
    for side in ("above", "left"):
        sphere_png(tmp_path / "rug" / f"rug_{side}.png")
    sphere_png(tmp_path / "rug_albedo.png")
    before = {path: path.read_bytes() for path in tmp_path.rglob("*") if path.is_file()}
    run = batch(tmp_path, tmp_path)
    assert run.returncode == 2, run.stdout + run.stderr
    assert "the outputs of rug/ would replace rug_albedo.png" in run.stderr and "Traceback" not in run.stderr
    assert {path: path.read_bytes() for path in tmp_path.rglob("*") if path.is_file()} == before


def test_out_dir_inside_in_dir_is_not_read_as_a_set(tmp_path):
    """batch.py D D/out twice: the second run finds the first's outputs in D/out, a subfolder of
    images, and must not reconstruct them as photographs of one subject."""
    sphere_png(tmp_path / "x.png")
    for _ in range(2):
        run = batch(tmp_path, tmp_path / "out")
        assert run.returncode == 0, run.stdout + run.stderr
    assert "skipped out/: it is OUT_DIR" in run.stdout and "1 of 1 image(s) done" in run.stdout
    assert sorted(path.name for path in (tmp_path / "out").iterdir()) == ["x.ply", "x_height.exr", "x_normal.png"]
