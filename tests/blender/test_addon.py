"""The add-on inside a real Blender: the operator end to end, working sizes, pixels, light frames."""

import math

import bpy
import numpy as np
import pytest
from mathutils import Euler, Vector

import shadecut
from shadecut import imaging, synthetic
from shadecut.blender import frames, image_input, reconstruct_job
from shadecut.blender.lambertian_scene import diffuse_material
from shadecut import vertex_step

LIGHT = (1.0, 0.0, 1.0)


def add_sun(direction, name="Sun"):
    """A sun whose light arrives from ``direction`` (world frame): its local +Z points there."""
    sun = bpy.data.objects.new(name, bpy.data.lights.new(name, "SUN"))
    sun.rotation_euler = Vector(direction).to_track_quat("Z", "Y").to_euler()
    bpy.context.collection.objects.link(sun)
    return sun


def pixels_of(image):
    buffer = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(buffer)
    return buffer


def scene_state():
    """What an operator must leave alone: every datablock collection's names and the objects' data."""
    collections = ("objects", "meshes", "materials", "images", "textures", "lights", "cameras")
    names = {key: sorted(item.name for item in getattr(bpy.data, key)) for key in collections}
    transforms = {obj.name: [tuple(row) for row in obj.matrix_basis] for obj in bpy.data.objects}
    return names, transforms


def test_reconstruct_builds_the_core_surface(addon, sphere_png):
    truth, path = sphere_png
    image = bpy.data.images.load(str(path))
    before = pixels_of(image)
    settings = bpy.context.scene.shadecut
    settings.image = image
    settings.light_source, settings.light_object = "OBJECT", add_sun(LIGHT)
    settings.width, settings.depth_scale = 3.0, 1.5
    objects_before = set(bpy.data.objects)

    # The core run on exactly the arrays the operator hands over.
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_allclose(job.light, np.array(LIGHT) / math.sqrt(2), atol=1e-6)
    core = shadecut.reconstruct(job.image, job.light, job.mask, method="graphcut")

    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    new = set(bpy.data.objects) - objects_before
    assert len(new) == 1
    obj = new.pop()
    assert obj.name == "sphere" and obj.type == "MESH"
    mesh = obj.data
    assert len(mesh.vertices) == np.count_nonzero(truth.mask)

    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    unit = 3.0 / truth.mask.shape[1]
    np.testing.assert_allclose(co[:, 2], core.depth[truth.mask] * unit * 1.5, rtol=1e-5, atol=1e-5)

    # The mesh's own vertex normals against the analytic sphere, with true proportions.
    settings.depth_scale = 1.0
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    normals = np.empty(3 * len(mesh.vertices), np.float32)
    bpy.context.active_object.data.vertices.foreach_get("normal", normals)
    mesh_normals = np.zeros_like(truth.normals)
    mesh_normals[truth.mask] = normals.reshape(-1, 3)
    mesh_error = truth.mean_error(mesh_normals)
    core_error = truth.mean_error(core.normals)
    print(f"sphere: core normals {core_error:.2f} deg, mesh vertex normals {mesh_error:.2f} deg")
    assert mesh_error < core_error + 1.0

    np.testing.assert_array_equal(pixels_of(image), before)
    assert image.filepath == str(path) and not image.is_dirty


def test_result_has_uvs_material_and_smooth_faces(addon, sphere_png):
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    settings.normal_map = True
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    mesh = bpy.context.active_object.data
    assert all(polygon.use_smooth for polygon in mesh.polygons)
    assert mesh.uv_layers.active.name == "UVMap"
    texture = next(node for node in mesh.materials[0].node_tree.nodes if node.type == "TEX_IMAGE")
    assert texture.image.name == "sphere albedo"  # the de-lit colour, not the shaded photo
    albedo = pixels_of(texture.image).reshape(*truth.mask.shape, 4)[::-1]  # Blender keeps row 0 at the bottom
    lit = albedo[truth.mask][:, :3]
    np.testing.assert_allclose(lit, lit[0, 0], rtol=1e-6)  # one albedo: a uniform colour, no shading left
    assert abs(lit[0, 0] - 1.0) < 0.05  # the sphere was rendered with albedo 1
    normal_map = bpy.data.images["sphere normals"]
    assert tuple(normal_map.size) == truth.mask.shape[::-1]


def test_density_samples_every_nth_pixel(addon, sphere_png):
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    settings.auto_density, settings.density = False, 3
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert len(bpy.context.active_object.data.vertices) == np.count_nonzero(truth.mask[::3, ::3])

    settings.density, settings.max_vertices = 1, 1000  # a forced density ignores the budget
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert len(bpy.context.active_object.data.vertices) == np.count_nonzero(truth.mask)


def test_automatic_density_is_the_finest_within_the_budget(addon, sphere_png):
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    assert settings.auto_density and np.count_nonzero(truth.mask) <= settings.max_vertices
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert len(bpy.context.active_object.data.vertices) == np.count_nonzero(truth.mask)

    settings.max_vertices = 1000  # the sphere has 5860 masked pixels
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    vertices = len(bpy.context.active_object.data.vertices)
    step = vertex_step(truth.mask, 1000)
    assert vertices == np.count_nonzero(truth.mask[::step, ::step]) <= 1000
    assert step > 1 and np.count_nonzero(truth.mask[::step - 1, ::step - 1]) > 1000


def image_of(name, width, height):
    """A new float image in Blender: a horizontal shading ramp, opaque."""
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    ramp = np.broadcast_to(np.linspace(0.2, 0.9, width, dtype=np.float32), (height, width))
    image.pixels.foreach_set(np.dstack([ramp, ramp, ramp, np.ones_like(ramp)]).ravel())
    return image


@pytest.mark.parametrize("width, height, working", [(600, 400, (400, 600)), (3000, 40, (20, 1500))])
def test_default_working_size(addon, width, height, working):
    """An image that fits in Max size (2048 px) is worked at its own size; a larger one shrinks by
    the smallest whole factor that makes it fit."""
    settings = bpy.context.scene.shadecut
    settings.image = image_of("photo", width, height)
    settings.light_source = "DIRECTION"
    assert reconstruct_job.prepare_job(bpy.context).image.shape == working


@pytest.mark.parametrize("max_size", [0, 25, 40, 70])
def test_pixels_read_in_bands_are_those_of_the_whole_image(addon, monkeypatch, max_size):
    """The image is converted and shrunk a band of rows at a time (so that no second full-size copy is
    made): the same as converting the whole buffer, then shrinking it."""
    rng = np.random.default_rng(max_size)
    width, height = 101, 67
    rgba = rng.random((height, width, 4)).astype(np.float32)
    rgba[..., 3] = rgba[..., 3] > 0.2
    image = bpy.data.images.new("noise", width, height, alpha=True, float_buffer=True)
    image.pixels.foreach_set(rgba.ravel())
    monkeypatch.setattr(image_input, "BAND_PIXELS", 3 * width)  # several bands, each of whole blocks
    intensity, mask, factor, _ = image_input.image_pixels(image, max_size)
    stored = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(stored)
    whole = stored.reshape(height, width, image.channels)[::-1]
    expected = imaging.downsample(*imaging.intensity_and_mask(image_input._rgba(whole), srgb_encoded=False)[:2],
                                  max_size)
    assert factor == expected[2]
    np.testing.assert_array_equal(intensity, expected[0])
    np.testing.assert_array_equal(mask, expected[1])


def test_mesh_edges_are_those_blender_computes(addon):
    """depth_mesh numbers the edges itself instead of asking Blender (calc_edges): the same edges,
    each loop's edge joining its corner to the next, nothing for validate() to fix."""
    from shadecut.blender.mesh import depth_mesh

    rng = np.random.default_rng(1)
    depth = rng.random((40, 57)).astype(np.float32)
    mask = rng.random((40, 57)) > 0.2
    for step in (1, 3):
        mesh = depth_mesh("ours", depth, mask, step=step)
        co = np.empty(3 * len(mesh.vertices), np.float32)
        mesh.vertices.foreach_get("co", co)
        reference = bpy.data.meshes.new("Blender's")
        reference.from_pydata(co.reshape(-1, 3).tolist(), [], [tuple(p.vertices) for p in mesh.polygons])
        reference.update(calc_edges=True)
        assert sorted(map(sorted, (e.vertices for e in mesh.edges))) == sorted(
            map(sorted, (e.vertices for e in reference.edges)))
        for polygon in mesh.polygons:
            corners = list(polygon.vertices)
            for corner, loop in enumerate(polygon.loop_indices):
                edge = mesh.edges[mesh.loops[loop].edge_index]
                assert set(edge.vertices) == {corners[corner], corners[(corner + 1) % 4]}
        assert not mesh.validate()


def test_displaced_plane_matches_the_mesh_heights(addon, sphere_png):
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    heights = np.array([v.co.z for v in bpy.context.active_object.data.vertices])

    settings.output = "DISPLACE"
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    plane = bpy.context.active_object
    assert plane.modifiers[0].type == "DISPLACE"
    assert all(v.co.z == 0 for v in plane.data.vertices)
    evaluated = plane.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    displaced = np.array([v.co.z for v in evaluated.vertices])
    assert np.abs(displaced - heights).mean() < 0.01 * heights.max()


def test_max_resolution_downsamples(addon, sphere_png):
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    settings.max_resolution = 48
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.image.shape == (48, 48)
    assert job.shrunk == ", worked at 48 x 48 (1/2 of 96 x 96: Max size 48 px)"  # said in the finish report
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert len(bpy.context.active_object.data.vertices) == np.count_nonzero(job.mask)


@pytest.mark.parametrize("suffix", ["png16", "png8", "exr"])
def test_blender_pixels_are_the_linear_values_load_image_reads(addon, tmp_path, suffix):
    scene = synthetic.sphere(light=LIGHT, size=64)
    path = tmp_path / f"sphere_{suffix}.{suffix[:3]}"
    if suffix == "png8":
        import OpenImageIO as oiio

        encoded = np.where(scene.image <= 0.0031308, 12.92 * scene.image, 1.055 * scene.image ** (1 / 2.4) - 0.055)
        buffer = oiio.ImageBuf(oiio.ImageSpec(64, 64, 1, "uint8"))
        buffer.set_pixels(oiio.ROI(), np.round(encoded * 255).astype(np.uint8))
        assert buffer.write(str(path))
    else:
        shadecut.save_image(path, scene.image, scene.mask)
    loaded = shadecut.load_image(path)
    intensity, mask, factor, _ = image_input.image_pixels(bpy.data.images.load(str(path)))
    assert factor == 1
    np.testing.assert_allclose(intensity, loaded.image, atol=2e-4)
    np.testing.assert_array_equal(mask, loaded.mask)


@pytest.mark.parametrize("direction", [(1, 0, 1), (1.5, 0.866, 1), (-0.939, 1.867, 1), (0.3, -0.2, 1), (0, 0, 1)])
def test_sun_direction_in_the_image_plane_frame(addon, direction):
    sun = add_sun(direction)
    bpy.context.view_layer.update()
    expected = np.array(direction) / np.linalg.norm(direction)
    np.testing.assert_allclose(frames.light_in_camera_frame(sun, None), expected, atol=1e-6)


@pytest.mark.parametrize("camera_rotation", [(0, 0, 0), (math.radians(90), 0, 0), (math.radians(60), 0, math.radians(45))])
def test_sun_direction_in_a_camera_frame(addon, camera_rotation):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.rotation_euler = Euler(camera_rotation)
    camera.scale = (2.0, 2.0, 2.0)  # scale must not leak into directions
    bpy.context.collection.objects.link(camera)
    world = Vector((0.2, -0.5, 0.8)).normalized()
    sun = add_sun(world)
    bpy.context.view_layer.update()
    rotation = np.array(Euler(camera_rotation).to_matrix())
    expected = rotation.T @ np.array(world)  # camera axes are the rotation's columns
    np.testing.assert_allclose(frames.light_in_camera_frame(sun, camera), expected, atol=1e-6)

    settings = bpy.context.scene.shadecut
    settings.light_source, settings.light_object, settings.frame = "OBJECT", sun, "CAMERA"
    bpy.context.scene.camera = camera
    light, _ = reconstruct_job._light(bpy.context, settings)
    if expected[2] > 0:
        np.testing.assert_allclose(light, expected, atol=1e-6)


def brightest_normal_in_cycles(tmp_path, size=64):
    """The normal of the brightest pixel of a unit sphere at the origin, rendered by Cycles (direct
    light only) from the top: on a Lambertian sphere it is the direction toward the light."""
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48)
    bpy.ops.object.shade_smooth()
    # Lambertian by its material: without one, Blender 5 renders a glossy default surface.
    bpy.context.active_object.data.materials.append(diffuse_material("Lambert", colour=(0.8, 0.8, 0.8, 1.0)))
    camera = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
    camera.data.type, camera.data.ortho_scale, camera.location = "ORTHO", 2.0, (0, 0, 5)
    scene.collection.objects.link(camera)
    scene.camera, scene.render.engine = camera, "CYCLES"
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.cycles.device, scene.cycles.samples, scene.cycles.max_bounces = "CPU", 1, 0
    scene.cycles.use_denoising = scene.view_layers[0].cycles.use_denoising = False
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = str(tmp_path / "top.exr")
    bpy.ops.render.render(write_still=True)
    red = pixels_of(bpy.data.images.load(scene.render.filepath)).reshape(size, size, 4)[..., 0]
    row, col = np.unravel_index(red.argmax(), red.shape)  # row 0 at the bottom, as Blender stores it
    x, y = (col + 0.5) * 2 / size - 1, (row + 0.5) * 2 / size - 1
    return np.array([x, y, math.sqrt(max(0.0, 1 - x * x - y * y))])


@pytest.mark.parametrize("aimed, scale", [((1, 0.5, 1), (-1, 1, 1)), ((1, 0.5, 1), (1, -2, 0.5)),
                                          ((1, 0.5, -1), (1, 1, -1))])
def test_a_mirrored_sun_gives_the_light_cycles_renders(addon, tmp_path, aimed, scale):
    """A negative scale makes the sun's rotation a reflection, whose quaternion put the light up to 180
    degrees off (for Reconstruct, the light preview and Render Lambertian alike). Blender lights along
    the world matrix's Z axis: with Z mirrored, a sun aimed from below lights from above."""
    sun = add_sun(aimed)
    sun.scale = scale
    bpy.context.view_layer.update()
    light = np.array(frames.light_in_camera_frame(sun, None))
    np.testing.assert_allclose(light, brightest_normal_in_cycles(tmp_path), atol=0.06)


def test_estimated_light_reconstructs_the_sphere(addon, sphere_png):
    truth, path = sphere_png
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source = "ESTIMATE"
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.light is None and job.albedo is None
    job.run()
    angle = math.degrees(math.acos(np.dot(job.result.light, np.array(LIGHT) / math.sqrt(2))))
    print(f"estimated light {job.result.light} is {angle:.1f} deg from the truth")
    assert angle < 10
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}


def test_a_blender_render_reconstructs_in_two_clicks(addon, tmp_path):
    """Render Lambertian test image, then Reconstruct: a Cycles-rendered sphere."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64)
    bpy.ops.object.shade_smooth()
    sphere = bpy.context.active_object
    render_settings = bpy.context.scene.shadecut_render
    render_settings.resolution_x = render_settings.resolution_y = 96
    render_settings.light_direction = (1.5, 0.866, 1.0)
    render_settings.output_dir = str(tmp_path / "render")
    assert bpy.ops.shadecut.render_lambertian() == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    assert settings.image is not None and settings.light_source == "DIRECTION"

    sphere.select_set(False)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    result = bpy.context.active_object
    truth = shadecut.dataset.load_sample(tmp_path / "render")
    normals = np.empty(3 * len(result.data.vertices), np.float32)
    result.data.vertices.foreach_get("normal", normals)
    mesh_normals = np.zeros_like(truth.normals)
    mesh_normals[truth.mask] = normals.reshape(-1, 3)
    error = shadecut.angular_error(mesh_normals, truth.normals, shadecut.erode_mask(truth.mask, 2))
    print(f"Cycles sphere, light (1.5, 0.866, 1): mesh normals {error:.2f} deg from the truth")
    assert error < 5


def test_a_relief_sits_flat_and_keeps_under_the_height_limit(addon, tmp_path):
    light = (0.6, 0.3, 1.0)
    wall = synthetic.bricks(light, size=96)
    path = tmp_path / "bricks.png"
    shadecut.save_image(path, wall.image)
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", light
    settings.scene, settings.width = "relief", 2.0

    def heights():
        assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
        co = np.empty(3 * len(bpy.context.active_object.data.vertices), np.float32)
        bpy.context.active_object.data.vertices.foreach_get("co", co)
        return co.reshape(-1, 3)

    co = heights()
    basis = np.column_stack([co[:, 0], co[:, 1], np.ones(len(co))])
    slope = np.hypot(*np.linalg.lstsq(basis, co[:, 2], rcond=None)[0][:2])
    assert slope <= 0.01  # a flat carrier: no ramp
    unlimited = np.ptp(co[:, 2])
    assert unlimited > 0.05  # the limit below lowers it
    settings.max_height = 0.05  # Limit height still off: Max height is not applied
    assert np.ptp(heights()[:, 2]) == pytest.approx(unlimited, rel=1e-6)
    settings.limit_height = True
    assert np.ptp(heights()[:, 2]) == pytest.approx(0.05, rel=1e-3)


def test_without_openimageio_the_render_panel_says_why_and_the_operator_is_greyed(addon, monkeypatch):
    from shadecut.blender import lambertian, panels

    reason = "Rendering test images needs OpenImageIO, which this installation lacks (no module named X)"
    monkeypatch.setattr(lambertian, "files_unavailable", lambda: reason)
    assert not bpy.ops.shadecut.render_lambertian.poll()
    labels = []

    class Layout:
        def column(self, **_):
            return self

        def label(self, text="", **_):
            labels.append(text)

        def prop(self, *args, **_):
            raise AssertionError(f"a setting was drawn: {args}")

    panels.draw_render_settings(Layout(), bpy.context.scene.shadecut_render)
    assert " ".join(labels).startswith(reason[:40])
    monkeypatch.undo()
    assert bpy.ops.shadecut.render_lambertian.poll()


def test_a_painted_photo_gives_its_de_lit_colour_as_the_material(addon, tmp_path):
    scene = synthetic.sphere((0.4, 0.3, 1.0), 96)
    colour, paint = synthetic.painted(scene, "patches", 4)
    path = tmp_path / "painted.exr"
    shadecut.save_image(path, colour, scene.mask)
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", (0.4, 0.3, 1.0)
    settings.albedo_method = "retinex"
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.colour is not None and job.colour.shape == (96, 96, 3)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    texture = next(node for node in bpy.context.active_object.data.materials[0].node_tree.nodes if node.type == "TEX_IMAGE")
    assert texture.image.name == "painted albedo"
    albedo = pixels_of(texture.image).reshape(96, 96, 4)[::-1][..., :3]
    core = shadecut.reconstruct(colour, (0.4, 0.3, 1.0), scene.mask, albedo_method="retinex")
    np.testing.assert_allclose(albedo[scene.mask], core.albedo_colour[scene.mask], rtol=1e-5, atol=1e-6)
    # The paint's colours, not the shading: its hue follows the true paint's.
    lit = scene.mask & (scene.image > 0.2)
    hue = lambda rgb: rgb / rgb.sum(axis=-1, keepdims=True)
    assert np.abs(hue(albedo[lit]) - hue(paint[lit])).mean() < 0.02


def test_the_residual_map_shows_a_stain_the_relief_does_not_explain(addon, tmp_path):
    """Residual map on: the image '<name> residual' holds the core's residual over the albedo, 0..1; a
    square of paint at half the albedo on a brick wall stands out. Off (the default): no such image."""
    wall = synthetic.bricks((0.5, 0.3, 1.0), size=128, albedo_noise=0.0)
    photograph, stain = wall.image.copy(), (slice(50, 70), slice(50, 70))
    photograph[stain] *= 0.5
    path = tmp_path / "stained.png"
    shadecut.save_image(path, photograph)
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.scene = "relief"
    settings.light_source, settings.light_direction = "DIRECTION", wall.light
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert "stained residual" not in bpy.data.images

    settings.residual_map = True
    job = reconstruct_job.prepare_job(bpy.context)
    core = shadecut.reconstruct(job.image, job.light, job.mask, job.albedo, **job.options)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    residual = bpy.data.images["stained residual"]
    assert residual.packed_file is not None and residual.colorspace_settings.name == "Non-Color"
    pixels = pixels_of(residual).reshape(128, 128, 4)[::-1]  # Blender keeps row 0 at the bottom
    np.testing.assert_allclose(pixels[..., 0], np.clip(core.residual / core.albedo_map, 0.0, 1.0), atol=1e-6)
    np.testing.assert_array_equal(pixels[..., 3], 1.0)
    elsewhere = np.ones(photograph.shape, dtype=bool)
    elsewhere[stain] = False
    assert np.median(pixels[..., 0][stain]) > 4.0 * np.median(pixels[..., 0][elsewhere])
