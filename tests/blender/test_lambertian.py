"""Lambertian renders by Cycles (shadecut.blender.lambertian) against the core renderer and analytic
ground truth, the scene left as it was, and the render operator."""

import json
import math
import re

import bpy
import numpy as np
import pytest
from mathutils import Vector

import shadecut
from shadecut import dataset
from shadecut.blender import lambertian, panels
from shadecut.blender.capabilities import eevee_engine

CENTRE = Vector((0.3, 0.2, -0.1))
LIGHT = (1.0, 0.5, 1.0)


def add_sphere(radius=1.0, location=CENTRE):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=radius, location=location)
    bpy.ops.object.shade_smooth()
    return bpy.context.active_object


def add_suzanne():
    bpy.ops.mesh.primitive_monkey_add()
    suzanne = bpy.context.active_object
    suzanne.modifiers.new("Subdivision", "SUBSURF").levels = 2
    bpy.ops.object.shade_smooth()
    return suzanne


def core_agreement(render):
    """Mean |Cycles - shadecut.render| inside the mask eroded by 2 pixels."""
    expected = shadecut.render(render.normals, render.light, render.albedo, render.mask)
    inside = shadecut.erode_mask(render.mask, 2)
    return float(np.abs(render.image - expected)[inside].mean())


def analytic_sphere(render, centre=CENTRE, radius=1.0):
    """Mask, normals and camera-frame z of the exact sphere at the render's pixel centres."""
    width, height = render.meta["resolution"]
    size = render.meta["pixel_size"]
    camera = np.array(render.meta["camera"]["matrix_world"])
    rows, cols = np.mgrid[0:height, 0:width]
    x = (cols + 0.5 - width / 2) * size
    y = (height / 2 - rows - 0.5) * size
    c = camera[:3, :3].T @ (np.array(centre) - camera[:3, 3])  # the centre in the camera frame
    dx, dy = x - c[0], y - c[1]
    h2 = radius**2 - dx**2 - dy**2
    mask = h2 > 0
    h = np.sqrt(np.maximum(h2, 0))
    return mask, np.dstack([dx, dy, h]) / radius, c[2] + h


def test_sphere_matches_core_renderer_and_analytic_normals_and_depth():
    sphere = add_sphere()
    render = lambertian.render_lambertian([sphere], light=LIGHT, resolution=(96, 96), albedo=0.8)
    agreement = core_agreement(render)
    mask, normals, z = analytic_sphere(render)
    inside = shadecut.erode_mask(render.mask, 2)
    angles = shadecut.angular_error_map(render.normals, normals.astype(np.float32), inside)[inside]
    depth_error = np.abs(render.depth - z)[inside] / render.meta["pixel_size"]  # pixels
    print(f"\nsphere 96 px: |Cycles - core| {agreement:.2e}, normals {angles.mean():.3f} deg mean "
          f"{angles.max():.3f} max, depth {depth_error.mean():.4f} px mean {depth_error.max():.4f} max, "
          f"mask differs at {np.count_nonzero(mask != render.mask)} px")
    assert agreement < 0.005
    assert angles.mean() < 0.1 and angles.max() < 0.5
    # The UV sphere's flat quads lie inside the true sphere, by up to r (1 - cos(pi/64)) ~ 0.05 px
    # across the rings plus the same along them near the equator.
    assert depth_error.mean() < 0.05 and depth_error.max() < 0.1
    assert np.count_nonzero(mask != render.mask) <= 4  # pixel centres within a facet's sag of the outline
    np.testing.assert_allclose(render.light, np.array(LIGHT) / 1.5)
    # 0.8 * cos at the pixel facing the light most directly.
    assert render.image.max() == pytest.approx(0.8, abs=2e-3)


def test_suzanne_matches_core_renderer():
    render = lambertian.render_lambertian([add_suzanne()], light=(-0.5, 0.8, 1.0), resolution=(128, 128), albedo=0.6)
    agreement = core_agreement(render)
    print(f"\nSuzanne 128 px: |Cycles - core| {agreement:.2e}")
    assert agreement < 0.005
    assert 0.15 < render.mask.mean() < 0.9


def test_meta_is_complete_and_written_sample_loads(tmp_path):
    render = lambertian.render_lambertian([add_sphere()], light=LIGHT, resolution=(64, 48), albedo=0.7)
    for key in ("light", "albedo", "camera", "pixel_size", "resolution", "noise_sigma", "quantization_bits",
                "seed", "samples", "shadows", "indirect", "blender_version", "objects", "light_slant_deg",
                "light_tilt_deg"):
        assert key in render.meta, key
    assert render.meta["camera"]["type"] == "orthographic" and render.meta["camera"]["fitted"]
    assert render.meta["resolution"] == [64, 48] and render.image.shape == (48, 64)
    render.write(tmp_path / "sphere")
    meta = json.loads((tmp_path / "sphere" / "meta.json").read_text())
    assert meta["conventions"] and meta["blender_version"] == bpy.app.version_string
    assert meta["camera"]["ortho_scale"] > 0
    sample = dataset.load_sample(tmp_path / "sphere")
    np.testing.assert_array_equal(sample.mask, render.mask)
    np.testing.assert_allclose(sample.image, render.image)
    np.testing.assert_allclose(sample.depth, render.depth_pixels, rtol=1e-6)
    png = shadecut.load_image(tmp_path / "sphere" / "image.png")
    np.testing.assert_allclose(png.image, render.image, atol=2e-5)


def scene_state():
    """What a render must leave as it was: data-blocks, scene settings, selection, materials."""
    scene = bpy.context.scene
    blocks = {name: sorted(block.name for block in getattr(bpy.data, name)
                           if not (name == "images" and block.type == "RENDER_RESULT"))
              for name in ("objects", "meshes", "materials", "cameras", "lights", "worlds", "scenes", "images",
                           "collections", "node_groups")}
    objects = {ob.name: (ob.hide_render, ob.select_get(), [tuple(row) for row in ob.matrix_world],
                         [slot.material.name if slot.material else None for slot in ob.material_slots],
                         sorted(c.name for c in ob.users_collection), len(ob.users_scene))
               for ob in bpy.data.objects}
    render = scene.render
    settings = (render.engine, render.resolution_x, render.resolution_y, render.resolution_percentage, render.filepath,
                render.film_transparent, render.image_settings.file_format, scene.cycles.samples,
                scene.cycles.filter_width, scene.cycles.max_bounces, scene.view_settings.view_transform,
                scene.view_settings.look, scene.view_settings.exposure, scene.camera.name if scene.camera else None,
                scene.world.name if scene.world else None, scene.frame_current,
                bpy.context.view_layer.material_override, bpy.context.view_layer.use_pass_normal)
    return blocks, objects, settings, bpy.context.view_layer.objects.active.name


def user_scene():
    """A scene with its own camera, light, world, coloured material and render settings."""
    bpy.ops.world.new()
    bpy.context.scene.world = bpy.data.worlds[-1]
    sphere = add_sphere()
    material = bpy.data.materials.new("Blue")
    material.use_nodes = True
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.2, 0.5, 0.9, 1.0)
    sphere.data.materials.append(material)
    bpy.ops.mesh.primitive_plane_add(size=6, location=(0, 2, 0), rotation=(math.pi / 2, 0, 0))
    bpy.ops.object.light_add(type="POINT", location=(2, -2, 3))
    bpy.ops.object.camera_add(location=(0.3, -8, -0.1), rotation=(math.pi / 2, 0, 0))
    bpy.context.scene.camera = bpy.context.active_object
    bpy.context.scene.render.engine = eevee_engine()
    bpy.context.scene.render.filepath = "//user_output"
    sphere.select_set(True)
    bpy.context.view_layer.objects.active = sphere
    return sphere


def test_user_scene_unchanged_after_renders_and_after_a_failure():
    sphere = user_scene()
    twin = bpy.data.objects.new("Twin", sphere.data)  # shares the mesh, so its material slot too
    twin.location = (-2.5, 0, 0)
    bpy.context.scene.collection.objects.link(twin)
    bpy.context.view_layer.update()  # twin's matrix_world, which any evaluation would bring up to date
    before = scene_state()
    lambertian.render_lambertian([sphere, twin], light=LIGHT, resolution=(32, 32), albedo=None, shadows=True)
    assert scene_state() == before
    lambertian.render_lambertian([sphere], light=LIGHT, camera=bpy.context.scene.camera, resolution=(32, 32))
    assert scene_state() == before
    # The light is checked after the temporary scene, camera and materials exist: all must go.
    with pytest.raises(lambertian.RenderError, match="horizon"):
        lambertian.render_lambertian([sphere], light=(0, 1, -0.2), resolution=(32, 32), albedo=None)
    assert scene_state() == before
    # A huge component is shown in a few digits, not 39.
    with pytest.raises(lambertian.RenderError, match=re.escape("the light (1e+38, 0, -1 in the camera frame)")):
        lambertian.render_lambertian([sphere], light=(1e38, 0, -1), resolution=(32, 32))


def test_own_colours_give_the_albedo_map():
    sphere = user_scene()
    render = lambertian.render_lambertian([sphere], light=LIGHT, resolution=(64, 64), albedo=None)
    luminance = 0.2126 * 0.2 + 0.7152 * 0.5 + 0.0722 * 0.9
    np.testing.assert_allclose(render.albedo_map[render.mask], luminance, atol=1e-4)
    assert render.albedo == pytest.approx(luminance, abs=1e-4) and render.meta["albedo_mode"] == "own_colours"
    assert core_agreement(render) < 0.005


def test_own_colours_keep_textures_and_parents():
    """A checker texture on the base colour survives; a material-less object is Cycles' 0.8 grey; a
    parent that is not rendered still places its child."""
    bpy.ops.object.empty_add(location=(3, 0, 0))
    parent = bpy.context.active_object
    plain = add_sphere(location=(-1.2, 0, 0))
    plain.parent = parent  # world x = 1.8
    textured = add_sphere(location=(1.2, 0, 0))
    material = bpy.data.materials.new("Checker")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Color1"].default_value = (0.9, 0.9, 0.9, 1.0)
    checker.inputs["Color2"].default_value = (0.1, 0.1, 0.1, 1.0)
    material.node_tree.links.new(checker.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    textured.data.materials.append(material)
    render = lambertian.render_lambertian([plain, textured], light=LIGHT, resolution=(96, 48), albedo=None)
    np.testing.assert_allclose(np.unique(np.round(render.albedo_map[render.mask], 3)), [0.1, 0.8, 0.9], atol=1e-6)
    # The objects span world x 0.2 to 2.8; the fitted camera is centred on them.
    assert render.meta["camera"]["matrix_world"][0][3] == pytest.approx(1.5, abs=1e-5)
    expected = shadecut.render(render.normals, render.light, 1.0, render.mask) * render.albedo_map
    inside = shadecut.erode_mask(render.mask, 2)
    assert np.abs(render.image - expected)[inside].mean() < 0.005
    assert [m.name for m in bpy.data.materials] == ["Checker"]


def test_perspective_scene_camera_and_sun_object():
    sphere = add_sphere()
    bpy.ops.object.camera_add(location=(0.3, -8, -0.1), rotation=(math.pi / 2, 0, 0))
    camera = bpy.context.active_object
    # Toward the light = the sun's +Z; a sun rotated about world X leans its +Z toward -Y, the camera.
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(60), 0, 0))
    sun = bpy.context.active_object
    render = lambertian.render_lambertian([sphere], light=sun, camera=camera, resolution=(64, 64))
    assert render.meta["camera"]["type"] == "perspective" and not render.meta["camera"]["fitted"]
    # World (0, -sin 60, cos 60) is camera (0, cos 60, sin 60) for a camera looking along +Y.
    np.testing.assert_allclose(render.light, [0, 0.5, math.sqrt(3) / 2], atol=1e-6)
    assert core_agreement(render) < 0.005
    inside = render.mask
    assert np.all(render.depth[inside] < -6.5) and np.all(render.depth[inside] > -8)
    with pytest.raises(lambertian.RenderError, match="use a Sun"):
        bpy.ops.object.light_add(type="POINT")
        lambertian.render_lambertian([sphere], light=bpy.context.active_object, resolution=(16, 16))


def test_cast_shadows_darken_and_are_masked():
    bpy.ops.mesh.primitive_plane_add(size=4, location=(0, 1, 0), rotation=(math.pi / 2, 0, 0))
    wall = bpy.context.active_object
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0, -0.5, 0))
    cube = bpy.context.active_object
    kwargs = dict(light=(1.0, 0.4, 1.0), resolution=(64, 64), albedo=0.8)
    lit = lambertian.render_lambertian([wall, cube], **kwargs)
    shadowed = lambertian.render_lambertian([wall, cube], shadows=True, **kwargs)
    assert lit.shadow_mask is None
    shadow = shadowed.shadow_mask
    print(f"\ncast shadow: {shadow.sum()} px, mean {shadowed.image[shadow].mean():.4f} "
          f"against {lit.image[shadow].mean():.4f} without shadows")
    assert shadow.sum() > 50
    assert np.all(shadowed.image[shadow] < lit.image[shadow] - 0.1)
    np.testing.assert_allclose(shadowed.image[~shadow], lit.image[~shadow], atol=1e-4)


def test_noise_and_quantization_are_seeded():
    sphere = add_sphere()
    kwargs = dict(light=LIGHT, resolution=(48, 48), noise=0.01, bits=8, seed=5)
    first = lambertian.render_lambertian([sphere], **kwargs)
    again = lambertian.render_lambertian([sphere], **kwargs)
    other = lambertian.render_lambertian([sphere], **dict(kwargs, seed=6))
    np.testing.assert_array_equal(first.image, again.image)
    assert not np.array_equal(first.image, other.image)
    inside = shadecut.erode_mask(first.mask, 2) & (first.clean_image > 0.2)
    assert 0.007 < np.std((first.image - first.clean_image)[inside]) < 0.013
    # Quantized values are 8-bit sRGB codes, which a PNG then stores exactly.
    encoded = np.where(first.image <= 0.0031308, 12.92 * first.image, 1.055 * first.image ** (1 / 2.4) - 0.055)
    np.testing.assert_allclose(encoded * 255, np.round(encoded * 255), atol=1e-3)
    assert first.meta["noise_sigma"] == 0.01 and first.meta["quantization_bits"] == 8 and first.meta["seed"] == 5


def test_bad_input_is_refused():
    sphere = add_sphere()
    with pytest.raises(lambertian.RenderError, match="no mesh"):
        lambertian.render_lambertian([])
    with pytest.raises(lambertian.RenderError, match="resolution"):
        lambertian.render_lambertian([sphere], resolution=(1, 64))
    with pytest.raises(lambertian.RenderError, match="albedo"):
        lambertian.render_lambertian([sphere], albedo=1.5)
    with pytest.raises(lambertian.RenderError, match="8 or 16"):
        lambertian.render_lambertian([sphere], bits=12)


@pytest.fixture
def operator_registered():
    shadecut.register()
    yield
    shadecut.unregister()


def test_operator_writes_a_sample(operator_registered, tmp_path):
    add_sphere()
    settings = bpy.context.scene.shadecut_render
    settings.resolution_x = settings.resolution_y = 32
    settings.output_dir = str(tmp_path / "render")
    settings.light_direction = (0.0, 1.0, 1.0)
    assert bpy.ops.shadecut.render_lambertian() == {"FINISHED"}
    sample = dataset.load_sample(tmp_path / "render")
    np.testing.assert_allclose(sample.light, [0, 2**-0.5, 2**-0.5], atol=1e-6)
    assert sample.image.shape == (32, 32) and sample.mask.any()
    # A second render into the same folder replaces the sample.
    settings.albedo = 0.5
    assert bpy.ops.shadecut.render_lambertian() == {"FINISHED"}
    assert dataset.load_sample(tmp_path / "render").albedo == 0.5


def test_operator_reports_errors(operator_registered, tmp_path):
    settings = bpy.context.scene.shadecut_render
    settings.output_dir = str(tmp_path / "render")
    # In background mode Blender turns an operator's ERROR report into a RuntimeError of the call.
    with pytest.raises(RuntimeError, match="no mesh object"):
        bpy.ops.shadecut.render_lambertian()
    add_sphere()
    settings.light_direction = (1.0, 0.0, -1.0)
    with pytest.raises(RuntimeError, match="horizon"):
        bpy.ops.shadecut.render_lambertian()
    settings.light_direction = (1.0, 0.0, 1.0)
    settings.light_source = "SUN"
    with pytest.raises(RuntimeError, match="Choose a Sun"):
        bpy.ops.shadecut.render_lambertian()
    settings.light_source, settings.camera_source = "DIRECTION", "SCENE"
    with pytest.raises(RuntimeError, match="no camera"):
        bpy.ops.shadecut.render_lambertian()
    settings.camera_source = "FIT"
    (tmp_path / "file").write_text("")
    settings.output_dir = str(tmp_path / "file" / "render")
    with pytest.raises(RuntimeError, match="ShadeCut render"):
        bpy.ops.shadecut.render_lambertian()
    assert not (tmp_path / "render").exists()
    settings.output_dir = "//render"  # relative to an unsaved .blend file
    with pytest.raises(RuntimeError, match="Save the .blend"):
        bpy.ops.shadecut.render_lambertian()


def test_draw_function_draws(operator_registered):
    # draw_render_settings only needs a layout; Blender's UI layout exists in background mode too.
    class Recorder:
        def __init__(self):
            self.calls = []

        def __getattr__(self, name):
            def record(*args, **kwargs):
                self.calls.append((name, args, kwargs))
                return self
            return record

    layout = Recorder()
    panels.draw_render_settings(layout, bpy.context.scene.shadecut_render)
    assert ("operator", ("shadecut.render_lambertian",), {"icon": "RENDER_STILL"}) in layout.calls
