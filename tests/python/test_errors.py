"""Bad input raises a clear Python exception, never a crash."""

import os
import re
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

GOOD = np.full((16, 16), 0.5, np.float32)
GOOD[4:12, 4:12] = np.linspace(0.2, 0.9, 8, dtype=np.float32)
LIGHT = (1.0, 0.0, 1.0)


@pytest.mark.parametrize(
    "image, light, kwargs, message",
    [
        (np.zeros((0, 0), np.float32), LIGHT, {}, "at least 2 x 2"),
        (np.ones((1, 1), np.float32), LIGHT, {}, "at least 2 x 2"),
        (np.ones((1, 16), np.float32), LIGHT, {}, "at least 2 x 2"),
        (np.ones((4, 4, 4), np.float32), LIGHT, {}, r"\(H, W\) or \(H, W, 3\)"),
        (np.ones(16, np.float32), LIGHT, {}, r"\(H, W, 3\) RGB"),
        (np.dstack([GOOD, GOOD, -GOOD]), LIGHT, {}, "negative"),
        (GOOD, LIGHT, {"albedo_method": "retinex", "retinex_rim": -1}, "retinex_rim"),
        (GOOD, LIGHT, {"albedo_method": "retinex", "retinex_shadow": -0.01}, "retinex_shadow"),
        (GOOD, LIGHT, {"albedo_method": "retinex", "retinex_passes": 0}, "retinex_passes"),
        (GOOD, LIGHT, {"albedo_method": "retinex", "retinex_chroma_edge": float("nan")}, "retinex_chroma_edge"),
        (np.where(GOOD > 0.6, np.nan, GOOD), LIGHT, {}, "NaN or infinite"),
        (np.where(GOOD > 0.6, np.inf, GOOD), LIGHT, {}, "NaN or infinite"),
        (GOOD, LIGHT, {"mask": np.ones((15, 16), bool)}, "mask is 15 x 16"),
        (GOOD, LIGHT, {"mask": np.zeros((16, 16), bool)}, "selects no pixel"),
        (GOOD, (0.0, 0.0, 0.0), {}, "zero vector"),
        (GOOD, (1.0, 0.0, 0.0), {}, "horizon"),
        (GOOD, (1.0, 0.0, -1.0), {}, "horizon"),
        (GOOD, (1.0, 0.0), {}, "3 components"),
        (np.zeros((16, 16), np.float32), LIGHT, {}, "dark everywhere"),
        (GOOD, LIGHT, {"labels": 3}, "labels must be"),
        (GOOD, LIGHT, {"method": "magic"}, "unknown method"),
        (GOOD, LIGHT, {"integrator": "magic"}, "integrator"),
        (GOOD, LIGHT, {"albedo": -1.0}, "albedo"),
        # Without a light the estimator used to read a bad albedo as "the image is dark everywhere".
        (GOOD, None, {"albedo": -1.0}, r"the albedo must be finite and > 0; got -1"),
        (GOOD, None, {"albedo": float("nan")}, r"the albedo must be finite and > 0; got nan"),
        (GOOD, None, {"albedo": 0.0, "albedo_method": "retinex"}, r"the albedo must be finite and > 0"),
        # NaN or -1 silently stopped the shadow filling, 1 or more marked every pixel as shadow.
        (GOOD, LIGHT, {"shadow_threshold": float("nan")}, r"shadow_threshold must be in \[0, 1\)"),
        (GOOD, LIGHT, {"shadow_threshold": -1.0}, r"shadow_threshold must be in \[0, 1\)"),
        (GOOD, LIGHT, {"shadow_threshold": 1.0}, r"shadow_threshold must be in \[0, 1\)"),
        (GOOD, LIGHT, {"shadow_threshold": float("inf")}, r"shadow_threshold must be in \[0, 1\); got inf$"),
        (GOOD, LIGHT, {"highlight_threshold": float("nan")}, "highlight_threshold must be finite"),
        (GOOD, LIGHT, {"highlight_threshold": float("inf")}, "highlight_threshold must be finite"),
        (GOOD, LIGHT, {"viscosity_weight": -1e300}, r"viscosity_weight must be finite and >= 0; got -1e\+300$"),
        (-GOOD, LIGHT, {}, "negative"),
    ],
)
def test_bad_input_raises_value_error(image, light, kwargs, message):
    with pytest.raises(ValueError, match=message):
        shadecut.reconstruct(image, light, **kwargs)


def test_missing_or_unreadable_files_raise_os_error(tmp_path):
    with pytest.raises(OSError, match="missing.png"):
        shadecut.load_image(tmp_path / "missing.png")
    garbage = tmp_path / "garbage.png"
    garbage.write_bytes(b"not an image at all")
    with pytest.raises(OSError):
        shadecut.load_image(garbage)


def test_other_functions_check_their_shapes():
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        shadecut.integrate(np.zeros((4, 4), np.float32))
    with pytest.raises(ValueError):
        shadecut.angular_error(np.zeros((4, 4, 3)), np.zeros((5, 4, 3)))
    with pytest.raises(ValueError, match="mesh"):
        shadecut.save_mesh("/tmp/x.stl", np.zeros((4, 4), np.float32))


def test_back_facing_normals_are_refused_by_integrate_until_folded():
    normals = np.zeros((6, 7, 3), np.float32)
    normals[..., 2] = 1.0
    normals[2, 3] = (-0.6, 0.0, -0.8)
    with pytest.raises(ValueError, match=r"pixel \(2, 3\) faces away from the viewer"):
        shadecut.integrate(normals)
    folded, count = shadecut.fold_back_facing(normals)
    assert count == 1
    np.testing.assert_array_equal(folded[2, 3], (-1.0, 0.0, 0.0))
    np.testing.assert_array_equal(np.delete(folded.reshape(-1, 3), 2 * 7 + 3, axis=0),
                                  np.delete(normals.reshape(-1, 3), 2 * 7 + 3, axis=0))
    assert np.isfinite(shadecut.integrate(folded)).all()


def test_an_unknown_option_is_a_type_error_that_lists_the_options():
    with pytest.raises(TypeError, match="unknown option 'maxflow'.*data_weight"):
        shadecut.reconstruct(GOOD, LIGHT, maxflow="grid")
    with pytest.raises(TypeError, match="unknown option 'lables'"):
        shadecut.ReconstructOptions(lables=12)


def test_an_option_of_the_wrong_type_names_the_option_and_the_value():
    with pytest.raises(TypeError, match=r"option 'labels' cannot be '36' \(str\); it is now 36"):
        shadecut.reconstruct(GOOD, LIGHT, labels="36")
    with pytest.raises(TypeError, match=r"option 'coarse_to_fine_radius' cannot be 2.5 \(float\)"):
        shadecut.ReconstructOptions().replace(coarse_to_fine_radius=2.5)
    options = shadecut.ReconstructOptions()
    for name, value, shown in [("seamless", "yes", r"'yes' \(str\); it is now False"),
                               ("data_weight", None, r"None \(NoneType\); it is now 0.2"),
                               ("integrator", 3.5, r"3.5 \(float\); it is now <Integrator.poisson: 0>")]:
        with pytest.raises(TypeError, match=f"option '{name}' cannot be {shown}"):
            setattr(options, name, value)
    options.tolerance = None  # an option that may be unset takes None


def test_options_given_as_a_dict_say_how_to_give_them():
    with pytest.raises(TypeError, match=r"options must be a ReconstructOptions, not a dict: "
                                        r"options=ReconstructOptions\(labels=24\), or the fields as keywords"):
        shadecut.reconstruct(GOOD, LIGHT, options={"labels": 24})


def test_a_max_pixels_beyond_any_image_is_no_limit(tmp_path):
    """2**70 gave pybind11's "incompatible function arguments": no header can declare that many pixels."""
    png_declaring(tmp_path / "normal.png", 4, 4)
    assert shadecut.load_image(tmp_path / "normal.png", max_pixels=2**70).image.shape == (4, 4)


def test_a_depth_file_that_is_not_text_is_named():
    """synthetic.mozart on a PNG raised UnicodeDecodeError from numpy's text reader."""
    from shadecut import synthetic

    picture = Path(__file__).resolve().parents[2] / "docs" / "addon_screenshot.png"
    with pytest.raises(ValueError, match=f"{picture} is not a text file of numbers"):
        synthetic.mozart(picture)


def test_a_falsy_progress_answer_cancels_and_none_goes_on():
    for answer in (False, 0, "", []):
        with pytest.raises(shadecut.Cancelled):
            shadecut.reconstruct(GOOD, LIGHT, progress=lambda fraction, stage: answer)
    shadecut.reconstruct(GOOD, LIGHT, progress=lambda fraction, stage: None)


def png_declaring(path, width: int, height: int) -> None:
    """A tiny, valid-looking PNG whose header claims width x height pixels (its data is 4 x 4)."""
    small = path.with_name("small.png")
    shadecut.save_image(small, np.full((4, 4), 0.5, np.float32))
    data = bytearray(small.read_bytes())
    ihdr = data.index(b"IHDR")
    data[ihdr + 4:ihdr + 12] = struct.pack(">II", width, height)
    data[ihdr + 17:ihdr + 21] = struct.pack(">I", zlib.crc32(bytes(data[ihdr:ihdr + 17])))
    path.write_bytes(bytes(data))


def test_an_image_declaring_too_many_pixels_is_refused_before_allocating(tmp_path):
    huge = tmp_path / "huge.png"
    png_declaring(huge, 100000, 100000)
    with pytest.raises(OSError, match="declares 100000 x 100000 pixels"):
        shadecut.load_image(huge)
    cli = Path(__file__).resolve().parents[2] / "build" / "native" / "shadecut"
    done = subprocess.run([str(cli), str(huge), "--out", str(tmp_path / "out")], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 2 and "declares 100000 x 100000" in done.stderr
    assert not (tmp_path / "out").exists()
    # The limit is the caller's to set.
    png_declaring(tmp_path / "normal.png", 4, 4)
    assert shadecut.load_image(tmp_path / "normal.png").image.shape == (4, 4)
    with pytest.raises(OSError, match="above the limit of 8"):
        shadecut.load_image(tmp_path / "normal.png", max_pixels=8)


def test_threads_are_bounded_and_shape_errors_name_the_mask_first():
    with pytest.raises(ValueError, match=f"threads must be in 0 .. {shadecut.MAX_THREADS}"):
        shadecut.reconstruct(GOOD, LIGHT, threads=1000)
    normals = np.dstack([np.zeros((16, 16)), np.zeros((16, 16)), np.ones((16, 16))]).astype(np.float32)
    with pytest.raises(ValueError, match="the mask is 15 x 16 but the normal map is 16 x 16"):
        shadecut.angular_error(normals, normals, np.ones((15, 16), bool))
    with pytest.raises(ValueError, match="the mask is 15 x 16 but the normal map is 16 x 16"):
        shadecut.render(normals, LIGHT, 1.0, np.ones((15, 16), bool))
    with pytest.raises(ValueError, match="compared with the albedo"):
        shadecut.reconstruct(GOOD, LIGHT, albedo=1e30)


@pytest.mark.parametrize("call", [
    lambda: shadecut.reconstruct(GOOD.astype(complex), LIGHT),
    lambda: shadecut.render(np.zeros((4, 4, 3), complex), LIGHT),
    lambda: shadecut.estimate_albedo(GOOD.astype(complex)),
    lambda: shadecut.integrate(np.zeros((4, 4, 3), complex)),
])
def test_complex_arrays_are_refused(call):
    with pytest.raises(ValueError, match="complex"):
        call()


def test_bad_paths_and_unwritable_outputs_fail_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="NUL"):
        shadecut.save_image(str(tmp_path / "a\0b.png"), GOOD)
    assert not list(tmp_path.iterdir())
    depth = np.full((4, 4), np.nan, np.float32)
    with pytest.raises(ValueError, match="NaN or infinite inside the mask"):
        shadecut.save_depth(tmp_path / "depth.png", depth)
    (tmp_path / "file").write_text("in the way")
    shadecut.save_image(tmp_path / "in.png", GOOD)
    cli = Path(__file__).resolve().parents[2] / "build" / "native" / "shadecut"
    done = subprocess.run([str(cli), str(tmp_path / "in.png"), "--light", "1,0,1", "--out", str(tmp_path / "file" / "out")],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "is a file, not a folder" in done.stderr


def test_nan_or_zero_normals_inside_the_mask_are_refused():
    normals = np.dstack([np.zeros((8, 8)), np.zeros((8, 8)), np.ones((8, 8))]).astype(np.float32)
    broken = normals.copy()
    broken[3, 4] = np.nan
    with pytest.raises(ValueError, match=r"NaN or infinite values inside the mask, at pixel \(3, 4\)"):
        shadecut.render(broken, LIGHT)
    with pytest.raises(ValueError, match="NaN or infinite"):
        shadecut.angular_error(normals, broken)
    zero = normals.copy()
    zero[2, 2] = 0.0
    with pytest.raises(ValueError, match=r"zero normal at pixel \(2, 2\)"):
        shadecut.integrate(zero)
    outside = np.ones((8, 8), bool)
    outside[3, 4] = False  # a NaN outside the mask is never read
    assert shadecut.render(broken, LIGHT, 1.0, outside)[3, 4] == 0.0


def test_a_folder_or_a_missing_file_is_named_as_such(tmp_path):
    with pytest.raises(OSError, match="it is a folder"):
        shadecut.load_image(tmp_path)
    with pytest.raises(OSError, match="no such file"):
        shadecut.load_image(tmp_path / "missing.png")


def test_a_named_pipe_or_a_device_is_refused_without_reading_it(tmp_path):
    """A FIFO blocked load_image forever and /dev/zero made it spin: neither is a regular file. Run in
    a child process, so that a regression fails on its time limit instead of hanging the suite."""
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    for path, kind in ((fifo, "a named pipe (FIFO)"), ("/dev/zero", "a character device")):
        code = f"import shadecut\ntry:\n    shadecut.load_image({str(path)!r})\nexcept OSError as e:\n    print(e)"
        completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30,
                                   env={**os.environ, "PYTHONPATH": str(Path(shadecut.__file__).parents[1])})
        assert completed.stdout.strip() == f'cannot read image "{path}": it is {kind}, not a regular file', \
            completed.stdout + completed.stderr

@pytest.mark.parametrize("albedo", [float("nan"), float("inf"), 0.0, -1.0])
def test_estimate_light_refuses_a_bad_albedo_like_reconstruct(albedo):
    for method in shadecut.LIGHT_METHODS:
        with pytest.raises(ValueError, match="the albedo must be finite and > 0"):
            shadecut.estimate_light(GOOD, method=method, albedo=albedo)


def test_a_light_is_not_estimated_from_a_handful_of_pixels():
    """Issue 48, finding 21: a one-pixel mask's light read (0, 0, 1) without a word."""
    scene = synthetic.sphere((1, 0, 1), size=64)
    few = np.zeros_like(scene.mask)
    few[30:33, 40:45] = True  # 15 pixels, all on the sphere
    for method in shadecut.LIGHT_METHODS:
        with pytest.raises(ValueError, match="cannot be estimated from 15 pixels.*at least 16 pixels; give the light"):
            shadecut.estimate_light(scene.image, few, method=method)
    with pytest.raises(ValueError, match="cannot be estimated from 15 pixels"):
        shadecut.reconstruct(scene.image, None, few)
    few[33, 40] = True
    shadecut.estimate_light(scene.image, few)  # sixteen are read
    assert shadecut.reconstruct(scene.image, scene.light, few).mask.sum() == 15 + 1


def test_the_default_pixel_limit_is_the_core_s_for_the_add_on():
    """The add-on ships _core without _imageio; the limit load_image applies is readable from both."""
    from shadecut import _core, _imageio
    assert _core.DEFAULT_MAX_PIXELS == _imageio.DEFAULT_MAX_PIXELS == 2**28


@pytest.mark.parametrize("name", ["method", "integrator", "scene", "albedo_method"])
def test_an_enum_option_given_none_names_the_option(name):
    """pybind11 took the enum's failed cast of None for a wrong overload: "incompatible function arguments"."""
    with pytest.raises(TypeError, match=f"shadecut: option '{name}' cannot be None"):
        shadecut.reconstruct(GOOD, LIGHT, **{name: None})


@pytest.mark.parametrize("call", [
    lambda: shadecut.render(np.zeros((2**31, 0, 3), np.float32), LIGHT),
    lambda: shadecut.render(np.zeros((2**31, 0), np.float32), LIGHT),
    lambda: shadecut.fold_back_facing(np.zeros((2**31, 0, 3), np.float32)),
    lambda: shadecut.erode_mask(np.zeros((2**31, 0), bool), 1),
    lambda: shadecut.mask_components(np.zeros((2**31, 0), bool)),
])
def test_a_side_beyond_a_32_bit_count_is_refused_not_wrapped(call):
    """An empty array can have 2^31 rows; the core counts them in int, where they wrapped negative."""
    with pytest.raises(ValueError, match="2147483648 x 0 pixels; a side may have at most 2147483647"):
        call()


UNDER_A_MEMORY_CAP = """
import resource, sys
import numpy as np
resource.setrlimit(resource.RLIMIT_AS, (int(sys.argv[1]), int(sys.argv[1])))
import shadecut
from shadecut import synthetic
small = synthetic.sphere((1, 0, 1), 64)
shadecut.reconstruct(small.image, small.light, small.mask)  # fits: runs as usual
image = np.full((8192, 8192), 0.5, np.float32)
stages = []
try:
    shadecut.reconstruct(image, (1, 0, 1), progress=lambda fraction, stage: stages.append(stage) or True)
except ValueError as error:
    print(f"{len(stages)} {error}")
"""


def test_a_call_too_large_for_the_memory_it_may_use_is_refused_at_once():
    """8192 x 8192 under a memory cap ran 45 s into an allocation failure; the peak memory is now
    estimated first (docs/benchmarks.md, "Memory") and the call refused, naming both figures."""
    cap = 3 * 2**30  # 3 GB of address space: 8192^2 pixels need about 11 GB
    done = subprocess.run([sys.executable, "-c", UNDER_A_MEMORY_CAP, str(cap)], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    assert done.returncode == 0, done.stderr
    stages_begun, message = done.stdout.split(" ", 1)
    assert stages_begun == "0"  # refused before any stage's work, not after running out
    needed, available = re.search(r"needs about ([\d.]+) GB for 8192 x 8192 pixels, but only ([\d.]+) GB can be", message).groups()
    assert float(needed) > 10 and float(available) < 3 and "max_pixels" in message


def test_options_outside_what_makes_sense_are_refused_with_their_range():
    """Issue 48: findings 5 (a paint line width that allocated gigabytes), 11 (a detail size that left a
    depth of 0), 21 (retinex_passes=10**9 ran until cancelled, max_slope=1e-300 left a depth of 0), each
    refused with the allowed range."""
    scene = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    for overrides, message in [
        ({"paint_line_width": 46341, "scene": "relief"}, r"paint_line_width must be in 0 \.\. 1024; got 46341"),
        ({"detail_size": 2.0, "scene": "relief"}, r"detail_size must be 0 .* or at least 5 pixels"),
        ({"retinex_passes": 10**9, "albedo_method": "retinex"}, r"retinex_passes must be in 1 \.\. 10"),
        ({"max_slope": 1e-300}, r"max_slope must be finite and >= 0\.01; got 1e-300"),
    ]:
        with pytest.raises(ValueError, match=message):
            shadecut.reconstruct(scene.image, scene.light, None, **overrides)


def test_integrate_refuses_a_slope_clamp_that_flattens_every_surface():
    scene = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    with pytest.raises(ValueError, match=r"max_slope must be finite and at least 0\.01 .* a flat surface\); got 1e-300"):
        shadecut.integrate(scene.normals, scene.mask, max_slope=1e-300)
    assert shadecut.integrate(scene.normals, scene.mask, max_slope=0.01).max() > 0


@pytest.mark.parametrize("name, value", [("refine", None), ("cut_out", 2), ("threads", True), ("labels", 36.0),
                                         ("data_weight", False), ("fill_shadows", "yes")])
def test_an_option_takes_only_values_of_its_kind(name, value):
    """Issue 48, finding 15: refine=None silently meant False, cut_out=2 and threads=True were taken."""
    with pytest.raises(TypeError, match=f"option '{name}' cannot be"):
        shadecut.ReconstructOptions(**{name: value})
    assert shadecut.ReconstructOptions(refine=np.bool_(False)).refine is False
    assert shadecut.ReconstructOptions(labels=np.int64(24)).labels == 24


def test_a_progress_answer_without_a_truth_value_is_an_error_not_a_cancel():
    """Issue 48, finding 19: a callback returning an array was reported as 'cancelled by the callback'."""
    scene = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    with pytest.raises(TypeError, match="the progress callback returned array"):
        shadecut.reconstruct(scene.image, scene.light, scene.mask, progress=lambda fraction, stage: np.ones(2))


def test_wrong_kinds_of_argument_get_a_sentence_not_a_signature_dump():
    """Issue 48, finding 18: pybind11's 'incompatible function arguments' dumps, a bare StopIteration and
    an AttributeError, each now a sentence naming the argument and what it takes."""
    scene = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    cases = [
        (lambda: shadecut.reconstruct(scene.image, scene.light, scene.mask, albedo=np.ones((32, 32))),
         TypeError, "albedo is one number .* albedo_method='retinex'"),
        (lambda: shadecut.reconstruct(scene.image, scene.light, scene.mask, albedo="0.5"), TypeError, "albedo is one number"),
        (lambda: shadecut.reconstruct(scene.image, scene.light, scene.mask, progress=5), TypeError, "progress is a function"),
        (lambda: shadecut.erode_mask(scene.mask, 2**40), ValueError, "pixels must be from 0 to"),
        (lambda: shadecut.estimate_albedo(scene.image, scene.mask, window=(0.1, 0.2)), ValueError, "window is three numbers"),
        (lambda: shadecut.cut_out(scene.image, options=shadecut.ReconstructOptions()), TypeError, "must be a CutOutOptions"),
        (lambda: shadecut.vertex_step(scene.mask, -1), ValueError, "max_vertices must be from 1"),
        (lambda: shadecut.estimate_reflectance(scene.image, options={"retinex_rim": 2}), TypeError,
         "must be a ReconstructOptions, not a dict"),
    ]
    for call, kind, message in cases:
        with pytest.raises(kind, match=message):
            call()
    with pytest.raises(ValueError, match="step must be from 1 to"):
        shadecut.save_mesh("never_written.ply", scene.depth, scene.mask, step=2**31)


def test_a_highlight_threshold_below_the_albedo_and_a_flip_of_an_infinite_depth_are_refused():
    """Issue 48, finding 21: highlight_threshold=1e-9 called every pixel a highlight; flip turned an
    infinite depth into NaN everywhere."""
    scene = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    with pytest.raises(ValueError, match=r"highlight_threshold must be <= 0 \(never\) or at least 1"):
        shadecut.reconstruct(scene.image, scene.light, scene.mask, highlight_threshold=1e-9)
    depth = scene.depth.copy()
    depth[16, 16] = np.inf
    with pytest.raises(ValueError, match=r"NaN or infinite inside the mask, at pixel \(16, 16\)"):
        shadecut.flip(depth, scene.normals, scene.mask)
