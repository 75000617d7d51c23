"""The dataset's and DiLiGenT's readers and writer on what a user's folder can hold (issue 48): a
named pipe where an image should be (finding 6), a pixel size of 0 in meta.json (13), a light below
the horizon in light_directions.txt (17), a folder of the user's named like a sample (the writer's
check of what it would replace)."""

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from shadecut import dataset, evaluation, synthetic
from test_diligent import write_fixture


def sphere_sample(folder, pixel_size=1.0):
    scene = synthetic.sphere((0.5, 0.3, 1.0), size=16)
    dataset.write_sample(folder, image=scene.image, normals=scene.normals, depth=scene.depth, mask=scene.mask,
                         light=scene.light, albedo=scene.albedo, meta={"pixel_size": pixel_size})
    return folder


@pytest.mark.parametrize("name", ["mask.png", "normals.exr", "depth.exr", "meta.json"])
def test_a_named_pipe_in_a_sample_is_refused_not_waited_on(tmp_path, name):
    """Each reader opened the pipe and waited for a writer that never comes; run in a child process
    so that a hang fails the test instead of stopping the run."""
    folder = sphere_sample(tmp_path / "s")
    (folder / name).unlink()
    os.mkfifo(folder / name)
    code = textwrap.dedent(f"""
        from shadecut import dataset
        for read in (dataset.load_sample, dataset.load_sample_meta):
            try:
                read({str(folder)!r})
            except (OSError, ValueError) as error:
                print(error)
        print(dataset.check_sample({str(folder)!r}))
    """)
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    if name == "meta.json":  # not a sample: is_sample looks for a regular file
        assert "is not a ShadeCut sample" in run.stdout
    else:
        assert f'cannot read "{folder / name}": it is a named pipe (FIFO), not a regular file' in run.stdout


@pytest.mark.parametrize("value", [0, -1.0, "NaN", None, True, "0.5"])
def test_a_pixel_size_that_is_not_a_positive_number_is_refused_by_the_readers(tmp_path, value):
    folder = sphere_sample(tmp_path / "s")
    meta = json.loads((folder / "meta.json").read_text())
    meta["pixel_size"] = float("nan") if value == "NaN" else value
    (folder / "meta.json").write_text(json.dumps(meta))
    with pytest.raises(ValueError, match="pixel_size .* is not a positive number of scene units per pixel"):
        dataset.load_sample(folder)
    assert "is not a positive number of scene units per pixel" in dataset.check_sample(folder)


def test_the_writer_and_the_readers_share_the_pixel_size_rule(tmp_path):
    with pytest.raises(ValueError, match="pixel_size 0 is not a positive number"):
        sphere_sample(tmp_path / "s", pixel_size=0)
    assert np.isfinite(dataset.load_sample(sphere_sample(tmp_path / "t", pixel_size=0.25)).depth).all()


def test_a_light_below_the_horizon_is_named_by_file_line_and_image_before_anything_is_written(tmp_path):
    source = tmp_path / "tinyPNG"
    write_fixture(source)
    lines = (source / "light_directions.txt").read_text().splitlines()
    lines[1] = "0.1000 0.2000 -0.5000"  # 002.png's light
    (source / "light_directions.txt").write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"light_directions.txt line 2 \(the light of 002.png: 0.1 0.2 -0.5\): "
                                         r"the light is at or below the horizon"):
        dataset.import_diligent(source, tmp_path / "out")
    assert not (tmp_path / "out").exists()
    with pytest.raises(evaluation.EvaluationError, match="line 2 .*002.png"):
        evaluation.import_objects([source], tmp_path / "eval" / "diligent", log=lambda line: None)
    assert not (tmp_path / "eval" / "diligent").exists()


def test_a_users_folder_named_like_a_sample_is_not_replaced(tmp_path):
    """import_diligent into a folder holding the user's own ball_001/ replaced it and all its files."""
    source = tmp_path / "ballPNG"
    write_fixture(source)
    own = tmp_path / "out" / "ball_001"
    own.mkdir(parents=True)
    (own / "notes.txt").write_text("the user's own")
    with pytest.raises(OSError, match=r"ball_001 exists and is not a ShadeCut sample \(it holds notes.txt\)"):
        dataset.import_diligent(source, tmp_path / "out")
    assert (own / "notes.txt").read_text() == "the user's own"
    (tmp_path / "file").write_text("a file")
    with pytest.raises(OSError, match="exists and is not a folder"):
        sphere_sample(tmp_path / "file")
    assert (tmp_path / "file").read_text() == "a file"


def test_a_sample_a_damaged_one_or_an_empty_folder_is_replaced(tmp_path):
    sphere_sample(tmp_path / "s")
    sphere_sample(tmp_path / "s", pixel_size=0.5)
    assert dataset.load_sample_meta(tmp_path / "s")["pixel_size"] == 0.5
    (tmp_path / "s" / "meta.json").unlink()  # damaged: its files alone, redone
    sphere_sample(tmp_path / "s")
    assert dataset.check_sample(tmp_path / "s") is None
    (tmp_path / "empty").mkdir()
    sphere_sample(tmp_path / "empty")
    assert dataset.is_sample(tmp_path / "empty")
