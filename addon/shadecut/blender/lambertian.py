"""Exact Lambertian renders of Blender meshes with ground truth (normals, depth, mask), by Cycles.

Cycles reproduces I = albedo * max(0, S . N) when the only light is a sun of strength pi and angle 0,
the surface a Diffuse BSDF of roughness 0, bounces are off, the world is black and the colour
management is the identity (Standard view, no look, exposure 0, gamma 1). The pixel filter is a box
0.01 pixel wide, so every sample lands on the pixel centre: the render then samples the surface where
the ground truth does (the conventions' pixel grid), silhouettes are not blended with the background,
and without indirect light one sample is already exact (the direct light of a delta sun has no noise).

Ground truth comes from Cycles passes of the same render: Normal (the shading normal, smooth or
flat as Cycles shades it), Position (turned into camera-frame coordinates: depth = z), alpha (mask),
Diffuse Colour (albedo) and Diffuse Direct (cast shadows).

Nothing of the user's scene is altered: the render happens in a temporary scene that links the
chosen objects, with its own camera, sun, world, material and settings, all removed afterwards, even
when the render fails. Only "own colours" mode swaps the objects' material slots for the duration of
the render (restored in the same ``finally``). Like any F12 render, the render also lands in
Blender's "Render Result" image, which is a view, not scene data.
"""

from __future__ import annotations

import functools
import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional, Sequence, Union

import bpy
import numpy as np
from mathutils import Matrix, Vector

from ..api import light_direction
from . import frames

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, Blender's scene-linear primaries
# The camera of the fitted view looks along world +Y with world +Z up (Blender's "front" view), so
# camera x = world X, camera y = world Z, camera z (toward the viewer) = world -Y.
FRONT_VIEW = Matrix(((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)))
INDIRECT_BOUNCES = 4  # with indirect light on: enough for inter-reflections to settle on concave parts
INDIRECT_SAMPLES = 512  # default samples with indirect light: its noise is then 0.4% rms (README)
SHADOW_RATIO = 0.5  # a lit-facing pixel is in cast shadow when its direct light is below this share
MIN_SHADOW_COSINE = 0.02  # below this S . N the pixel is (nearly) in attached shadow, not cast


class RenderError(RuntimeError):
    """A render that cannot be done as asked (bad objects, light, camera or a failed Cycles run)."""


@dataclass
class LambertianRender:
    """One render and its ground truth, arrays in the project's conventions (row 0 at the top)."""

    image: np.ndarray  # (H, W) float32 linear, after the optional noise and quantization
    clean_image: np.ndarray  # (H, W) float32 linear, Cycles' render before noise and quantization
    normals: np.ndarray  # (H, W, 3) float32 camera frame, unit, 0 outside the mask
    depth: np.ndarray  # (H, W) float32 camera-frame z in scene units (larger = closer), 0 outside the mask
    mask: np.ndarray  # (H, W) bool
    light: np.ndarray  # (3,) unit vector toward the light, camera frame
    albedo: float  # the uniform albedo, or the mean of albedo_map over the mask
    meta: dict = field(default_factory=dict)
    shadow_mask: Optional[np.ndarray] = None  # (H, W) bool, with cast shadows on
    albedo_map: Optional[np.ndarray] = None  # (H, W) float32, with the objects' own colours

    @property
    def depth_pixels(self) -> np.ndarray:
        """Depth in pixel units (z / pixel_size), 0 outside the mask."""
        return np.where(self.mask, self.depth / np.float32(self.meta["pixel_size"]), 0).astype(np.float32)

    def write(self, folder) -> None:
        """Writes the sample folder (image.exr/.png, normals.exr, depth.exr, mask.png, meta.json)."""
        _dataset().write_sample(folder, image=self.image, normals=self.normals, depth=self.depth, mask=self.mask,
                             light=self.light, albedo=self.albedo, meta=self.meta, shadow_mask=self.shadow_mask,
                             albedo_map=self.albedo_map)


def mesh_objects(context, selected_only: bool = True) -> list:
    """The mesh objects to render: the selection, or every mesh visible in the view layer."""
    candidates = context.selected_objects if selected_only else context.view_layer.objects
    return [ob for ob in candidates if ob.type == "MESH" and (selected_only or ob.visible_get())
            and not ob.hide_render]


def camera_frame_light(light, camera_rotation: Matrix) -> np.ndarray:
    """The unit light vector in the camera frame from a camera-frame direction or a Sun object."""
    if isinstance(light, bpy.types.Object):
        try:
            light = camera_rotation.transposed() @ frames.sun_direction_world(light)
        except frames.FrameError as error:
            raise RenderError(str(error)) from error
    try:
        return light_direction(light)
    except ValueError as error:
        raise RenderError(f"the light ({', '.join(f'{v:.3f}' for v in np.ravel(light))} in the camera frame): "
                          f"{error}") from error


def _fitted_ortho(objects, depsgraph, resolution, margin: float) -> tuple[Matrix, float, float, float]:
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


def _camera_info(camera_data, resolution) -> dict:
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


def _diffuse_material(name: str, colour=None, colour_socket=None, base: Optional[bpy.types.Material] = None):
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


def _own_colour_material(material: Optional[bpy.types.Material]):
    """The Lambertian stand-in of a user's material, keeping its base colour (or texture)."""
    if material is None:
        return _diffuse_material("ShadeCut own colour", colour=(0.8, 0.8, 0.8, 1.0))
    surface = None
    if material.use_nodes and material.node_tree is not None:
        for node in material.node_tree.nodes:
            if node.type == "OUTPUT_MATERIAL" and node.is_active_output and node.inputs["Surface"].is_linked:
                surface = node.inputs["Surface"].links[0].from_node
    colour_input = None
    if surface is not None:
        colour_input = surface.inputs.get("Base Color") or surface.inputs.get("Color")
    if colour_input is None:
        return _diffuse_material(f"ShadeCut {material.name}", colour=tuple(material.diffuse_color))
    copy = _diffuse_material(f"ShadeCut {material.name}", base=material,
                             colour=tuple(colour_input.default_value))
    if colour_input.is_linked:
        # The copy has the same nodes under the same names: the socket's path finds its twin there.
        source = copy.node_tree.path_resolve(colour_input.links[0].from_socket.path_from_id())
        diffuse = [node for node in copy.node_tree.nodes if node.type == "BSDF_DIFFUSE"][-1]
        copy.node_tree.links.new(source, diffuse.inputs["Color"])
    return copy


@functools.cache  # asked at every redraw of the panel
def files_unavailable() -> Optional[str]:
    """Why test images cannot be rendered here, or None. Their files go through OpenImageIO (its
    Python module and shadecut._imageio): there in Debian's Blender with a source build, not in the
    add-on's zip (docs/portable_addon.md)."""
    try:
        from .. import _imageio, dataset  # noqa: F401  (that they import is what is asked)
    except ImportError as error:
        return f"Rendering test images needs OpenImageIO, which this installation lacks ({error})"
    return None


def _dataset():
    """shadecut.dataset, or RenderError saying why it cannot be used here."""
    reason = files_unavailable()
    if reason:
        raise RenderError(reason)
    from .. import dataset

    return dataset


def _read_passes(path: Path) -> dict:
    """The multilayer EXR Cycles wrote, as {"Combined.R": (H, W) array, ...}, row 0 at the top."""
    dataset = _dataset()
    try:
        pixels, names = dataset.read_image_channels(path)
    except OSError as error:
        raise RenderError(f"Cycles wrote no readable image: {error}") from error
    # Channels are named "<view layer>.<pass>.<channel>"; drop the view layer.
    return {name.split(".", 1)[1]: pixels[..., i] for i, name in enumerate(names)}


def _quantize(image: np.ndarray, bits: int) -> np.ndarray:
    """Rounds to ``bits``-bit sRGB codes (as an 8/16-bit PNG stores them) and back to linear."""
    levels = 2**bits - 1
    value = np.clip(image, 0.0, 1.0)
    encoded = np.where(value <= 0.0031308, 12.92 * value, 1.055 * value ** (1 / 2.4) - 0.055)
    encoded = np.round(encoded * levels) / levels
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def render_lambertian(
    objects: Sequence[bpy.types.Object],
    *,
    light: Union[Sequence[float], bpy.types.Object] = (1.0, 0.0, 1.0),
    camera: Optional[bpy.types.Object] = None,
    resolution: Sequence[int] = (256, 256),
    albedo: Optional[float] = 0.8,
    shadows: bool = False,
    indirect: bool = False,
    noise: float = 0.0,
    bits: Optional[int] = None,
    seed: int = 0,
    samples: Optional[int] = None,
    margin: float = 0.05,
    frame: Optional[int] = None,
) -> LambertianRender:
    """Renders ``objects`` (mesh objects) as a Lambertian image with exact ground truth.

    Args:
        objects: the meshes to render; every other object of the scene is left out.
        light: a direction toward the light in the camera frame (S_z > 0), or a Sun object (its
            direction only: the strength is always pi so that the image is albedo * cos).
        camera: None = an orthographic camera fitted to the objects, seen from the front (looking
            along +Y, Z up); or a camera object (orthographic or perspective).
        resolution: (width, height) in pixels.
        albedo: uniform diffuse albedo in (0, 1]; None = the objects' own base colours (luminance).
        shadows: cast shadows (off by default: the paper's model has none); their mask is returned.
        indirect: light bouncing between surfaces (off by default).
        noise: standard deviation of Gaussian noise added to the linear image (0 = none).
        bits: 8 or 16 = quantize to that many bits of sRGB code, as a PNG stores the image.
        seed: seed of the noise.
        samples: Cycles samples per pixel; None = 1 without indirect light (the render is then exact)
            and INDIRECT_SAMPLES with it.
        margin: share of the image left free on each side by the fitted camera.
        frame: the frame to render; None = the objects' scene's current frame.

    Raises RenderError for anything that makes the render impossible as asked.
    """
    objects = list(objects)
    resolution = _check_request(objects, camera, resolution, albedo, bits, noise)
    if samples is None:
        samples = INDIRECT_SAMPLES if indirect else 1
    if samples < 1:
        raise RenderError(f"samples must be >= 1; got {samples}")
    if frame is None:
        frame = objects[0].users_scene[0].frame_current if objects[0].users_scene else 1

    temporary = _Temporary()
    scene = bpy.data.scenes.new("ShadeCut Lambertian")
    with tempfile.TemporaryDirectory(prefix="shadecut_render_") as scratch:
        try:
            scene.frame_current = frame
            for ob in objects:
                scene.collection.objects.link(ob)
            view_layer = scene.view_layers[0]
            view_layer.update()  # a new scene has no depsgraph until its view layer is updated
            camera_object = _set_camera(scene, objects, camera, resolution, margin, temporary)
            view_layer.update()
            camera_eval = camera_object.evaluated_get(view_layer.depsgraph)
            camera_matrix = camera_eval.matrix_world.copy()
            rotation = camera_matrix.to_3x3().normalized()
            light_vector = camera_frame_light(light, rotation)
            lens = _camera_info(camera_eval.data, resolution)
            lens.update(fitted=camera is None, name=None if camera is None else camera.name)

            _add_sun(scene, rotation @ Vector(light_vector), shadows, temporary)
            _add_black_world(scene, temporary)
            _set_materials(view_layer, objects, albedo, temporary)
            output = Path(scratch) / "passes.exr"
            _set_exact_cycles(scene, resolution, samples, indirect, output)
            passes = _render_passes(scene, output)
        finally:
            temporary.remove(scene)

    return _assemble(passes, light_vector, camera_matrix, lens, resolution, albedo, shadows, indirect, noise,
                     bits, seed, samples, frame, [ob.name for ob in objects])


def _check_request(objects, camera, resolution, albedo, bits, noise) -> tuple[int, int]:
    """Raises RenderError for a request that cannot be rendered; returns (width, height) as ints."""
    if not objects:
        raise RenderError("no mesh object to render: select one, or add one to the scene")
    not_meshes = [ob.name for ob in objects if ob.type != "MESH"]
    if not_meshes:
        raise RenderError(f"not mesh objects: {', '.join(not_meshes)}")
    hidden = [ob.name for ob in objects if ob.hide_render]
    if hidden:
        raise RenderError(f"disabled for rendering (hide_render): {', '.join(hidden)}")
    width, height = (int(v) for v in resolution)
    if width < 2 or height < 2 or width > 16384 or height > 16384:
        raise RenderError(f"the resolution must be 2 to 16384 pixels per side; got {width} x {height}")
    if albedo is not None and not 0 < albedo <= 1:
        raise RenderError(f"the albedo must be in (0, 1]; got {albedo}")
    if bits not in (None, 8, 16):
        raise RenderError(f"quantization must be 8 or 16 bits; got {bits}")
    if noise < 0 or not math.isfinite(noise):
        raise RenderError(f"the noise level must be >= 0; got {noise}")
    if camera is not None and camera.type != "CAMERA":
        raise RenderError(f"'{camera.name}' is not a camera")
    return width, height


# Which bpy.data collection removes a temporary data-block of each type.
_COLLECTION = {"Object": "objects", "Camera": "cameras", "SunLight": "lights", "World": "worlds",
               "Material": "materials"}


@dataclass
class _Temporary:
    """What a render adds to the file and changes in it, all undone by :meth:`remove`."""

    blocks: list = field(default_factory=list)  # data-blocks, objects first (they use the others)
    swapped_slots: list = field(default_factory=list)  # (material slot, original material), own colours

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
        bpy.data.scenes.remove(scene)
        for block in self.blocks:
            getattr(bpy.data, _COLLECTION[type(block).__name__]).remove(block)


def _set_camera(scene, objects, camera, resolution, margin: float, temporary: _Temporary) -> bpy.types.Object:
    """Links the given camera, or a fitted orthographic one, to the scene as its camera."""
    if camera is None:
        camera = temporary.new_object("ShadeCut camera", bpy.data.cameras.new("ShadeCut camera"))
        matrix, scale, clip_start, clip_end = _fitted_ortho(objects, scene.view_layers[0].depsgraph, resolution,
                                                            margin)
        camera.data.type = "ORTHO"
        camera.data.ortho_scale = scale
        camera.data.clip_start, camera.data.clip_end = clip_start, clip_end
        camera.matrix_world = matrix
    scene.collection.objects.link(camera)
    scene.camera = camera
    return camera


def _add_sun(scene, direction: Vector, shadows: bool, temporary: _Temporary) -> None:
    """A sun shining from ``direction`` (world frame) with irradiance pi and a point-like disc."""
    sun = temporary.new_object("ShadeCut sun", bpy.data.lights.new("ShadeCut sun", "SUN"))
    sun.data.energy = math.pi  # irradiance pi: a white Lambertian surface facing it has radiance 1
    sun.data.angle = 0.0
    sun.data.cycles.cast_shadow = shadows
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = direction.to_track_quat("Z", "Y")
    scene.collection.objects.link(sun)


def _add_black_world(scene, temporary: _Temporary) -> None:
    world = temporary.add(bpy.data.worlds.new("ShadeCut black"))
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    scene.world = world


def _set_materials(view_layer, objects, albedo: Optional[float], temporary: _Temporary) -> None:
    """One Lambertian material of the uniform albedo for all, or each slot's own-colour stand-in."""
    if albedo is not None:
        view_layer.material_override = temporary.add(
            _diffuse_material("ShadeCut albedo", colour=(albedo, albedo, albedo, 1.0)))
        return
    stand_ins = {}
    for ob in objects:
        for slot in ob.material_slots:
            if slot.material in stand_ins.values():
                continue  # a mesh shared with an object already done: its slot is swapped
            if slot.material not in stand_ins:
                stand_ins[slot.material] = temporary.add(_own_colour_material(slot.material))
            temporary.swapped_slots.append((slot, slot.material))
            slot.material = stand_ins[slot.material]


def _set_exact_cycles(scene, resolution, samples: int, indirect: bool, output: Path) -> None:
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
    render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    render.image_settings.color_depth = "32"
    render.image_settings.exr_codec = "ZIP"
    render.filepath = str(output)


def _render_passes(scene, output: Path) -> dict:
    """Renders the scene and reads the passes Cycles wrote to ``output``."""
    outcome = bpy.ops.render.render(scene=scene.name, write_still=True)
    if "FINISHED" not in outcome or not output.is_file():
        raise RenderError(f"Cycles did not finish the render ({', '.join(sorted(outcome))})")
    return _read_passes(output)


def _assemble(passes, light_vector, camera_matrix, lens, resolution, albedo, shadows, indirect, noise, bits, seed,
              samples, frame, object_names) -> LambertianRender:
    """Turns Cycles' passes into the arrays and meta of a :class:`LambertianRender`."""
    width, height = resolution
    mask, clean, normals, depth = _camera_frame_truth(passes, camera_matrix)
    albedo_map, albedo_value = _albedo(passes, mask, albedo)
    shadow_mask = _cast_shadows(passes, mask, normals, light_vector) if shadows else None
    image = _degrade(clean, noise, bits, seed)
    camera = dict(lens, matrix_world=[list(row) for row in camera_matrix])
    pixel_size = _pixel_size(camera, depth, mask)
    meta = {
        "source": "blender_cycles",
        "blender_version": bpy.app.version_string,
        "objects": object_names,
        "frame": frame,
        "light": light_vector.tolist(),
        "light_slant_deg": math.degrees(math.acos(min(1.0, light_vector[2]))),
        "light_tilt_deg": math.degrees(math.atan2(light_vector[1], light_vector[0])) % 360,
        "albedo": albedo_value,
        "albedo_mode": "uniform" if albedo is not None else "own_colours",
        "resolution": [width, height],
        "camera": camera,
        "pixel_size": pixel_size,
        "shadows": shadows,
        "indirect": indirect,
        "noise_sigma": noise,
        "quantization_bits": bits,
        "seed": seed,
        "samples": samples,
        "pixel_filter": "box 0.01 px (samples at pixel centres)",
    }
    if camera["type"] == "perspective":
        meta["pixel_size_note"] = "perspective camera: pixel size at the objects' median distance"
    return LambertianRender(image=image, clean_image=clean, normals=normals, depth=depth,
                            mask=mask, light=light_vector, albedo=albedo_value, meta=meta, shadow_mask=shadow_mask,
                            albedo_map=albedo_map)


def _channels(passes: dict, name: str, channels: str) -> np.ndarray:
    """One pass as an (H, W, len(channels)) array, e.g. ``_channels(passes, "Normal", "XYZ")``."""
    return np.dstack([passes[f"{name}.{c}"] for c in channels])


def _camera_frame_truth(passes: dict, camera_matrix: Matrix) -> tuple[np.ndarray, ...]:
    """The mask, the clean image, and the normals and depth in the camera frame, 0 outside the mask."""
    rotation = np.array(camera_matrix.to_3x3().normalized())
    origin = np.array(camera_matrix.translation)
    mask = passes["Combined.A"] > 0.5
    clean = (_channels(passes, "Combined", "RGB") @ LUMINANCE).astype(np.float32)

    # World to camera frame: v_cam = R^T (v - origin), written for row vectors.
    normals = _channels(passes, "Normal", "XYZ") @ rotation
    length = np.linalg.norm(normals, axis=2, keepdims=True)
    normals = np.where(mask[..., None] & (length > 0), normals / np.maximum(length, 1e-12), 0).astype(np.float32)
    points = (_channels(passes, "Position", "XYZ") - origin) @ rotation
    depth = np.where(mask, points[..., 2], 0).astype(np.float32)
    return mask, clean, normals, depth


def _albedo(passes: dict, mask: np.ndarray, albedo: Optional[float]) -> tuple[Optional[np.ndarray], float]:
    """(albedo map, albedo): (None, the uniform albedo), or the own colours' map and its mean on the mask."""
    if albedo is not None:
        return None, float(albedo)
    albedo_map = np.where(mask, _channels(passes, "DiffCol", "RGB") @ LUMINANCE, 0).astype(np.float32)
    return albedo_map, float(albedo_map[mask].mean()) if mask.any() else 0.0


def _cast_shadows(passes: dict, mask: np.ndarray, normals: np.ndarray, light_vector: np.ndarray) -> np.ndarray:
    """The pixels in cast shadow.

    Diffuse Direct is the light arriving at the surface (sun strength pi: cos where it is lit); a
    pixel facing the light that gets clearly less than its cosine lies in a cast shadow.
    """
    direct = _channels(passes, "DiffDir", "RGB") @ LUMINANCE
    cosine = normals @ light_vector
    return mask & (cosine > MIN_SHADOW_COSINE) & (direct < SHADOW_RATIO * cosine)


def _degrade(clean: np.ndarray, noise: float, bits: Optional[int], seed: int) -> np.ndarray:
    """The clean image with the Gaussian noise (seeded) and the quantization asked for, float32."""
    image = clean.astype(np.float64)
    if noise > 0:
        image = np.maximum(image + np.random.default_rng(seed).normal(0.0, noise, image.shape), 0.0)
    if bits is not None:
        image = _quantize(image, bits)
    return image.astype(np.float32)


def _pixel_size(camera: dict, depth: np.ndarray, mask: np.ndarray) -> float:
    """The size of a pixel in scene units (for a perspective camera, at the objects' median distance)."""
    if camera["type"] == "orthographic":
        return camera["ortho_scale"] / camera["side_px"]
    # A perspective pixel grows with distance; this is its size at the objects' median distance.
    distance = float(-np.median(depth[mask])) if mask.any() else 1.0
    return distance / camera["focal_px"]
