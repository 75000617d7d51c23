"""blender_scripts/batch.py run by plain Python (it needs no Blender): what it must never do to the
user's files. Its normal runs are tested inside Blender (tests/blender/test_batch.py)."""

import subprocess
import sys
from pathlib import Path

import shadecut
from shadecut import synthetic

BATCH = Path(__file__).resolve().parents[2] / "blender_scripts" / "batch.py"


def batch(*args):
    return subprocess.run([sys.executable, str(BATCH), *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def sphere_png(path, light):
    scene = synthetic.sphere(light=light, size=32)
    shadecut.save_image(path, scene.image, scene.mask)
    return path.read_bytes()


def test_an_output_that_would_replace_an_input_is_refused_before_any_work(tmp_path):
    """x.png's normal map is x_normal.png: in the same folder as an input of that name it would be
    overwritten before it is read, and the overwritten image then reconstructed."""
    inputs = {name: sphere_png(tmp_path / name, light) for name, light in
              (("x.png", (1.0, 0.0, 1.0)), ("x_normal.png", (0.0, 1.0, 1.0)))}
    run = batch(tmp_path, tmp_path)
    assert run.returncode == 2, run.stdout + run.stderr
    assert "x_normal.png" in run.stderr and "would replace" in run.stderr and "Traceback" not in run.stderr
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(inputs)  # nothing written
    assert all((tmp_path / name).read_bytes() == data for name, data in inputs.items())


def test_the_same_folder_for_output_is_fine_when_no_input_is_named_like_an_output(tmp_path):
    sphere_png(tmp_path / "x.png", (1.0, 0.0, 1.0))
    run = batch(tmp_path, tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert sorted(path.name for path in tmp_path.iterdir()) == ["x.ply", "x.png", "x_height.exr", "x_normal.png"]
