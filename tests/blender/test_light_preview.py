"""The light preview beside the Light setting: a Lambertian sphere whose bright side faces the light."""

import math

import bpy
import numpy as np
import pytest
from mathutils import Euler

import shadecut
from shadecut.blender import light_preview


def brightest_offset(rgba):
    """Where the preview is brightest, from its centre in units of the sphere's radius: (right, up)."""
    shade = rgba[..., 0] * (rgba[..., 3] > 0.5)
    # The centre of the brightest pixels: a preview keeps 8 bits, so the peak is a small plateau.
    rows, cols = np.nonzero(shade >= shade.max() - 1.5 / 255)  # row 0 at the bottom
    row, col = rows.mean(), cols.mean()
    centre, radius = (shade.shape[0] - 1) / 2, 0.45 * shade.shape[0]
    return np.array([col - centre, row - centre]) / radius


@pytest.mark.parametrize("light", [(1, 0, 1), (-1, 0, 1), (0, 1, 1), (0, -1, 1), (0.6, 0.5, 1.0), (0, 0, 1)])
def test_the_brightest_point_lies_toward_the_light(light):
    rgba = light_preview.sphere_pixels(np.array(light) / np.linalg.norm(light))
    assert rgba.shape == (light_preview.SIZE, light_preview.SIZE, 4)
    unit = np.array(light) / np.linalg.norm(light)
    # On a Lambertian sphere the brightest point is where the normal is the light: (x, y) of it.
    np.testing.assert_allclose(brightest_offset(rgba), unit[:2], atol=0.08)


def test_the_panel_shows_the_typed_direction_and_follows_a_sun(addon):
    settings = bpy.context.scene.shadecut
    assert light_preview.panel_light(bpy.context, settings) is None  # Estimate: nothing to show
    settings.light_source, settings.light_direction = "DIRECTION", (0.0, 2.0, 2.0)
    light = light_preview.panel_light(bpy.context, settings)
    np.testing.assert_allclose(light, (0.0, math.sqrt(0.5), math.sqrt(0.5)), atol=1e-6)
    icon = light_preview.preview_icon(light)
    preview = light_preview._state["collection"]["light"]
    assert preview.image_size[:] == (light_preview.SIZE, light_preview.SIZE)
    pixels = np.empty(light_preview.SIZE ** 2 * 4, np.float32)
    preview.image_pixels_float.foreach_get(pixels)
    np.testing.assert_allclose(brightest_offset(pixels.reshape(light_preview.SIZE, light_preview.SIZE, 4)),
                               light[:2], atol=0.08)
    assert light_preview.preview_icon(light) == icon

    # A Sun seen from the top view, aimed from the +X side: the light comes from the right.
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.rotation_euler = Euler((0.0, math.radians(45), 0.0))
    bpy.context.collection.objects.link(sun)
    bpy.context.view_layer.update()
    settings.light_source = "OBJECT"  # no Sun picked: the scene's only one
    light = light_preview.panel_light(bpy.context, settings)
    np.testing.assert_allclose(light, (math.sqrt(0.5), 0.0, math.sqrt(0.5)), atol=1e-6)
    light_preview.preview_icon(light)
    preview.image_pixels_float.foreach_get(pixels)
    np.testing.assert_allclose(brightest_offset(pixels.reshape(light_preview.SIZE, light_preview.SIZE, 4)),
                               light[:2], atol=0.08)
    sun.rotation_euler = Euler((0.0, math.radians(180), 0.0))  # shining up from below: no preview
    bpy.context.view_layer.update()
    assert light_preview.panel_light(bpy.context, settings) is None


def test_the_panel_shows_a_light_named_by_its_side(addon):
    settings = bpy.context.scene.shadecut
    settings.light_source = "SIDE"
    assert light_preview.panel_light(bpy.context, settings) is None  # no side picked yet
    settings.light_side = "top-left"
    light = light_preview.panel_light(bpy.context, settings)
    np.testing.assert_allclose(light, shadecut.light_from_side("top-left"), atol=1e-12)
    assert light[0] < 0 < light[1]
