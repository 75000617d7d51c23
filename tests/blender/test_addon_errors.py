"""The add-on refusing input or failing in a real Blender: every refusal is a report naming the fix,
and a refused, failed or cancelled run leaves the scene as it was."""

import math
import os
import re
import struct
import zlib

import bpy
import numpy as np
import pytest

import shadecut
from shadecut import _core
from shadecut.blender import image_input, reconstruct_job, reconstruct_operator
from test_addon import LIGHT, add_sun, scene_state


class Reports:
    """Stands in for the operator whose report() a job's finish calls: keeps the last report."""

    def report(self, kind, message):
        self.last = (kind, message)


def sphere_with_its_light(sphere_png):
    """The panel set to the sphere image (not decoded yet) and its light typed in; the settings."""
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(sphere_png[1]))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    return settings


def write_file(path, pixels):
    """Writes (H, W, C) pixels with OpenImageIO (not the library, which may refuse bad images)."""
    import OpenImageIO as oiio

    pixels = np.asarray(pixels)
    height, width, channels = pixels.shape
    kind = "float" if pixels.dtype.kind == "f" else "uint8"
    buffer = oiio.ImageBuf(oiio.ImageSpec(width, height, channels, kind))
    buffer.set_pixels(oiio.ROI(), pixels)
    assert buffer.write(str(path)), buffer.geterror()
    return str(path)


def _bad_file(case, tmp_path):
    """The file of a "file ..." case, for the operator's filepath."""
    grey = np.full((16, 16, 1), 128, np.uint8)
    if case == "file black":
        return write_file(tmp_path / "black.png", np.zeros((16, 16, 1), np.uint8))
    if case == "file transparent":
        return write_file(tmp_path / "clear.png", np.dstack([grey, np.zeros_like(grey)]))
    if case == "file 1 x 1":
        return write_file(tmp_path / "dot.png", grey[:1, :1])
    if case == "file 200 x 1":
        return write_file(tmp_path / "line.png", np.full((1, 200, 1), 128, np.uint8))
    if case == "file NaN":
        pixels = np.full((16, 16, 1), 0.5, np.float32)
        pixels[3, 4] = np.nan
        return write_file(tmp_path / "nan.exr", pixels)
    if case == "file directory":
        (tmp_path / "folder.png").mkdir()
        return str(tmp_path / "folder.png")
    if case == "file not an image":
        (tmp_path / "notes.png").write_text("not an image")
        return str(tmp_path / "notes.png")
    if case == "file missing":
        return str(tmp_path / "missing.png")
    if case == "file declaring 100000 x 100000 pixels":
        return png_declaring(tmp_path / "huge.png", 100000, 100000)
    if case == "file named pipe":
        os.mkfifo(tmp_path / "pipe.png")
        return str(tmp_path / "pipe.png")
    if case == "file device":
        return "/dev/zero"
    if case == "file of the user's, black":
        path = write_file(tmp_path / "black.png", np.zeros((16, 16, 1), np.uint8))
        bpy.data.images.load(path)  # the user's own: a failure must not remove it
        return path
    raise KeyError(case)


def png_declaring(path, width, height):
    """A small PNG whose header claims width x height pixels (its data is 8 x 8)."""
    write_file(path, np.full((8, 8, 1), 128, np.uint8))
    data = bytearray(path.read_bytes())
    data[16:24] = struct.pack(">II", width, height)  # IHDR's width and height, then its CRC
    data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])))
    path.write_bytes(bytes(data))
    return str(path)


def test_a_file_larger_than_memory_allows_is_refused_before_blender_decodes_it(addon, sphere_png, monkeypatch):
    """The panel's image, not decoded yet: its header says how large it is (issue 30: a 250 KB PNG of
    16000 x 16000 pixels took 11.7 GB for 27 s)."""
    settings = sphere_with_its_light(sphere_png)
    monkeypatch.setattr(image_input, "available_memory", lambda: 96 * 96 * image_input.READ_BYTES_PER_PIXEL - 1)
    with pytest.raises(image_input.InputError, match="'sphere.png' is 96 x 96 pixels .* 295 KB, more than the 295 KB"):
        reconstruct_job.prepare_job(bpy.context)
    assert not settings.image.has_data  # refused before Blender read the pixels
    monkeypatch.setattr(image_input, "available_memory", lambda: 96 * 96 * image_input.READ_BYTES_PER_PIXEL)
    assert reconstruct_job.prepare_job(bpy.context).image.shape == (96, 96)


def test_a_file_above_the_library_s_pixel_limit_is_refused_before_blender_decodes_it(addon, tmp_path, monkeypatch):
    """Even with the memory to read it: the add-on refuses what shadecut.load_image would."""
    monkeypatch.setattr(image_input, "available_memory", lambda: 1 << 50)
    side = math.isqrt(_core.DEFAULT_MAX_PIXELS) + 1
    path = png_declaring(tmp_path / "large.png", side, side)
    with pytest.raises(image_input.InputError, match=f"is {side:,} x {side:,} pixels .*, more than the "
                                                     f"{_core.DEFAULT_MAX_PIXELS:,} ShadeCut reads from a file"):
        image_input.check_declared_size("Image file 'large.png'", path)
    image_input.check_declared_size("Image file 'large.png'", png_declaring(tmp_path / "fits.png", side - 1, side - 1))


def _error_setup(case, sphere_png, tmp_path):
    """Sets up a bad input; returns the operator's arguments."""
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    if case.startswith("file"):
        return {"filepath": _bad_file(case, tmp_path)}
    if case != "no image":
        settings.image = bpy.data.images.load(str(path))
    if case == "no pixels":
        gone = tmp_path / "gone.png"
        gone.write_bytes(path.read_bytes())
        settings.image = bpy.data.images.load(str(gone))
        gone.unlink()
        settings.image.reload()
    elif case == "dark":
        settings.image = bpy.data.images.new("dark", 32, 32)
        settings.image.pixels.foreach_set(np.tile([0, 0, 0, 1], 32 * 32).astype(np.float32))
    elif case == "horizon":
        settings.light_direction = (1, 0, 0)
    elif case == "huge light below":
        settings.light_direction = (1e38, 0, -1)
    elif case == "area light":
        lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "AREA"))
        bpy.context.collection.objects.link(lamp)
        settings.light_source, settings.light_object = "OBJECT", lamp
    elif case == "image sequence":
        settings.image.source = "SEQUENCE"
    elif case == "not a sun":
        lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
        bpy.context.collection.objects.link(lamp)
        settings.light_source, settings.light_object = "OBJECT", lamp
    elif case == "no camera":
        settings.light_source, settings.light_object, settings.frame = "OBJECT", add_sun(LIGHT), "CAMERA"
    elif case == "sun below":
        settings.light_source, settings.light_object = "OBJECT", add_sun((1, 0, -1))
    elif case == "sun scaled to zero":
        settings.light_source, settings.light_object = "OBJECT", add_sun(LIGHT)
        settings.light_object.scale = (0.0, 0.0, 0.0)
    elif case == "camera scaled to zero":
        camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
        camera.scale = (1.0, 0.0, 1.0)
        bpy.context.collection.objects.link(camera)
        settings.light_source, settings.light_object = "OBJECT", add_sun(LIGHT)
        settings.frame, settings.camera = "CAMERA", camera
    elif case == "max size 1":
        settings.max_resolution = 1
    elif case == "width NaN":
        settings.width = math.nan
    elif case == "width infinite":
        settings.width = math.inf
    elif case == "depth scale NaN":
        settings.depth_scale = math.nan
    elif case == "depth scale infinite":
        settings.depth_scale = -math.inf
    elif case == "density of the image size":
        settings.auto_density, settings.density = False, truth.mask.shape[1]
    elif case == "density leaving no face":
        settings.auto_density, settings.density = False, truth.mask.shape[1] // 2
    elif case == "max vertices leaving no face":
        settings.image = bpy.data.images.new("band", 64, 64, alpha=True, float_buffer=True)
        pixels = np.zeros((64, 64, 4), np.float32)
        pixels[30:32] = 0.5, 0.5, 0.5, 1.0  # two opaque rows: any step above 1 samples one of them
        settings.image.pixels.foreach_set(pixels.ravel())
        settings.max_vertices = 100
    return {}


@pytest.mark.parametrize("case, message", [
    ("no image", "No image"),
    ("no pixels", "has no pixels"),
    ("dark", "is black"),
    ("horizon", "at or below the horizon"),
    ("huge light below", "The light (1e+38, 0, -1) cannot be used"),
    ("area light", "Light 'Lamp' is an area light"),
    ("image sequence", "Image 'sphere.png' is an image sequence: ShadeCut reconstructs one still image"),
    ("not a sun", "point light"),
    ("no camera", "No camera"),
    ("sun below", "at or below the horizon"),
    ("sun scaled to zero", "Sun 'Sun' (or a parent) is scaled to zero"),
    ("camera scaled to zero", "Camera 'Camera' (or a parent) is scaled to zero"),
    ("max size 1", "Max size 1 px is too small for the 96 x 96 image 'sphere.png' (fewer than 2 x 2 pixels would "
                   "remain): use at least 2"),
    ("width NaN", "Width must be a finite number > 0 (it is nan)"),
    ("width infinite", "Width must be a finite number > 0"),
    ("depth scale NaN", "Depth scale must be a finite number (it is nan)"),
    ("depth scale infinite", "Depth scale must be a finite number"),
    ("density of the image size", "leaves no face on the 96 x 96 working image of 'sphere.png': the largest usable "
                                  "density is"),
    ("density leaving no face", "the largest usable density is"),
    ("max vertices leaving no face", "Vertex limit 100 gives density 2, which leaves no face on the 64 x 64 working "
                                     "image of 'band': raise the Vertex limit, or turn Auto density off and set "
                                     "Density to 1 or less"),
    ("file black", "Image 'black.png' is black"),
    ("file transparent", "Image 'clear.png' is transparent everywhere"),
    ("file 1 x 1", "Image 'dot.png' is 1 x 1 pixels: at least 2 x 2 are needed"),
    ("file 200 x 1", "Image 'line.png' is 200 x 1 pixels: at least 2 x 2 are needed"),
    ("file NaN", "Image 'nan.exr' has 1 NaN or infinite pixel"),
    ("file directory", "folder.png': it is a directory, not an image file"),
    ("file not an image", "notes.png': it is not an image file Blender can read"),
    ("file missing", "missing.png': there is no such file"),
    ("file declaring 100000 x 100000 pixels", "huge.png' is 100,000 x 100,000 pixels (its file's header says so): "
                                              "reading it takes about 320 GB, more than the"),
    ("file named pipe", "pipe.png': it is a named pipe (FIFO), not an image file"),
    ("file device", "Cannot read '/dev/zero': it is a character device, not an image file"),
    ("file of the user's, black", "Image 'black.png' is black"),
])
def test_errors_are_reports_and_leave_the_scene_alone(addon, sphere_png, tmp_path, case, message):
    arguments = _error_setup(case, sphere_png, tmp_path)
    before = scene_state()
    # An ERROR report raises in background mode; CANCELLED is the operator's result behind it.
    with pytest.raises(RuntimeError, match=re.escape(message)) as raised:
        bpy.ops.shadecut.reconstruct(**arguments)
    assert "Traceback" not in str(raised.value)
    assert str(raised.value).count("Cannot read") <= 1  # said once, not repeated
    assert scene_state() == before


def test_errors_return_cancelled(addon, sphere_png, tmp_path):
    """The operator's own result for a refused input, seen without bpy.ops (which raises)."""
    settings = bpy.context.scene.shadecut
    settings.light_source = "DIRECTION"
    settings.auto_density, settings.density = False, 96

    class Operator(Reports):
        filepath, _interactive = str(sphere_png[1]), False

    operator = Operator()
    before = scene_state()
    assert reconstruct_operator.SHADECUT_OT_reconstruct.execute(operator, bpy.context) == {"CANCELLED"}
    assert operator.last[0] == {"ERROR"} and "largest usable density" in operator.last[1]
    assert scene_state() == before


def test_a_failed_job_removes_the_image_it_loaded(addon, sphere_png):
    truth, path = sphere_png
    bpy.context.scene.shadecut.light_source = "DIRECTION"
    before = scene_state()
    job = reconstruct_job.prepare_job(bpy.context, str(path))
    assert job.created_image and job.source_image.name in bpy.data.images
    job.error = ValueError("refused by the core")

    assert reconstruct_job.finish_job(Reports(), bpy.context, job) == {"CANCELLED"}
    assert scene_state() == before


def test_a_mesh_without_faces_is_refused_before_anything_is_made(addon):
    from shadecut.blender.mesh import MeshError, depth_mesh

    before = scene_state()
    mask = np.zeros((8, 8), bool)
    mask[::2, ::2] = True  # no four masked neighbours anywhere
    with pytest.raises(MeshError, match="no face"):
        depth_mesh("holes", np.zeros((8, 8), np.float32), mask)
    with pytest.raises(MeshError, match="not be finite"):
        depth_mesh("huge", np.full((8, 8), 1e30, np.float32), np.ones((8, 8), bool), depth_scale=1e30)
    assert scene_state() == before


def test_cancelling_leaves_nothing_behind(addon, sphere_png):
    sphere_with_its_light(sphere_png)
    job = reconstruct_job.prepare_job(bpy.context)
    job.cancel = True  # what Esc sets while the worker thread runs
    job.run()
    assert isinstance(job.error, shadecut.Cancelled)
    before = scene_state()
    reports = Reports()
    assert reconstruct_job.finish_job(reports, bpy.context, job) == {"CANCELLED"}
    assert "cancelled" in reports.last[1]
    assert scene_state() == before


def test_the_worker_thread_gives_the_synchronous_result(addon, sphere_png):
    import threading

    sphere_with_its_light(sphere_png)
    threaded, direct = reconstruct_job.prepare_job(bpy.context), reconstruct_job.prepare_job(bpy.context)
    worker = threading.Thread(target=threaded.run)
    worker.start()
    worker.join()
    direct.run()
    assert threaded.error is None and threaded.fraction == 1.0
    np.testing.assert_array_equal(threaded.result.depth, direct.result.depth)


def test_file_chosen_in_the_browser(addon, sphere_png):
    truth, path = sphere_png
    bpy.context.scene.shadecut.light_source = "DIRECTION"
    assert bpy.ops.shadecut.reconstruct(filepath=str(path)) == {"FINISHED"}
    assert len(bpy.context.active_object.data.vertices) == np.count_nonzero(truth.mask)
