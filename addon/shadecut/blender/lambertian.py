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

This module checks the request and runs the render; the temporary scene is set up by
:mod:`.lambertian_scene`, and Cycles' passes become a :class:`LambertianRender` in
:mod:`.lambertian_passes`.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Optional, Sequence, Union

import bpy
import numpy as np
from mathutils import Matrix, Vector

from ..api import light_direction
from . import frames, lambertian_passes, lambertian_scene
# Part of this module's interface, written where they are built.
from .lambertian_passes import LambertianRender, files_unavailable  # noqa: F401
from .lambertian_scene import RenderError
from .wording import short_number

INDIRECT_SAMPLES = 512  # default samples with indirect light: their noise is measured in docs/datasets_and_evaluation.md


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
        shown = ", ".join(short_number(value) for value in np.ravel(light))
        raise RenderError(f"the light ({shown} in the camera frame): {error}") from error


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

    temporary = lambertian_scene.Temporary()
    scene = bpy.data.scenes.new("ShadeCut Lambertian")
    with tempfile.TemporaryDirectory(prefix="shadecut_render_") as scratch:
        try:
            scene.frame_current = frame
            for ob in objects:
                scene.collection.objects.link(ob)
            view_layer = scene.view_layers[0]
            view_layer.update()  # a new scene has no depsgraph until its view layer is updated
            camera_object = lambertian_scene.set_camera(scene, objects, camera, resolution, margin, temporary)
            view_layer.update()
            camera_eval = camera_object.evaluated_get(view_layer.depsgraph)
            camera_matrix = camera_eval.matrix_world.copy()
            rotation = camera_matrix.to_3x3().normalized()
            light_vector = camera_frame_light(light, rotation)
            lens = lambertian_scene.camera_info(camera_eval.data, resolution)
            lens.update(fitted=camera is None, name=None if camera is None else camera.name)

            lambertian_scene.add_sun(scene, rotation @ Vector(light_vector), shadows, temporary)
            lambertian_scene.add_black_world(scene, temporary)
            lambertian_scene.set_materials(view_layer, objects, albedo, temporary)
            output = Path(scratch) / "passes.exr"
            lambertian_scene.set_exact_cycles(scene, resolution, samples, indirect, output)
            passes = _render_passes(scene, output)
        finally:
            temporary.remove(scene)

    return lambertian_passes.assemble(passes, light_vector, camera_matrix, lens, resolution, albedo, shadows,
                                      indirect, noise, bits, seed, samples, frame, [ob.name for ob in objects])


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


def _render_passes(scene, output: Path) -> dict:
    """Renders the scene and reads the passes Cycles wrote to ``output``."""
    outcome = bpy.ops.render.render(scene=scene.name, write_still=True)
    if "FINISHED" not in outcome or not output.is_file():
        raise RenderError(f"Cycles did not finish the render ({', '.join(sorted(outcome))})")
    return lambertian_passes.read_passes(output)
