"""The issue's acceptance for the normal map: rendered through its Normal Map node on a flat plane
with the result's UV layout, it reproduces the shading of the reconstructed mesh (on a sphere).

Both are rendered by Cycles (CPU, direct light only, no denoising, Standard view transform, linear
EXR) from above by an orthographic camera, lit by one Sun, with a white Diffuse BSDF; the plane's
maps are put there by Apply to = Active object (result.apply_maps)."""

import math

import bpy
import numpy as np
from mathutils import Vector

import shadecut
from shadecut import synthetic
from shadecut.blender.capabilities import set_cast_shadow

LIGHT = (0.6, 0.5, 1.0)  # both tangent axes matter: a flipped red or green channel would show
SIZE = 64  # the sphere image's pixels = the renders' pixels
WIDTH = 2.0  # the result's width and the plane's size, in scene units


def diffuse_material(name):
    """A white Diffuse BSDF (Lambert) as the surface."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    material.node_tree.links.new(diffuse.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    return material


def set_up_render(scene, path):
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0  # direct light only: Lambert's model
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = str(path)
    scene.world = None  # black
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type, camera.data.ortho_scale = "ORTHO", WIDTH
    camera.location = (0.0, 0.0, 10.0)  # looking down -Z, image right = +X, image up = +Y
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy, sun.data.angle = math.pi, 0.0  # a white Lambertian surface facing it renders 1
    set_cast_shadow(sun.data, False)
    sun.rotation_euler = Vector(LIGHT).to_track_quat("Z", "Y").to_euler()  # its +Z toward the light
    scene.collection.objects.link(sun)


def render_alone(obj, others, path):
    """The red channel (white surfaces: the intensity) of a render showing ``obj`` only, row 0 at the top."""
    for other in others:
        other.hide_render = other != obj
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[::-1, :, 0]


def test_the_normal_map_on_a_plane_shades_as_the_mesh(addon, tmp_path):
    truth = synthetic.sphere(light=LIGHT, size=SIZE)
    path = tmp_path / "sphere.png"
    shadecut.save_image(path, truth.image, truth.mask)
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(path))
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    settings.width, settings.auto_density, settings.density = WIDTH, False, 1

    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}  # the mesh, no maps
    mesh = bpy.context.active_object
    mesh.data.materials.clear()
    mesh.data.materials.append(diffuse_material("Mesh"))

    bpy.ops.mesh.primitive_plane_add(size=WIDTH)  # UVs 0..1 over it: the mesh's UV layout
    plane = bpy.context.active_object
    plane.data.materials.append(diffuse_material("Plane"))
    settings.target, settings.normal_map = "ACTIVE_MATERIAL", True
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    normal_link, = plane.active_material.node_tree.nodes["Diffuse BSDF"].inputs["Normal"].links
    assert normal_link.from_node.type == "NORMAL_MAP" and not normal_link.is_muted

    scene = bpy.context.scene
    output = tmp_path / "render.exr"
    set_up_render(scene, output)
    of_mesh = render_alone(mesh, (mesh, plane), output)
    of_plane = render_alone(plane, (mesh, plane), output)

    inside = shadecut.erode_mask(truth.mask, 3)
    a, b = of_mesh[inside], of_plane[inside]
    difference = float(np.abs(a - b).mean() / a.max())
    correlation = float(np.corrcoef(a, b)[0, 1])
    print(f"mesh vs normal-mapped plane over {inside.sum()} px: mean |difference| {difference:.4f} of the "
          f"maximum {a.max():.3f}, correlation {correlation:.4f}; mesh vs the input image: "
          f"{np.abs(a - truth.image[inside]).mean():.4f}")
    # Measured: 0.0420 and 0.9818 (with light (1, 0, 1): 0.0297 and 0.9916). The whole of the
    # difference is where the normals tilt more than 45 degrees from the plane's: there Cycles bends a
    # normal-mapped normal toward the surface's own (so that the view's reflection stays above it),
    # which brightens the plane toward the terminator by about 0.10 on average. Below 45 degrees:
    assert difference <= 0.05 and correlation >= 0.97
    gentle = inside & (truth.normals[..., 2] > math.cos(math.radians(45)))
    a, b = of_mesh[gentle], of_plane[gentle]
    difference = float(np.abs(a - b).mean() / a.max())
    correlation = float(np.corrcoef(a, b)[0, 1])
    print(f"where the normals tilt under 45 degrees ({gentle.sum()} px): mean |difference| {difference:.4f}, "
          f"correlation {correlation:.4f}")
    # Measured: 0.0072 and 0.9992 (a swapped or flipped tangent axis breaks this: the light has x and y).
    assert difference <= 0.012 and correlation >= 0.998
