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


SIDES = ("above", "below", "left", "right")
# One step of a 16-bit normal-map channel is 2/65535 of a unit component, 0.00175 degrees: four
# noiseless Lambertian photographs fix every normal, so what is left is the rounding of the 16-bit
# photographs and of the normal map (measured: mean 0.0009, max 0.0025 degrees; 64 px bumps, patches).
NORMAL_STEP_DEGREES = np.degrees(2 / 65535)


def painted_bumps(folder, names_and_lights, size=64):
    """The bump field (synthetic.bumps) painted in colour patches and photographed under each light,
    as 16-bit PNGs without alpha (a subject that fills the frame); the true normals and paint."""
    folder.mkdir(parents=True)
    for name, light in names_and_lights:
        scene = synthetic.bumps(light=light, size=size)
        colour, paint = synthetic.painted(scene, "patches", seed=3)
        shadecut.save_image(folder / name, colour)
    return scene.normals, paint


def normal_map(path):
    """The unit normals a 16-bit normal map's colours hold (0.5 n + 0.5)."""
    colours, _ = read_image_channels(path)
    normals = 2.0 * colours - 1.0
    return normals / np.linalg.norm(normals, axis=2, keepdims=True)


def test_a_subfolder_of_photographs_named_by_their_light_gives_true_normals_and_the_paint(tmp_path):
    """rug/rug_above.png ... rug_right.png: one set, its lights the sides the names end with
    (shadecut.light_from_side); the normal map is the truth to within the 16-bit rounding, and
    rug_albedo.png (sRGB, alpha = mask) holds the paint without any of the shading."""
    in_dir = tmp_path / "in"
    photographs = [(f"rug_{side}.png", shadecut.light_from_side(side)) for side in SIDES]
    truth, paint = painted_bumps(in_dir / "rug", photographs)
    run = batch(in_dir, tmp_path / "out")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 image(s) and 1 set(s) of photographs in" in run.stdout
    (line,) = [line for line in run.stdout.splitlines() if line.startswith("[1/1] rug/: ")]
    assert ("4 photographs, subject relief (auto: no alpha, it fills the frame), lights from the names" in line
            and "-> rug_height.exr, rug_normal.png, rug_albedo.png, rug.ply (4,096 vertices, one every 1 px)" in line)
    assert sorted(path.name for path in (tmp_path / "out").iterdir()) == [
        "rug.ply", "rug_albedo.png", "rug_height.exr", "rug_normal.png"]

    error = shadecut.angular_error_map(normal_map(tmp_path / "out" / "rug_normal.png"), truth)
    assert error.mean() < NORMAL_STEP_DEGREES and error.max() < 4 * NORMAL_STEP_DEGREES, (error.mean(), error.max())
    albedo = shadecut.load_image(tmp_path / "out" / "rug_albedo.png")
    assert albedo.color_space == "srgb" and albedo.has_alpha and albedo.mask.all()
    np.testing.assert_allclose(albedo.colour, paint, atol=1e-4)  # a few 16-bit steps
    depth, mask = height_exr(tmp_path / "out" / "rug_height.exr")
    assert mask.all() and np.ptp(depth) > 1.0


def test_a_set_takes_its_lights_from_lights_txt(tmp_path):
    """Photographs named without a side: lights.txt gives each its light, as a direction (any length)
    or a side; comments and blank lines are left out."""
    lights = {"shot 1.png": (0.0, 2.0, 2.0), "shot 2.png": (-1.0, 0.0, 1.0), "shot 3.png": "below",
              "shot 4.png": "right"}
    directions = [shadecut.light_from_side(light) if isinstance(light, str) else light for light in lights.values()]
    truth, _ = painted_bumps(tmp_path / "in" / "plaster", zip(lights, directions))
    (tmp_path / "in" / "plaster" / "lights.txt").write_text(
        "# file, then x y z toward the lamp or a side\n\n"
        + "".join(f"{name} {light if isinstance(light, str) else ' '.join(map(str, light))}\n"
                  for name, light in lights.items()))
    run = batch(tmp_path / "in", tmp_path / "out")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "[1/1] plaster/: " in run.stdout and "lights from lights.txt" in run.stdout
    assert "skipped" not in run.stdout  # lights.txt is the set's own file
    error = shadecut.angular_error_map(normal_map(tmp_path / "out" / "plaster_normal.png"), truth)
    assert error.mean() < NORMAL_STEP_DEGREES and error.max() < 4 * NORMAL_STEP_DEGREES, (error.mean(), error.max())


def test_a_set_of_four_that_names_no_light_has_them_estimated(tmp_path):
    """Four photographs lit from around at a side's slant, named without a side and without
    lights.txt: the library estimates their lights (its default hint is that slant), so the normals
    are the truth to within what the estimate's 1/20-degree turn and the 16-bit map allow."""
    photographs = [(f"shot_{k}.png", shadecut.light_from_side(side)) for k, side in enumerate(("top", "left", "bottom", "right"))]
    truth, _ = painted_bumps(tmp_path / "in" / "wall", photographs)
    run = batch(tmp_path / "in", tmp_path / "out")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "[1/1] wall/: " in run.stdout and "lights from the photographs (estimated)" in run.stdout
    error = shadecut.angular_error_map(normal_map(tmp_path / "out" / "wall_normal.png"), truth)
    assert error.mean() < 0.2, error.mean()


def test_a_set_without_its_lights_is_named_and_the_rest_is_still_done(tmp_path):
    """Each bad set gets an error line saying what is missing, nothing is written for it, the flat
    image beside them is done and the exit code is 1."""
    in_dir = tmp_path / "in"
    side_lights = [(f"rug_{side}.png", shadecut.light_from_side(side)) for side in SIDES[:3]]
    painted_bumps(in_dir / "rug", side_lights + [("rug_3.png", shadecut.light_from_side("right"))])
    painted_bumps(in_dir / "none", [(f"n_{k}.png", shadecut.light_from_side(side)) for k, side in enumerate(SIDES[:3])])
    painted_bumps(in_dir / "one", side_lights[:1])
    painted_bumps(in_dir / "typo", side_lights[:2])
    (in_dir / "typo" / "lights.txt").write_text("rug_above.png above\nrug_below.png 0 -1\n")
    sphere_png(in_dir / "ball.png", (1.0, 0.0, 1.0))
    run = batch(in_dir, tmp_path / "out")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "Traceback" not in run.stderr
    assert "[1/5] ball.png: " in run.stdout and "1 of 5 image(s) and set(s) done" in run.stdout
    assert "[2/5] none/: error: estimating the lights needs 4 or more photographs, got 3" in run.stderr
    assert "[3/5] one/: error: one photograph (rug_above.png): a set needs two or more" in run.stderr
    assert ("[4/5] rug/: error: no light for rug_3.png: name it rug_3_<side>.png (a side: top, bottom, "
            in run.stderr and "or list it in lights.txt" in run.stderr)
    assert "[5/5] typo/: error: lights.txt line 2: 'rug_below.png 0 -1' is neither 'file x y z' nor 'file side'" \
        in run.stderr
    assert sorted(path.name for path in (tmp_path / "out").iterdir()) == [
        "ball.ply", "ball_height.exr", "ball_normal.png"]


def test_photographs_of_different_sizes_get_the_librarys_error(tmp_path):
    """The library counts the photographs of its list; the line names the file it means."""
    in_dir = tmp_path / "in"
    painted_bumps(in_dir / "mixed", [("m_above.png", shadecut.light_from_side("above"))], size=64)
    scene = synthetic.bumps(light=shadecut.light_from_side("left"), size=48)
    shadecut.save_image(in_dir / "mixed" / "m_left.png", scene.image)
    run = batch(in_dir, tmp_path / "out")
    assert run.returncode == 1, run.stdout + run.stderr
    assert ("[1/1] mixed/: error: photograph 2 (m_left.png) is 48 x 48 pixels but the first is 64 x 64; several "
            "photographs must be of one view, all of one size") in run.stderr  # the library's, the file named
    assert list((tmp_path / "out").iterdir()) == []
