"""blender_scripts/batch.py: a folder of images reconstructed headless, as an artist runs it
(``blender -b -P blender_scripts/batch.py -- IN_DIR OUT_DIR``), bad files named and skipped over."""

import subprocess

import bpy
import numpy as np
import pytest

import shadecut
from shadecut import synthetic
from shadecut.dataset import read_image_channels

SIZES = {"a_sphere.png": 64, "d_sphere.exr": 48}  # name -> size; the good images
LIGHTS = {"a_sphere.png": (1.0, 0.0, 1.0), "d_sphere.exr": (-0.4, 0.5, 1.0)}


def batch(repo, *args):
    command = [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
               "-P", str(repo / "blender_scripts" / "batch.py"), "--", *map(str, args)]
    return subprocess.run(command, capture_output=True, text=True, timeout=300)


def ply_vertex_count(path):
    header = path.read_bytes().split(b"end_header", 1)[0].decode("ascii")
    (line,) = [line for line in header.splitlines() if line.startswith("element vertex")]
    return int(line.split()[-1])


def blender_pixels(path):
    """(H, W, 4) float pixels of an image as bpy.data.images.load reads it, row 0 at the top."""
    image = bpy.data.images.load(str(path))
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, np.float32)
        image.pixels.foreach_get(pixels)
        return pixels.reshape(height, width, 4)[::-1]
    finally:
        bpy.data.images.remove(image)


@pytest.fixture
def folder(tmp_path):
    """Two sphere renders (a 16-bit PNG and a float EXR, mask as alpha) with, sorted between them, a
    truncated PNG and a text file named like a JPEG; and a text file that is not named like an image."""
    in_dir = tmp_path / "in"
    in_dir.mkdir()
    scenes = {}
    for name, size in SIZES.items():
        scenes[name] = synthetic.sphere(light=LIGHTS[name], size=size)
        shadecut.save_image(in_dir / name, scenes[name].image, scenes[name].mask)
    whole = (in_dir / "a_sphere.png").read_bytes()
    (in_dir / "b_broken.png").write_bytes(whole[: len(whole) // 3])
    (in_dir / "c_notes.jpg").write_text("not an image\n")
    (in_dir / "e_readme.txt").write_text("the renders of the test\n")
    return in_dir, scenes


def test_batch_writes_every_good_image_and_names_the_bad_ones(repo, folder, tmp_path):
    in_dir, scenes = folder
    out_dir = tmp_path / "out" / "nested"  # created by the script
    run = batch(repo, in_dir, out_dir)
    print(run.stdout, run.stderr)
    assert run.returncode == 1, "a failed file must give a non-zero exit code"
    assert "Traceback" not in run.stderr

    # One progress line per image, in name order: index/total, name, seconds, the subject, the light found.
    for index, name in enumerate(sorted([*SIZES, "b_broken.png", "c_notes.jpg"]), 1):
        stream = run.stdout if name in SIZES else run.stderr
        assert f"[{index}/4] {name}: " in stream, name
    for name in SIZES:
        (line,) = [line for line in run.stdout.splitlines() if f"] {name}: " in line]
        assert " s, subject object (auto: its alpha cuts it out), light found (" in line, line
    assert "[2/4] b_broken.png: error: " in run.stderr and "[3/4] c_notes.jpg: error: " in run.stderr
    assert "skipped e_readme.txt" in run.stdout
    assert "2 of 4 image(s) done" in run.stdout

    expected = set()
    for name, size in SIZES.items():
        stem, truth = name.split(".")[0], scenes[name]
        expected |= {f"{stem}_height.exr", f"{stem}_normal.png", f"{stem}.ply"}
        pixels, channels = read_image_channels(out_dir / f"{stem}_height.exr")
        assert pixels.shape[:2] == (size, size)
        depth, mask = pixels[..., channels.index("Y")], pixels[..., channels.index("A")] > 0.5
        np.testing.assert_array_equal(mask, truth.mask)
        assert np.isfinite(depth).all()
        # The sphere's centre stands above its rim (the mask's outermost ring of pixels).
        inner = shadecut.erode_mask(mask, 1)
        rim = mask & ~inner
        assert depth[size // 2, size // 2] > np.mean(depth[rim]) + 0.2 * size, name
        # Blender opens it as a grey image of the same heights (a Z channel opened black), the mask in alpha.
        loaded = blender_pixels(out_dir / f"{stem}_height.exr")
        for channel in range(3):
            np.testing.assert_array_equal(loaded[..., channel], depth)
        np.testing.assert_array_equal(loaded[..., 3] > 0.5, mask)
        assert loaded[..., 0].max() > 0.2 * size

        colors, _ = read_image_channels(out_dir / f"{stem}_normal.png")
        assert colors.shape == (size, size, 3)
        np.testing.assert_allclose(colors[size // 2, size // 2], (0.5, 0.5, 1.0), atol=0.05)  # faces the viewer
        np.testing.assert_allclose(colors[0, 0], (0.5, 0.5, 1.0), atol=1e-4)  # outside the mask: flat
        assert ply_vertex_count(out_dir / f"{stem}.ply") == np.count_nonzero(truth.mask)
    assert {path.name for path in out_dir.iterdir()} == expected  # nothing for the bad files, no leftovers


def test_max_size_and_relief(repo, folder, tmp_path):
    in_dir, _ = folder
    out_dir = tmp_path / "out"
    run = batch(repo, in_dir, out_dir, "--max-size", "32", "--scene", "relief")
    print(run.stdout, run.stderr)
    assert run.returncode == 1 and "scene relief" in run.stdout and "subject relief (--scene)" in run.stdout
    assert "32 x 32 (shrunk by 2 from 64 x 64)" in run.stdout  # the add-on's whole-factor rule
    pixels, _ = read_image_channels(out_dir / "a_sphere_height.exr")
    assert pixels.shape[:2] == (32, 32)
    pixels, _ = read_image_channels(out_dir / "d_sphere_height.exr")
    assert pixels.shape[:2] == (24, 24)


@pytest.mark.parametrize("args, message", [
    (["{tmp}/missing", "{tmp}/out"], "IN_DIR {tmp}/missing does not exist"),
    (["{tmp}"], "the following arguments are required: OUT_DIR"),
    (["{tmp}/in", "{tmp}/out", "--max-size", "-1"], "--max-size must be 0"),
    (["{tmp}/in", "{tmp}/out", "--scene", "wall"], "argument --scene: invalid choice"),
])
def test_bad_arguments_are_exit_2_with_a_message(repo, folder, tmp_path, args, message):
    run = batch(repo, *(arg.format(tmp=tmp_path) for arg in args))
    assert run.returncode == 2, run.stdout + run.stderr
    assert f"batch.py: error: {message.format(tmp=tmp_path)}" in run.stderr
    assert "Traceback" not in run.stderr
    assert not (tmp_path / "out").exists()
