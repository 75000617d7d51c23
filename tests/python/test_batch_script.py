"""blender_scripts/batch.py run by plain Python (it needs no Blender): what it must never do to the
user's files, the subject it chooses, and its meshes' vertex budget. Its normal runs are tested inside
Blender (tests/blender/test_batch.py), where its height EXR is loaded as Blender loads it."""

import subprocess
import sys
from pathlib import Path

import numpy as np

import shadecut
from shadecut import synthetic
from shadecut.dataset import read_image_channels

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


def ply_vertices(path):
    """The (V, 3) vertices of a binary PLY written by shadecut.save_mesh."""
    data = path.read_bytes()
    header, body = data.split(b"end_header\n", 1)
    (line,) = [line for line in header.decode("ascii").splitlines() if line.startswith("element vertex")]
    count = int(line.split()[-1])
    return np.frombuffer(body[: count * 12], dtype="<f4").reshape(count, 3)


def texture_png(path, size):
    """A brick wall filling the frame, saved without alpha: a texture as an artist's folder holds it."""
    scene = synthetic.bricks(light=(0.4, 0.5, 1.0), size=size)
    shadecut.save_image(path, scene.image)  # no mask: no alpha channel
    return scene


def height_exr(path):
    """The height EXR's depth (channel Y, grey as Blender reads it) and mask (alpha A)."""
    pixels, channels = read_image_channels(path)
    assert sorted(channels) == ["A", "Y"], channels
    return pixels[..., channels.index("Y")], pixels[..., channels.index("A")] > 0.5


def test_the_default_subject_is_relief_for_a_texture_and_object_for_a_cut_out(tmp_path):
    """A texture (no alpha) is a relief, as --scene relief would make it; an image whose alpha cuts out
    an object is an object; each line says which was chosen and why; --scene overrides."""
    in_dir = tmp_path / "in"
    in_dir.mkdir()
    texture_png(in_dir / "wall.png", 64)
    sphere_png(in_dir / "ball.png", (1.0, 0.0, 1.0))
    run = batch(in_dir, tmp_path / "auto")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "scene auto (relief without transparent pixels, else object)" in run.stdout
    assert "ball.png: " in run.stdout and "subject object (auto: its alpha cuts it out)" in run.stdout
    assert "wall.png: " in run.stdout and "subject relief (auto: no alpha, it fills the frame)" in run.stdout

    relief = batch(in_dir, tmp_path / "relief", "--scene", "relief")
    assert relief.returncode == 0 and "subject relief (--scene)" in relief.stdout
    np.testing.assert_array_equal(height_exr(tmp_path / "auto" / "wall_height.exr")[0],
                                  height_exr(tmp_path / "relief" / "wall_height.exr")[0])
    obj = batch(in_dir, tmp_path / "object", "--scene", "object")
    assert obj.returncode == 0 and obj.stdout.count("subject object (--scene)") == 2


def test_the_mesh_keeps_to_the_addons_vertex_limit_unless_full_is_asked(tmp_path):
    """A 512 px texture has 262,144 pixels, over the add-on's 250,000: the PLY samples every other
    pixel (shadecut.vertex_step), its vertices at the height EXR's values; --full-mesh keeps them all."""
    in_dir = tmp_path / "in"
    in_dir.mkdir()
    texture_png(in_dir / "wall.png", 512)
    run = batch(in_dir, tmp_path / "out")
    assert run.returncode == 0, run.stdout + run.stderr
    depth, mask = height_exr(tmp_path / "out" / "wall_height.exr")
    assert mask.all() and np.ptp(depth) > 0  # a relief filling the frame, not a black image
    step = shadecut.vertex_step(mask)
    assert step == 2 and shadecut.MAX_VERTICES == 250_000
    vertices = ply_vertices(tmp_path / "out" / "wall.ply")
    assert len(vertices) == 256 * 256 <= shadecut.MAX_VERTICES
    assert "wall.ply (65,536 vertices, one every 2 px)" in run.stdout
    # The vertices stand at (column, -row, depth) of the sampled pixels: the same heights as the EXR.
    rows, cols = (-vertices[:, 1]).astype(int), vertices[:, 0].astype(int)
    assert set(np.unique(rows)) == set(range(0, 512, 2))
    np.testing.assert_array_equal(vertices[:, 2], depth[rows, cols])

    full = batch(in_dir, tmp_path / "full", "--full-mesh")
    assert full.returncode == 0, full.stdout + full.stderr
    assert len(ply_vertices(tmp_path / "full" / "wall.ply")) == 512 * 512
    small = batch(in_dir, tmp_path / "small", "--max-vertices", "1000")
    assert small.returncode == 0 and len(ply_vertices(tmp_path / "small" / "wall.ply")) <= 1000


def test_bad_mesh_flags_are_refused(tmp_path):
    sphere_png(tmp_path / "x.png", (1.0, 0.0, 1.0))
    run = batch(tmp_path, tmp_path / "out", "--max-vertices", "3")
    assert run.returncode == 2 and "--max-vertices must be at least 4" in run.stderr
    run = batch(tmp_path, tmp_path / "out", "--max-vertices", "9", "--full-mesh")
    assert run.returncode == 2 and "not allowed with" in run.stderr
    assert not (tmp_path / "out").exists()
