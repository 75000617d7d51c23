"""Objects without alpha in the add-on (issue 29, item 5): cut out of a plain background and the mask
shown, a picked Mask used, and a warning that says why when no object is found."""

import bpy
import numpy as np

from shadecut import synthetic
from shadecut.blender import reconstruct_job

LIGHT = (1.0, 0.0, 1.0)


class Reports:
    """Stands in for the operator whose report() a job's finish calls: keeps every report."""

    def __init__(self):
        self.all = []

    def report(self, kind, message):
        self.all.append((next(iter(kind)), message))


def opaque_image(name, grey):
    """A float image without transparency (a photo's pixels), row 0 of ``grey`` at the top."""
    height, width = grey.shape
    image = bpy.data.images.new(name, width, height, alpha=False, float_buffer=True)
    rows = np.ascontiguousarray(grey[::-1], dtype=np.float32)
    image.pixels.foreach_set(np.dstack([rows, rows, rows, np.ones_like(rows)]).ravel())
    return image


def set_up(image):
    settings = bpy.context.scene.shadecut
    settings.image = image
    settings.scene = "object"
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    return settings


def finish(job):
    job.run()
    reports = Reports()
    assert reconstruct_job.finish_job(reports, bpy.context, job) == {"FINISHED"}, reports.all
    return reports


def test_an_object_on_white_without_alpha_is_cut_out_and_its_mask_shown(addon):
    truth = synthetic.sphere(LIGHT, size=96, albedo=0.8)
    set_up(opaque_image("sphere", np.where(truth.mask, truth.image, 1.0)))
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.mask is None  # no alpha: reconstruct() cuts out
    reports = finish(job)
    obj = bpy.context.active_object
    assert len(obj.data.vertices) == np.count_nonzero(truth.mask)  # the object only, not the white
    shown = bpy.data.images["sphere mask"]
    pixels = np.empty(len(shown.pixels), np.float32)
    shown.pixels.foreach_get(pixels)
    np.testing.assert_array_equal(pixels.reshape(96, 96, 4)[::-1, :, 0] > 0.5, truth.mask)
    assert any(kind == "INFO" and "cut out" in message and "'sphere mask'" in message for kind, message in reports.all)


def test_a_picked_mask_is_used(addon):
    truth = synthetic.sphere(LIGHT, size=96, albedo=0.8)
    settings = set_up(opaque_image("sphere", np.where(truth.mask, truth.image, 1.0)))
    half = truth.mask.copy()
    half[:, :48] = False
    settings.mask_image = opaque_image("painted mask", half.astype(np.float32))
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_array_equal(job.mask, half)
    finish(job)
    assert len(bpy.context.active_object.data.vertices) == np.count_nonzero(half)
    assert "sphere mask" not in bpy.data.images


def test_a_textured_image_warns_and_suggests_relief(addon):
    rng = np.random.default_rng(2)
    set_up(opaque_image("gravel", rng.uniform(0.2, 0.9, (64, 64))))
    reports = finish(reconstruct_job.prepare_job(bpy.context))
    warnings = [message for kind, message in reports.all if kind == "WARNING" and "No object cut out" in message]
    assert len(warnings) == 1 and "no plain background" in warnings[0] and "set Subject to Relief" in warnings[0]
    assert len(bpy.context.active_object.data.vertices) == 64 * 64
