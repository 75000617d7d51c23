"""The temporary scene of a Lambertian render (see :mod:`.lambertian`): the fitted camera, the sun,
the black world, the Lambert materials and the Cycles settings that make the render exact, and
:class:`Temporary`, which removes all of it again."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import bpy
import numpy as np
from mathutils import Matrix, Vector

from .capabilities import set_cast_shadow, set_multilayer_exr

# The camera of the fitted view looks along world +Y with world +Z up (Blender's "front" view), so
# camera x = world X, camera y = world Z, camera z (toward the viewer) = world -Y.
FRONT_VIEW = Matrix(((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)))
INDIRECT_BOUNCES = 4  # with indirect light on: enough for inter-reflections to settle on concave parts


class RenderError(RuntimeError):
    """A render that cannot be done as asked (bad objects, light, camera or a failed Cycles run)."""



def fitted_ortho(objects, depsgraph, resolution, margin: float) -> tuple[Matrix, float, float, float]:
    """A front-view orthographic camera framing the evaluated objects with ``margin`` on each side.

    Returns (camera matrix_world, ortho_scale, clip_start, clip_end).
    """
    to_camera = FRONT_VIEW.transposed()
    points = []
    for ob in objects:
        evaluated = ob.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        try:
            local = np.empty(len(mesh.vertices) * 3)
            mesh.vertices.foreach_get("co", local)
        finally:
            evaluated.to_mesh_clear()
        matrix = np.array(to_camera @ evaluated.matrix_world.to_3x3())
        offset = np.array(to_camera @ evaluated.matrix_world.translation)
        points.append(local.reshape(-1, 3) @ matrix.T + offset)
    points = np.concatenate(points)
    if len(points) == 0:
        raise RenderError("the objects to render have no vertices")
    low, high = points.min(axis=0), points.max(axis=0)
    extent = high - low
    width, height = resolution
    longest = max(width, height)
    # Blender's AUTO sensor fit spreads ortho_scale over the longer image side.
    scale = (1 + 2 * margin) * max(extent[0] * longest / width, extent[1] * longest / height)
    if scale <= 0:
        raise RenderError("the objects to render have no extent seen from the front")
    distance = max(float(extent.max()), 1e-3)
    centre = (low + high) / 2
    position = FRONT_VIEW @ Vector((centre[0], centre[1], high[2] + distance))
    matrix = Matrix.Translation(position) @ FRONT_VIEW.to_4x4()
    return matrix, scale, distance / 2, extent[2] + 2 * distance


def camera_info(camera_data, resolution) -> dict:
    """The projection of a camera for meta.json, read while the camera still exists.

    Blender's sensor fit maps the sensor (or the ortho scale) onto the longer image side (AUTO) or the
    chosen one; "side" is that side in pixels.
    """
    width, height = resolution
    fit = camera_data.sensor_fit
    horizontal = fit == "HORIZONTAL" or (fit == "AUTO" and width >= height)
    side = width if horizontal else height
    sensor = camera_data.sensor_height if fit == "VERTICAL" else camera_data.sensor_width
    info = {"shift": [camera_data.shift_x, camera_data.shift_y], "side_px": side}
    if camera_data.type == "ORTHO":
        info.update(type="orthographic", ortho_scale=camera_data.ortho_scale)
    elif camera_data.type == "PERSP":
        focal = camera_data.lens / sensor * side
        centre = [width / 2 - camera_data.shift_x * side, height / 2 + camera_data.shift_y * side]  # row down
        info.update(type="perspective", lens_mm=camera_data.lens, sensor_mm=sensor, focal_px=focal,
                    principal_point_px=centre)
    else:
        raise RenderError(f"camera type {camera_data.type} is not supported (orthographic or perspective)")
    return info


def diffuse_material(name: str, colour=None, colour_socket=None, base: Optional[bpy.types.Material] = None):
    """A material whose surface is a Diffuse BSDF of roughness 0 (Lambert).

    With ``base`` it is a copy of that material whose output gets the diffuse node instead, fed by the
    socket that fed the original base colour, so textures keep working.
    """
    material = base.copy() if base is not None else bpy.data.materials.new(name)
    material.name = name
    material.use_nodes = True
    tree = material.node_tree
    outputs = [node for node in tree.nodes if node.type == "OUTPUT_MATERIAL"]
    output = next((node for node in outputs if node.is_active_output), None) or (outputs[0] if outputs else None)
    if output is None:
        output = tree.nodes.new("ShaderNodeOutputMaterial")
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0
    if colour_socket is not None:
        tree.links.new(colour_socket, diffuse.inputs["Color"])
    else:
        diffuse.inputs["Color"].default_value = colour
    tree.links.new(diffuse.outputs["BSDF"], output.inputs["Surface"])
    return material


def own_colour_material(material: Optional[bpy.types.Material]):
    """The Lambertian stand-in of a user's material, keeping its base colour (or texture)."""
    if material is None:
        return diffuse_material("ShadeCut own colour", colour=(0.8, 0.8, 0.8, 1.0))
    surface = None
    if material.use_nodes and material.node_tree is not None:
        for node in material.node_tree.nodes:
            if node.type == "OUTPUT_MATERIAL" and node.is_active_output and node.inputs["Surface"].is_linked:
                surface = node.inputs["Surface"].links[0].from_node
    colour_input = None
    if surface is not None:
        colour_input = surface.inputs.get("Base Color") or surface.inputs.get("Color")
    if colour_input is None:
        return diffuse_material(f"ShadeCut {material.name}", colour=tuple(material.diffuse_color))
    copy = diffuse_material(f"ShadeCut {material.name}", base=material,
                             colour=tuple(colour_input.default_value))
    if colour_input.is_linked:
        # The copy has the same nodes under the same names: the socket's path finds its twin there.
        source = copy.node_tree.path_resolve(colour_input.links[0].from_socket.path_from_id())
        diffuse = [node for node in copy.node_tree.nodes if node.type == "BSDF_DIFFUSE"][-1]
        copy.node_tree.links.new(source, diffuse.inputs["Color"])
    return copy


# Which bpy.data collection removes a temporary data-block of each type.
_COLLECTION = {"Object": "objects", "Camera": "cameras", "SunLight": "lights", "World": "worlds",
               "Material": "materials"}


@dataclass
class Temporary:
    """What a render adds to the file and changes in it, all undone by :meth:`remove`."""

    blocks: list = field(default_factory=list)  # data-blocks, objects first (they use the others)
    swapped_slots: list = field(default_factory=list)  # (material slot, original material), own colours
    given_slots: list = field(default_factory=list)  # meshes without materials given a stand-in's slot

    def add(self, block):
        if isinstance(block, bpy.types.Object):
            self.blocks.insert(0, block)
        else:
            self.blocks.append(block)
        return block

    def new_object(self, name: str, data) -> bpy.types.Object:
        self.add(data)
        return self.add(bpy.data.objects.new(name, data))

    def remove(self, scene: bpy.types.Scene) -> None:
        """Puts the swapped materials back and deletes the scene and every temporary data-block."""
        for slot, material in reversed(self.swapped_slots):
            slot.material = material
        for mesh in reversed(self.given_slots):
            mesh.materials.pop()
        bpy.data.scenes.remove(scene)
        for block in self.blocks:
            getattr(bpy.data, _COLLECTION[type(block).__name__]).remove(block)


def set_camera(scene, objects, camera, resolution, margin: float, temporary: Temporary) -> bpy.types.Object:
    """Links the given camera, or a fitted orthographic one, to the scene as its camera."""
    if camera is None:
        camera = temporary.new_object("ShadeCut camera", bpy.data.cameras.new("ShadeCut camera"))
        matrix, scale, clip_start, clip_end = fitted_ortho(objects, scene.view_layers[0].depsgraph, resolution,
                                                            margin)
        camera.data.type = "ORTHO"
        camera.data.ortho_scale = scale
        camera.data.clip_start, camera.data.clip_end = clip_start, clip_end
        camera.matrix_world = matrix
    scene.collection.objects.link(camera)
    scene.camera = camera
    return camera


def add_sun(scene, direction: Vector, shadows: bool, temporary: Temporary) -> None:
    """A sun shining from ``direction`` (world frame) with irradiance pi and a point-like disc."""
    sun = temporary.new_object("ShadeCut sun", bpy.data.lights.new("ShadeCut sun", "SUN"))
    sun.data.energy = math.pi  # irradiance pi: a white Lambertian surface facing it has radiance 1
    sun.data.angle = 0.0
    set_cast_shadow(sun.data, shadows)
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = direction.to_track_quat("Z", "Y")
    scene.collection.objects.link(sun)


def add_black_world(scene, temporary: Temporary) -> None:
    """A world that sends no light: its colour black, and where Blender renders worlds by their nodes
    whatever use_nodes says (5.0+, whose new worlds have a grey Background node), every background's
    strength 0."""
    world = temporary.add(bpy.data.worlds.new("ShadeCut black"))
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    if world.use_nodes and world.node_tree is not None:
        for node in world.node_tree.nodes:
            if node.type == "BACKGROUND":
                node.inputs["Strength"].default_value = 0.0
    scene.world = world


def set_materials(view_layer, objects, albedo: Optional[float], temporary: Temporary) -> None:
    """One Lambertian material of the uniform albedo for all, or each slot's own-colour stand-in."""
    if albedo is not None:
        view_layer.material_override = temporary.add(
            diffuse_material("ShadeCut albedo", colour=(albedo, albedo, albedo, 1.0)))
        return
    stand_ins = {}
    for ob in objects:
        if not ob.material_slots:
            # Blender's surface for objects without a material is diffuse 0.8 grey before 5.0 and glossy
            # since: the stand-in of "no material" makes it the same Lambertian grey in every version.
            if None not in stand_ins:
                stand_ins[None] = temporary.add(own_colour_material(None))
            ob.data.materials.append(stand_ins[None])
            temporary.given_slots.append(ob.data)
            continue
        for slot in ob.material_slots:
            if slot.material in stand_ins.values():
                continue  # a mesh shared with an object already done: its slot is swapped
            if slot.material not in stand_ins:
                stand_ins[slot.material] = temporary.add(own_colour_material(slot.material))
            temporary.swapped_slots.append((slot, slot.material))
            slot.material = stand_ins[slot.material]


def set_exact_cycles(scene, resolution, samples: int, indirect: bool, output: Path) -> None:
    """Cycles on the CPU with samples at the pixel centres, identity colour management, the passes
    of the ground truth, written to ``output`` as a 32-bit multilayer EXR."""
    render = scene.render
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y = resolution
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.film_transparent = True
    render.use_border = False
    render.use_compositing = False
    render.use_sequencer = False
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = 0
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 0.01  # Cycles' minimum: every sample at the pixel centre
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    bounces = INDIRECT_BOUNCES if indirect else 0
    cycles.max_bounces = cycles.diffuse_bounces = bounces
    cycles.glossy_bounces = cycles.transmission_bounces = cycles.volume_bounces = 0
    cycles.caustics_reflective = cycles.caustics_refractive = False
    view = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    view.view_transform, view.look, view.exposure, view.gamma = "Standard", "None", 0.0, 1.0
    view.use_curve_mapping = False
    view_layer = scene.view_layers[0]
    view_layer.cycles.use_denoising = False
    for name in ("combined", "normal", "position", "diffuse_color", "diffuse_direct"):
        setattr(view_layer, f"use_pass_{name}", True)
    set_multilayer_exr(render.image_settings)
    render.image_settings.color_depth = "32"
    render.image_settings.exr_codec = "ZIP"
    render.filepath = str(output)
