"""The maps an artist wires into a material: the tangent-space normal map, the height image, and
the input taken from the selected Image Texture node."""

import bpy
import numpy as np
import pytest
from mathutils import Euler, Matrix

import shadecut
from shadecut import imaging, synthetic
from shadecut.blender import image_input, reconstruct_job

LIGHT = (1.0, 0.0, 1.0)


def reconstruct(path, **settings):
    options = bpy.context.scene.shadecut
    options.image = bpy.data.images.load(str(path))
    options.light_source, options.light_direction = "DIRECTION", LIGHT
    options.auto_density, options.density = False, 1
    for key, value in settings.items():
        setattr(options, key, value)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    return bpy.context.active_object


def rgba_of(image):
    """An image's pixels (H, W, 4), row 0 at the top."""
    width, height = image.size
    buffer = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(buffer)
    return buffer.reshape(height, width, 4)[::-1]


def vertex_array(mesh, attribute):
    values = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get(attribute, values)
    return values.reshape(-1, 3)


def linked(links, from_node, from_socket, to_node, to_socket, muted=False):
    return any(link.from_node == from_node and link.from_socket.name == from_socket and link.to_node == to_node
               and link.to_socket.name == to_socket and link.is_muted == muted for link in links)


# --- 1. The normal map in the material ---------------------------------------------------------------------

def test_normal_map_is_wired_through_a_normal_map_node(addon, sphere_png):
    obj = reconstruct(sphere_png[1], normal_map=True)
    tree = obj.active_material.node_tree
    image = bpy.data.images[f"{obj.name} normals"]
    texture = next(node for node in tree.nodes if node.type == "TEX_IMAGE" and node.image == image)
    normal_map = next(node for node in tree.nodes if node.type == "NORMAL_MAP")
    shader = next(node for node in tree.nodes if node.type == "BSDF_PRINCIPLED")
    assert normal_map.space == "TANGENT" and normal_map.uv_map == "UVMap" == obj.data.uv_layers.active.name
    assert linked(tree.links, texture, "Color", normal_map, "Color")
    # Muted: the result's geometry has the shape already (the maps are for a flat surface).
    assert linked(tree.links, normal_map, "Normal", shader, "Normal", muted=True)
    assert image.colorspace_settings.name == "Non-Color"
    assert image.packed_file is not None and image.users >= 1
    assert image.alpha_mode == "CHANNEL_PACKED"  # the mask in alpha leaves the colours alone


def test_no_normal_map_without_the_option(addon, sphere_png):
    obj = reconstruct(sphere_png[1])
    assert f"{obj.name} normals" not in bpy.data.images
    assert not any(node.type == "NORMAL_MAP" for node in obj.active_material.node_tree.nodes)


def test_the_maps_survive_saving_and_reloading(addon, sphere_png, tmp_path):
    obj = reconstruct(sphere_png[1], normal_map=True, height_map=True)
    saved = {name: rgba_of(bpy.data.images[f"{obj.name} {name}"]) for name in ("normals", "height")}
    path = tmp_path / "saved.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path), load_ui=False)
    for name, pixels in saved.items():
        image = bpy.data.images[f"sphere {name}"]
        assert image.packed_file is not None and image.colorspace_settings.name == "Non-Color"
        np.testing.assert_allclose(rgba_of(image), pixels, atol=1e-6)
    material = bpy.data.objects["sphere"].active_material
    assert any(node.type == "TEX_IMAGE" and node.image == bpy.data.images["sphere normals"]
               for node in material.node_tree.nodes)


@pytest.mark.parametrize("frame", ["IMAGE_PLANE", "CAMERA"])
def test_uvs_lay_the_image_out_along_the_objects_x_and_y(addon, sphere_png, frame):
    """Tangent = +X (U grows with x), bitangent = +Y (V grows with y), normal = +Z: the camera frame.
    A Sun read through a turned camera changes the light only; the object is never rotated."""
    truth, path = sphere_png
    settings = {}
    if frame == "CAMERA":
        camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
        camera.rotation_euler = Euler((1.1, 0.0, 0.7))
        bpy.context.collection.objects.link(camera)
        bpy.context.scene.camera = camera
        sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
        sun.rotation_euler = camera.rotation_euler  # the sun behind the camera: light along the view
        bpy.context.collection.objects.link(sun)
        settings = dict(light_source="OBJECT", light_object=sun, frame="CAMERA")
        bpy.context.view_layer.update()
    obj = reconstruct(path, normal_map=True, **settings)
    assert obj.matrix_world.to_3x3() == Matrix.Identity(3)
    mesh = obj.data
    co = vertex_array(mesh, "co")
    uv = np.empty(2 * len(mesh.loops), np.float32)
    mesh.uv_layers["UVMap"].data.foreach_get("uv", uv)
    corners = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", corners)
    vertex_uv = np.empty((len(co), 2), np.float32)
    vertex_uv[corners] = uv.reshape(-1, 2)
    height, width = truth.mask.shape
    rows, cols = np.nonzero(truth.mask)  # the vertices' pixels, in vertex order
    np.testing.assert_allclose(vertex_uv[:, 0], (cols + 0.5) / width, atol=1e-5)
    np.testing.assert_allclose(vertex_uv[:, 1], 1 - (rows + 0.5) / height, atol=1e-5)
    for axis in range(2):  # U follows X, V follows Y, in proportion
        assert np.corrcoef(co[:, axis], vertex_uv[:, axis])[0, 1] > 0.9999


def test_decoded_normal_map_matches_the_mesh_normals(addon, sphere_png):
    truth, path = sphere_png
    obj = reconstruct(path, normal_map=True)
    rgba = rgba_of(bpy.data.images[f"{obj.name} normals"])
    np.testing.assert_array_equal(rgba[..., 3] > 0.5, truth.mask)
    np.testing.assert_allclose(rgba[~truth.mask][:, :3], [imaging.FLAT_NORMAL_COLOR] * np.count_nonzero(~truth.mask))
    decoded = np.zeros_like(truth.normals)
    decoded[truth.mask] = 2 * rgba[truth.mask][:, :3] - 1  # tangent space = object X, Y, Z here
    mesh_normals = np.zeros_like(truth.normals)
    mesh_normals[truth.mask] = vertex_array(obj.data, "normal")
    middle = shadecut.erode_mask(truth.mask, 12)
    errors = shadecut.angular_error_map(decoded, mesh_normals, middle)[middle]
    print(f"normal map vs mesh vertex normals: mean {errors.mean():.2f} deg, 95th percentile "
          f"{np.percentile(errors, 95):.2f} deg, max {errors.max():.2f} deg")
    # The mesh's normals come from the integrated heights, the map's are the method's own (a few
    # graph-cut label steps apart at single pixels).
    assert errors.mean() < 2.0 and np.percentile(errors, 95) < 4.0 and errors.max() < 10.0
    assert shadecut.angular_error(decoded, truth.normals, middle) < 5.0


# --- 2. The height image in the material -------------------------------------------------------------------

def displacement_of(obj):
    """The material's height texture and Displacement node, checked to be wired to the output."""
    tree = obj.active_material.node_tree
    image = bpy.data.images[f"{obj.name} height"]
    texture = next(node for node in tree.nodes if node.type == "TEX_IMAGE" and node.image == image)
    displacement = next(node for node in tree.nodes if node.type == "DISPLACEMENT")
    output = next(node for node in tree.nodes if node.type == "OUTPUT_MATERIAL")
    assert linked(tree.links, texture, "Color", displacement, "Height")
    assert linked(tree.links, displacement, "Displacement", output, "Displacement", muted=True)
    assert image.colorspace_settings.name == "Non-Color" and image.packed_file is not None
    return image, displacement


@pytest.mark.parametrize("output", ["MESH", "DISPLACE"])
@pytest.mark.parametrize("scene, depth_scale", [("object", 1.0), ("relief", 2.5)])
def test_height_map_displaces_as_high_as_the_mesh(addon, sphere_png, tmp_path, output, scene, depth_scale):
    if scene == "relief":
        wall = synthetic.bricks(LIGHT, size=96)
        path = tmp_path / "bricks.png"
        shadecut.save_image(path, wall.image)
    else:
        path = sphere_png[1]
    mesh = reconstruct(path, scene=scene, width=3.0, depth_scale=depth_scale)
    heights = vertex_array(mesh.data, "co")[:, 2]
    assert not any(node.type == "DISPLACEMENT" for node in mesh.active_material.node_tree.nodes)

    obj = reconstruct(path, scene=scene, width=3.0, depth_scale=depth_scale, output=output, height_map=True)
    image, displacement = displacement_of(obj)
    scale, zero = displacement.inputs["Scale"].default_value, displacement.inputs["Midlevel"].default_value
    height = rgba_of(image)[..., 0]
    assert 0.0 <= height.min() and height.max() <= 1.0
    # Scale x the image's range = the result's height range in scene units.
    assert scale * np.ptp(height) == pytest.approx(np.ptp(heights), rel=0.01)
    # And every vertex: (height - Midlevel) x Scale = its height in scene units.
    mask = rgba_of(bpy.context.scene.shadecut.image)[..., 3] > 0.5
    np.testing.assert_allclose((height[mask] - zero) * scale, heights, atol=1e-4 * max(np.ptp(heights), 1e-3))
    if output == "DISPLACE":  # the modifier and the material read the same image, the same way
        modifier = obj.modifiers["ShadeCut height"]
        assert modifier.texture.image == image
        assert (modifier.strength, modifier.mid_level) == pytest.approx((scale, zero))
        assert len([i for i in bpy.data.images if i.name.startswith(f"{obj.name} height")]) == 1


def test_no_height_map_without_the_option(addon, sphere_png):
    obj = reconstruct(sphere_png[1])
    assert f"{obj.name} height" not in bpy.data.images
    obj = reconstruct(sphere_png[1], output="DISPLACE")  # the modifier's image, not in the material
    assert not any(node.type == "DISPLACEMENT" for node in obj.active_material.node_tree.nodes)


# --- 3. The input from the selected Image Texture node ------------------------------------------------------

def textured_plane(image, select_texture=True):
    """A plane whose material shows ``image`` through an Image Texture node, active (selected)."""
    material = bpy.data.materials.new("Bark")
    material.use_nodes = True
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.name, texture.image = "Bark colour", image
    material.node_tree.links.new(texture.outputs["Color"],
                                 material.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    material.node_tree.nodes.active = texture if select_texture else material.node_tree.nodes["Principled BSDF"]
    plane = bpy.data.objects.new("Plane", bpy.data.meshes.new("Plane"))
    plane.data.materials.append(material)
    bpy.context.collection.objects.link(plane)
    bpy.context.view_layer.objects.active = plane
    return plane, material


def scene_state():
    collections = ("objects", "meshes", "materials", "images", "textures")
    names = {key: sorted(item.name for item in getattr(bpy.data, key)) for key in collections}
    return names


def test_the_selected_image_texture_node_is_the_input(addon, sphere_png):
    truth, path = sphere_png
    image = bpy.data.images.load(str(path))
    plane, material = textured_plane(image)
    links_before = len(material.node_tree.links)
    settings = bpy.context.scene.shadecut
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    assert settings.image is None
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.source_image == image and "'Bark colour'" in job.image_origin and "'Bark'" in job.image_origin

    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    result = bpy.context.active_object
    assert result.name == "sphere" and len(result.data.vertices) == np.count_nonzero(truth.mask)
    assert settings.image is None  # the panel is left as it was
    assert len(material.node_tree.links) == links_before and plane.active_material == material


def test_the_finish_report_names_the_node(addon, sphere_png):
    class Operator:
        def __init__(self):
            self.reports = []

        def report(self, kind, text):
            self.reports.append((kind, text))

    image = bpy.data.images.load(str(sphere_png[1]))
    textured_plane(image)
    settings = bpy.context.scene.shadecut
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    job = reconstruct_job.prepare_job(bpy.context)
    job.run()
    operator = Operator()
    assert reconstruct_job.finish_job(operator, bpy.context, job) == {"FINISHED"}
    (kind, text), = operator.reports
    assert kind == {"INFO"}
    assert "image 'sphere.png' from the Image Texture node 'Bark colour' of material 'Bark'" in text


def test_the_panels_image_wins_over_the_node(addon, sphere_png, tmp_path):
    other = tmp_path / "other.png"
    scene = synthetic.sphere(light=LIGHT, size=64)
    shadecut.save_image(other, scene.image, scene.mask)
    textured_plane(bpy.data.images.load(str(sphere_png[1])))
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(other))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert bpy.context.active_object.name == "other"


@pytest.mark.parametrize("case", ["not selected", "no image", "not an image texture"])
def test_without_a_selected_image_texture_it_is_an_error_that_changes_nothing(addon, sphere_png, case):
    image = bpy.data.images.load(str(sphere_png[1]))
    plane, material = textured_plane(image if case != "no image" else None, select_texture=case != "not selected")
    if case == "not an image texture":
        material.node_tree.nodes.active = material.node_tree.nodes.new("ShaderNodeTexNoise")
    bpy.context.scene.shadecut.light_source = "DIRECTION"
    before = scene_state()
    with pytest.raises(image_input.InputError, match="No image"):
        reconstruct_job.prepare_job(bpy.context)
    with pytest.raises(RuntimeError, match="No image"):  # an ERROR report raises in background mode
        bpy.ops.shadecut.reconstruct()
    assert scene_state() == before and bpy.context.view_layer.objects.active == plane
