"""The command-line tool reads an image file and writes depth, normals and a mesh."""

import re
import signal
import subprocess
from pathlib import Path

import numpy as np

import shadecut
from shadecut import synthetic

CLI = Path(__file__).resolve().parents[2] / "build" / "native" / "shadecut"


def run(*args):
    return subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True, timeout=120)


def test_reconstructs_a_png_with_alpha(tmp_path):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    done = run(tmp_path / "sphere.png", "--light", "1,0,1", "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    for name in ("depth.exr", "depth.png", "normals.exr", "normals.png", "mesh.ply"):
        assert (tmp_path / "out" / name).stat().st_size > 0
    depth = shadecut.load_image(tmp_path / "out" / "depth.exr")
    np.testing.assert_array_equal(depth.mask, sphere.mask)  # the alpha channel was the mask


def test_an_object_without_alpha_is_cut_out_of_its_background(tmp_path):
    sphere = synthetic.sphere((0.3, 0.4, 0.866), size=96, albedo=0.8)
    shadecut.save_image(tmp_path / "photo.png", np.where(sphere.mask, sphere.image, 1.0))  # no alpha
    done = run(tmp_path / "photo.png", "--light", "0.3,0.4,0.866", "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    assert "cut out: " in done.stdout
    np.testing.assert_array_equal(shadecut.load_image(tmp_path / "out" / "depth.exr").mask, sphere.mask)
    whole = run(tmp_path / "photo.png", "--light", "0.3,0.4,0.866", "--out", tmp_path / "whole", "--quiet", "--no-cut-out")
    assert whole.returncode == 0 and "cut out" not in whole.stdout
    assert shadecut.load_image(tmp_path / "whole" / "depth.exr").mask.all()
    rng = np.random.default_rng(0)
    shadecut.save_image(tmp_path / "texture.png", rng.uniform(0.2, 0.9, (48, 48)))
    busy = run(tmp_path / "texture.png", "--light", "0.3,0.4,0.866", "--out", tmp_path / "busy", "--quiet")
    assert busy.returncode == 0 and "cut-out: no plain background" in busy.stdout and "--scene relief" in busy.stdout


def test_an_albedo_below_the_image_is_named(tmp_path):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    low = run(tmp_path / "sphere.png", "--light", "1,0,1", "--albedo", 0.5, "--out", tmp_path / "low", "--quiet")
    assert low.returncode == 0, low.stderr
    assert "albedo: " in low.stdout and "brighter than the albedo given (0.500)" in low.stdout
    right = run(tmp_path / "sphere.png", "--light", "1,0,1", "--albedo", 1, "--out", tmp_path / "right", "--quiet")
    assert right.returncode == 0 and "albedo: " not in right.stdout


def test_without_a_light_it_estimates_one_and_says_which(tmp_path):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=64, albedo=0.8)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    for light_method in shadecut.LIGHT_METHODS:
        done = run(tmp_path / "sphere.png", "--light-method", light_method, "--out", tmp_path / light_method, "--quiet")
        assert done.returncode == 0, done.stderr
        expected, _ = shadecut.estimate_light(shadecut.load_image(tmp_path / "sphere.png").image, sphere.mask,
                                              light_method)
        reported = done.stdout.splitlines()[0]
        assert reported.endswith(f"(estimated by {light_method})")
        used = np.array([float(v) for v in reported.split()[1].split(",")])
        np.testing.assert_allclose(used, expected, atol=1e-4)


def test_bad_arguments_exit_2_with_a_message(tmp_path):
    assert run("--help").returncode == 0
    missing = run(tmp_path / "none.png", "--light", "1,0,1")
    assert missing.returncode == 2 and "none.png" in missing.stderr
    below = run(tmp_path / "none.png", "--light", "1,0,-1")
    assert below.returncode == 2
    bad_estimator = run(tmp_path / "x.png", "--light-method", "pentland")
    assert bad_estimator.returncode == 2 and "unknown light estimator" in bad_estimator.stderr


def test_seamless_relief_tiles_and_an_object_cannot(tmp_path):
    wall = synthetic.bricks((0.6, 0.3, 1.0), size=64)
    shadecut.save_image(tmp_path / "wall.png", wall.image)
    done = run(tmp_path / "wall.png", "--scene", "relief", "--seamless", "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    z = shadecut.load_image(tmp_path / "out" / "depth.exr").image
    seam = max(np.abs(z[:, 0] - z[:, -1]).max(), np.abs(z[0] - z[-1]).max())
    assert seam <= max(np.abs(np.diff(z, axis=1)).max(), np.abs(np.diff(z, axis=0)).max())
    refused = run(tmp_path / "wall.png", "--seamless", "--out", tmp_path / "object", "--quiet")
    assert refused.returncode == 2 and "seamless output is for reliefs" in refused.stderr


def test_the_paper_s_energy_alone_from_the_command_line(tmp_path):
    """--contour-weight 0 --viscosity-weight 0 is reconstruct(contour_weight=0, viscosity_weight=0)."""
    bumps = synthetic.bumps((1.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "bumps.exr", bumps.image)
    image = shadecut.load_image(tmp_path / "bumps.exr").image
    for flags, options in (((), {}), (("--contour-weight", 0, "--viscosity-weight", 0),
                                      {"contour_weight": 0.0, "viscosity_weight": 0.0})):
        out = tmp_path / ("paper" if flags else "default")
        done = run(tmp_path / "bumps.exr", "--light", "1,0,1", "--albedo", 1, "--out", out, "--quiet", *flags)
        assert done.returncode == 0, done.stderr
        expected = shadecut.reconstruct(image, (1.0, 0.0, 1.0), albedo=1.0, **options)
        np.testing.assert_allclose(shadecut.load_image(out / "depth.exr").image, expected.depth, atol=1e-4)
        np.testing.assert_allclose(shadecut.load_image(out / "residual.exr").image, expected.residual, atol=1e-4)
    bad = run(tmp_path / "bumps.exr", "--light", "1,0,1", "--viscosity-weight", -1, "--out", tmp_path / "bad")
    assert bad.returncode == 2 and "viscosity_weight" in bad.stderr


OUTPUTS = ("depth.exr", "depth.png", "normals.exr", "normals.png", "mesh.ply", "albedo.exr", "albedo.png", "residual.exr")


def test_a_write_that_fails_part_way_keeps_every_old_file(tmp_path, file_size_limit):
    """The files were written in place one after another: a full disk part-way left new depth beside
    old normals and a truncated mesh. Now all are written under temporary names and renamed at the
    end, or none. The disk fills just below the mesh's size (the same mask, so the same size)."""
    out = tmp_path / "out"
    for light in ("1,0,1", "0,1,1"):
        sphere = synthetic.sphere(tuple(map(float, light.split(","))), size=64)
        shadecut.save_image(tmp_path / f"{light}.png", sphere.image, sphere.mask)
    assert run(tmp_path / "1,0,1.png", "--light", "1,0,1", "--out", out, "--quiet").returncode == 0
    old = {name: (out / name).read_bytes() for name in OUTPUTS}
    failed = subprocess.run([str(CLI), str(tmp_path / "0,1,1.png"), "--light", "0,1,1", "--out", str(out), "--quiet"],
                            capture_output=True, text=True, timeout=120,
                            preexec_fn=file_size_limit(len(old["mesh.ply"]) - 1))
    assert failed.returncode == 2, failed.stderr
    assert f"wrote none of {', '.join(OUTPUTS)} to {out}" in failed.stderr
    assert "the files there are unchanged" in failed.stderr
    assert {name: (out / name).read_bytes() for name in OUTPUTS} == old
    assert sorted(entry.name for entry in out.iterdir()) == sorted(OUTPUTS)


def test_a_failed_write_removes_the_folders_it_made(tmp_path, file_size_limit):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    failed = subprocess.run([str(CLI), str(tmp_path / "sphere.png"), "--light", "1,0,1", "--quiet",
                             "--out", str(tmp_path / "new" / "out")],
                            capture_output=True, text=True, timeout=120, preexec_fn=file_size_limit(4096))
    assert failed.returncode == 2 and "wrote none of" in failed.stderr, failed.stderr
    assert sorted(entry.name for entry in tmp_path.iterdir()) == ["sphere.png"]


def test_ctrl_c_stops_the_reconstruction_and_writes_nothing(tmp_path):
    """Ctrl+C killed the tool wherever it was; now the reconstruction stops at its next progress
    report, nothing is written and the exit code is the shell's for SIGINT."""
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=512)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    process = subprocess.Popen([str(CLI), str(tmp_path / "sphere.png"), "--light", "1,0,1", "--out",
                                str(tmp_path / "out")], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        first = process.stderr.readline()  # the first progress line: the reconstruction has started
        assert first.rstrip().endswith(b"%"), first
        process.send_signal(signal.SIGINT)
        _, stderr = process.communicate(timeout=30)
    finally:
        process.kill()
    assert process.returncode == 128 + signal.SIGINT, stderr
    assert b"shadecut: interrupted: nothing written" in stderr.splitlines()
    assert not (tmp_path / "out").exists()


def test_arguments_are_read_whole_and_numbers_printed_short(tmp_path):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    image = tmp_path / "sphere.png"
    glued = run(image, "--light", "1x,0,1")
    assert glued.returncode == 2 and "--light takes three numbers" in glued.stderr
    assert run(image, "--light", "1,0,1", "--max-pixels", "99999999999999", "--quiet",
               "--out", tmp_path / "big").returncode == 0
    zero = run(image, "--max-pixels", "0")
    assert zero.returncode == 2 and "--max-pixels takes a whole number from 1 to" in zero.stderr
    empty = run(image, "--out", "")
    assert empty.returncode == 2 and "--out is empty" in empty.stderr
    bright = run(image, "--albedo", "1e300", "--out", tmp_path / "bright")
    assert bright.returncode == 2 and "1e+300" in bright.stderr and len(bright.stderr) < 400, bright.stderr
    # The message starts a line of its own, not the end of the progress line before it.
    assert any(line.startswith("shadecut: ") for line in bright.stderr.split("\n")), bright.stderr


def test_flip_writes_the_other_orientation_and_the_report_says_when_it_is_ambiguous(tmp_path):
    """A ball lit from the camera: the report says the image cannot choose; --flip writes
    shadecut.flip's inversion of the same result."""
    ball = synthetic.sphere((0.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "ball.exr", ball.image, ball.mask)
    loaded = shadecut.load_image(tmp_path / "ball.exr")
    expected = shadecut.reconstruct(loaded.image, (0.0, 0.0, 1.0), loaded.mask, 1.0)
    flipped_depth, _ = shadecut.flip(expected.depth, expected.normals, expected.mask)
    for flags, depth in (((), expected.depth), (("--flip",), flipped_depth)):
        out = tmp_path / ("flipped" if flags else "kept")
        done = run(tmp_path / "ball.exr", "--light", "0,0,1", "--albedo", 1, "--out", out, "--quiet", *flags)
        assert done.returncode == 0, done.stderr
        assert "orientation " + ("flipped; " if flags else "") + "ambiguous" in done.stdout
        np.testing.assert_allclose(shadecut.load_image(out / "depth.exr").image[loaded.mask], depth[loaded.mask], atol=1e-4)
    lit_aside = synthetic.sphere((1.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "aside.exr", lit_aside.image, lit_aside.mask)
    oblique = run(tmp_path / "aside.exr", "--light", "1,0,1", "--albedo", 1, "--out", tmp_path / "oblique", "--quiet")
    assert "orientation read from the image" in oblique.stdout


def test_an_output_named_like_the_input_is_refused_before_anything_is_written(tmp_path):
    """An input named albedo.png in the output folder was replaced by the albedo output (issue 48, 1)."""
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    for name in ("albedo.png", "depth.png", "normals.png"):
        shadecut.save_image(tmp_path / name, sphere.image, sphere.mask)
        before = (tmp_path / name).read_bytes()
        done = run(tmp_path / name, "--light", "1,0,1", "--out", tmp_path, "--quiet")
        assert done.returncode == 2 and f"would replace the input image" in done.stderr, done.stderr
        assert (tmp_path / name).read_bytes() == before
        (tmp_path / name).unlink()
    assert sorted(entry.name for entry in tmp_path.iterdir()) == []


def test_every_option_of_the_table_is_a_flag_with_its_default_in_the_help(tmp_path):
    """The flags and --help are made from the option table: each field is there, and each is read."""
    text = run("--help").stdout
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    for field in shadecut.option_fields():
        flag = "--" + field["name"].replace("_", "-")
        assert f"\n  {flag}" in text and f"[default {field['default_text']}" in text.split(f"\n  {flag}")[1], flag
    attached = run(tmp_path / "sphere.png", "--light=1,0,1", "--labels=24", "--no-refine", "--out", tmp_path / "out",
                   "--quiet")
    assert attached.returncode == 0, attached.stderr
    bad = run(tmp_path / "sphere.png", "--light", "1,0,1", "--labels", "3", "--quiet", "--out", tmp_path / "bad")
    assert bad.returncode == 2 and "labels must be in 4 .. 360; got 3" in bad.stderr
    word = run(tmp_path / "sphere.png", "--retinex-passes", "two")
    assert word.returncode == 2 and "retinex_passes takes a whole number; got 'two'" in word.stderr


def test_a_log_gets_a_progress_line_per_step_and_runtime_errors_no_usage_hint(tmp_path):
    """Progress into a file was one line of carriage returns; a disk error ended with the usage hint."""
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=64)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    done = run(tmp_path / "sphere.png", "--light", "1,0,1", "--out", tmp_path / "out")
    assert done.returncode == 0 and "\r" not in done.stderr
    lines = done.stderr.splitlines()
    assert 3 <= len(lines) <= 60 and all(line.rstrip().endswith("%") for line in lines), lines
    with open("/dev/full", "w") as full:
        broken = subprocess.run([str(CLI), str(tmp_path / "sphere.png"), "--light", "1,0,1", "--out", str(tmp_path / "again"),
                                 "--quiet"], stdout=full, stderr=subprocess.PIPE, text=True, timeout=120)
    assert broken.returncode == 2 and "standard output failed" in broken.stderr
    assert "--help" not in broken.stderr
    long_name = run(tmp_path / ("x" * 300 + ".png"), "--light", "1,0,1", "--quiet")
    assert long_name.returncode == 2 and "filesystem error" not in long_name.stderr, long_name.stderr


# Four lights about 40 degrees from the viewer, from the top, the left, the bottom and the right.
AROUND = ["0,0.64,0.77", "-0.64,0,0.77", "0,-0.64,0.77", "0.64,0,0.77"]


def bump_photographs(tmp_path, lights):
    """synthetic.bumps (albedo 0.8) rendered under each light, saved as PNGs: the scene and the paths."""
    scene = synthetic.bumps((0.0, 0.0, 1.0), size=64)
    paths = []
    for k, light in enumerate(lights):
        paths.append(tmp_path / f"photo{k}.png")
        shadecut.save_image(paths[-1], shadecut.render(scene.normals, [float(v) for v in light.split(",")], 0.8, scene.mask))
    return scene, paths


def with_lights(lights):
    return [arg for light in lights for arg in ("--light", light)]


def test_several_photographs_each_with_its_light(tmp_path):
    """Four photographs of one view, a --light each in their order: photometric stereo's surface."""
    lights = AROUND
    scene, paths = bump_photographs(tmp_path, lights)
    done = run(*paths, *with_lights(lights), "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    assert "and 3 more" in done.stdout
    normals = shadecut.load_image(tmp_path / "out" / "normals.exr")
    assert scene.mean_error(np.asarray(normals.colour)) < 2.0
    short = run(*paths, "--light", lights[0], "--out", tmp_path / "short", "--quiet")
    assert short.returncode == 2 and "4 photographs but 1 --light" in short.stderr
    estimated = run(*paths, "--light-slant", "39.7", "--out", tmp_path / "estimated", "--quiet")
    assert estimated.returncode == 0, estimated.stderr
    assert "estimated from the photographs at 39.7 degrees from the viewer" in estimated.stdout
    normals = shadecut.load_image(tmp_path / "estimated" / "normals.exr")
    assert scene.mean_error(np.asarray(normals.colour)) < 2.0


def test_an_objects_outline_turning_the_estimated_lights_is_said(tmp_path):
    """Four photographs of a sphere (its outline the alpha), the first lit from the bottom against
    --first-light-tilt's default top: the line of the lights says the outline turned them."""
    sphere = synthetic.sphere((0.0, 0.0, 1.0), size=64)
    paths = [tmp_path / f"sphere{k}.png" for k in range(4)]
    for path, light in zip(paths, AROUND[2:] + AROUND[:2]):
        shadecut.save_image(path, shadecut.render(sphere.normals, [float(v) for v in light.split(",")], 0.8, sphere.mask),
                            sphere.mask)
    done = run(*paths, "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    assert "turned by half a circle from --first-light-tilt's side: the object's outline showed it inside out" in done.stdout
    hinted = run(*paths, "--first-light-tilt", "-90", "--out", tmp_path / "hinted", "--quiet")
    assert hinted.returncode == 0 and "turned by half a circle" not in hinted.stdout


def test_the_summary_of_several_photographs_says_how_each_pixel_was_decided(tmp_path):
    """Not the single photograph's method and cycles: how many photographs, and how many pixels were
    fitted from three or more, chosen from two, filled. Every pixel of these bumps faces all four
    lights, so four fit them all and two of them leave every pixel a circle of normals."""
    scene, paths = bump_photographs(tmp_path, AROUND)
    pixels = int(scene.mask.sum())
    four = run(*paths, *with_lights(AROUND), "--out", tmp_path / "four", "--quiet")
    assert four.returncode == 0, four.stderr
    assert (f"photometric stereo of 4 photographs, median albedo 0.8: {pixels} pixels fitted from three or more, "
            "0 chosen from two by the graph cut (0 cycles), 0 lit in fewer filled from their neighbours, ") in four.stdout
    two = run(*paths[:2], *with_lights(AROUND[:2]), "--out", tmp_path / "two", "--quiet", "--albedo", "0.8")
    assert two.returncode == 0, two.stderr
    assert (f"photometric stereo of 2 photographs, albedo 0.8: 0 pixels fitted from three or more, {pixels} taken "
            "on the circle the two leave, nearest the two read alone, 0 lit in fewer") in two.stdout
    assert "graph cut (" not in two.stdout  # two photographs' pixels are not the cut's choice between two
    for done in (four, two):
        assert "method graphcut" not in done.stdout and "cycles, 0 moves" not in done.stdout
        assert "orientation" not in done.stdout  # the photographs fix it: there is no inversion to weigh
    flipped = run(*paths, *with_lights(AROUND), "--out", tmp_path / "flipped", "--quiet", "--flip")
    assert flipped.returncode == 0 and "\norientation flipped\n" in flipped.stdout
    one = run(paths[0], "--light", AROUND[0], "--out", tmp_path / "one", "--quiet")
    assert one.returncode == 0, one.stderr
    assert re.search(r"\nmethod graphcut, albedo [0-9.]+, \d+ cycles, \d+ moves, [0-9.e-]+ s\norientation ", one.stdout), one.stdout


def test_the_summary_of_several_photographs_counts_as_the_library_does(tmp_path):
    """A sphere's rim is dark under some of the lights: the line gives the counts the library's stats
    give for the same files."""
    sphere = synthetic.sphere((0.0, 0.0, 1.0), size=64)
    lights = [[float(v) for v in light.split(",")] for light in AROUND]
    paths = [tmp_path / f"sphere{k}.png" for k in range(len(lights))]
    for path, light in zip(paths, lights):
        shadecut.save_image(path, shadecut.render(sphere.normals, light, 0.8, sphere.mask), sphere.mask)
    loaded = [shadecut.load_image(path) for path in paths]
    stats = shadecut.reconstruct([image.image for image in loaded], lights, loaded[0].mask).stats
    fitted = int(loaded[0].mask.sum()) - stats.pair_pixels - stats.single_pixels - stats.dark_pixels
    assert stats.pair_pixels > 0 and fitted > 0
    rim = run(*paths, *with_lights(AROUND), "--out", tmp_path / "rim", "--quiet")
    assert rim.returncode == 0, rim.stderr
    assert (f"{fitted} pixels fitted from three or more, {stats.pair_pixels} chosen from two by the graph cut "
            f"({stats.cycles} cycles), {stats.single_pixels + stats.dark_pixels} lit in fewer filled") in rim.stdout


def test_the_summary_says_where_the_graph_cut_chose_which_of_four_to_leave_out(tmp_path):
    """A shiny sphere under four lights: where one photograph's highlight misses the others' fit, any
    three of the four fit exactly and the graph cut chooses which to leave out; the line counts those
    pixels as the library does, and says nothing of them where no photograph shines."""
    sphere = synthetic.sphere((0.0, 0.0, 1.0), size=64)
    lights = np.array([[float(v) for v in light.split(",")] for light in AROUND])
    paths = [tmp_path / f"shiny{k}.png" for k in range(len(lights))]
    for path, light in zip(paths, lights):
        half = (light / np.linalg.norm(light) + [0.0, 0.0, 1.0])
        highlight = 0.5 * np.clip(sphere.normals @ (half / np.linalg.norm(half)), 0.0, None) ** 50
        image = shadecut.render(sphere.normals, light, 0.6, sphere.mask) + highlight.astype(np.float32) * sphere.mask
        shadecut.save_image(path, image, sphere.mask)
    loaded = [shadecut.load_image(path) for path in paths]
    stats = shadecut.reconstruct([image.image for image in loaded], lights, loaded[0].mask).stats
    assert stats.four_fit_pixels > 0
    shiny = run(*paths, *with_lights(AROUND), "--out", tmp_path / "shiny", "--quiet")
    assert shiny.returncode == 0, shiny.stderr
    assert (f" pixels fitted from three or more ({stats.four_fit_pixels} of them from three of four, the graph cut "
            "choosing which to leave out), ") in shiny.stdout


def test_lights_named_by_their_sides(tmp_path):
    """--light top: a light from that side at the slant a light nobody measured is given."""
    scene = synthetic.bumps((0.0, 0.0, 1.0), size=64)
    sides = ["top", "left", "bottom", "right"]
    paths = []
    for side in sides:
        paths.append(tmp_path / f"{side}.png")
        shadecut.save_image(paths[-1], shadecut.render(scene.normals, shadecut.light_from_side(side), 0.8, scene.mask))
    done = run(*paths, *with_lights(sides), "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    assert scene.mean_error(np.asarray(shadecut.load_image(tmp_path / "out" / "normals.exr").colour)) < 2.0
    # The light used, to four decimals: from the top, (0, sin 45, cos 45), not 4.32978e-17 across.
    assert done.stdout.startswith("light 0,0.7071,0.7071 and 3 more\n"), done.stdout
    wrong = run(paths[0], "--light", "sideways", "--out", tmp_path / "wrong", "--quiet")
    assert wrong.returncode == 2 and "three numbers X,Y,Z or a side such as top; got 'sideways'" in wrong.stderr
    assert "top, bottom, left, right" in run("--help").stdout


def test_the_system_reason_is_given_for_a_path_that_cannot_be_read(tmp_path):
    """Issue 48, finding 20: a symbolic link loop read 'there is no such file', an empty file 'Not a PNG
    file', a light just above the horizon 'S_z <= 0'."""
    (tmp_path / "loop1").symlink_to(tmp_path / "loop2")
    (tmp_path / "loop2").symlink_to(tmp_path / "loop1")
    loop = run(tmp_path / "loop1", "--light", "1,0,1", "--out", tmp_path / "out")
    assert loop.returncode == 2 and "Too many levels of symbolic links" in loop.stderr
    (tmp_path / "empty.png").write_bytes(b"")
    empty = run(tmp_path / "empty.png", "--light", "1,0,1", "--out", tmp_path / "out")
    assert empty.returncode == 2 and "the file is empty (0 bytes)" in empty.stderr
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    shadecut.save_image(tmp_path / "sphere.png", sphere.image, sphere.mask)
    grazing = run(tmp_path / "sphere.png", "--light", "1,0,1e-12", "--out", tmp_path / "out", "--quiet")
    assert grazing.returncode == 2 and "at or below the horizon (0 degrees above it)" in grazing.stderr, grazing.stderr
