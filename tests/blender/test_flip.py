"""Issue 27 in the add-on: a ball lit from the camera comes back a dome, the reconstruction says when
the image could not tell a dome from a hollow, and Flip turns the result over in one undo step."""

import bpy
import numpy as np
import pytest

import shadecut
from shadecut import synthetic
from shadecut.blender import reconstruct_operator
from shadecut.blender.flip_operator import RESULT_PROPERTY
from shadecut.blender.result import NORMAL_TEXTURE


class Reports:
    """Stands in for the operator: keeps every report."""

    def __init__(self):
        self.all = []

    def report(self, kind, message):
        self.all.append((kind, message))

    def warnings(self):
        return [message for kind, message in self.all if "WARNING" in kind]


def heights(obj) -> np.ndarray:
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def dome_rise(obj) -> float:
    """How much higher the result's middle is than its rim (scene units): > 0 for a dome."""
    co = heights(obj)
    radial = np.hypot(co[:, 0] - co[:, 0].mean(), co[:, 1] - co[:, 1].mean())
    return float(co[radial < 0.2 * radial.max(), 2].mean() - co[radial > 0.9 * radial.max(), 2].mean())


def image_of(path, light):
    scene = synthetic.sphere(light=light, size=96)
    shadecut.save_image(path, scene.image, scene.mask)
    return bpy.data.images.load(str(path))


def reconstructed(image, light_source="ESTIMATE", direction=(0.0, 0.0, 1.0)) -> tuple[bpy.types.Object, Reports]:
    settings = bpy.context.scene.shadecut
    settings.image = image
    settings.light_source = light_source
    if light_source == "DIRECTION":
        settings.light_direction = direction
    settings.normal_map = True
    job = reconstruct_operator.prepare_job(bpy.context)
    job.run()
    reports = Reports()
    assert reconstruct_operator.finish_job(reports, bpy.context, job) == {"FINISHED"}
    return bpy.context.active_object, reports


def test_a_ball_lit_from_the_camera_comes_back_a_dome_with_a_warning(addon, tmp_path):
    obj, reports = reconstructed(image_of(tmp_path / "frontal.png", (0.0, 0.0, 1.0)))
    assert obj.get(RESULT_PROPERTY)
    assert dome_rise(obj) > 0.2 * (heights(obj)[:, 2].max() - heights(obj)[:, 2].min())
    assert [message for message in reports.warnings() if "inversion" in message and "Flip" in message]


def test_no_warning_where_the_image_tells(addon, tmp_path):
    obj, reports = reconstructed(image_of(tmp_path / "oblique.png", (1.0, 0.0, 1.0)), "DIRECTION", (1.0, 0.0, 1.0))
    assert dome_rise(obj) > 0
    assert reports.warnings() == []


def normal_map_pixels(obj) -> np.ndarray:
    image = obj.active_material.node_tree.nodes[NORMAL_TEXTURE].image
    pixels = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(-1, 4)


def test_flip_turns_the_result_over_and_undo_brings_it_back(addon, tmp_path):
    """Background mode pushes no undo step of its own (see test_apply_maps): the flags are checked,
    and undoing past the operator restores the heights and the normal map."""
    assert {"REGISTER", "UNDO"} <= bpy.types.SHADECUT_OT_flip.bl_options
    image = image_of(tmp_path / "frontal.png", (0.0, 0.0, 1.0))
    settings = bpy.context.scene.shadecut
    settings.image, settings.normal_map = image, True
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    obj = bpy.context.active_object
    name, before, colours = obj.name, heights(obj), normal_map_pixels(obj)
    assert dome_rise(obj) > 0
    bpy.ops.ed.undo_push(message="before flip")
    assert bpy.ops.shadecut.flip() == {"FINISHED"}
    after = heights(obj)
    np.testing.assert_allclose(after[:, 2], before[:, 2].max() - before[:, 2], atol=1e-5)
    np.testing.assert_array_equal(after[:, :2], before[:, :2])
    assert dome_rise(obj) < 0
    flipped = normal_map_pixels(obj)
    np.testing.assert_allclose(flipped[:, :2], 1.0 - colours[:, :2], atol=1e-6)
    np.testing.assert_array_equal(flipped[:, 2:], colours[:, 2:])
    bpy.ops.ed.undo_push(message="after flip")
    bpy.ops.ed.undo()
    obj = bpy.data.objects[name]
    np.testing.assert_array_equal(heights(obj), before)
    np.testing.assert_array_equal(normal_map_pixels(obj), colours)


def test_flip_turns_a_displaced_grid_over(addon, tmp_path):
    settings = bpy.context.scene.shadecut
    settings.image, settings.output = image_of(tmp_path / "frontal.png", (0.0, 0.0, 1.0)), "DISPLACE"
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    obj = bpy.context.active_object
    modifier = obj.modifiers["ShadeCut height"]
    image, mid_level = modifier.texture.image, modifier.mid_level
    heights_before = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(heights_before)
    assert bpy.ops.shadecut.flip() == {"FINISHED"}
    assert modifier.mid_level == pytest.approx(1.0 - mid_level)
    heights_after = np.empty_like(heights_before)
    modifier.texture.image.pixels.foreach_get(heights_after)
    np.testing.assert_allclose(heights_after.reshape(-1, 4)[:, 0], 1.0 - heights_before.reshape(-1, 4)[:, 0], atol=1e-6)
    assert not np.any(heights(obj)[:, 2])  # the grid itself stays flat


def test_flip_needs_a_result(addon):
    bpy.ops.mesh.primitive_plane_add()
    assert not bpy.types.SHADECUT_OT_flip.poll(bpy.context)
    with pytest.raises(RuntimeError):
        bpy.ops.shadecut.flip()
