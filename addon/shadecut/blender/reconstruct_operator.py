"""The "Reconstruct" operator: a Blender image in, a new mesh object at the 3-D cursor out (or, with
Apply to = Active object, its maps in the active object's material)."""

from __future__ import annotations

import math
import os
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import bpy
import numpy as np

from .. import api, imaging
from .flip_operator import RESULT_PROPERTY
from .frames import FrameError, light_in_camera_frame
from .preferences import addon_preferences
from .mesh import MeshError, vertex_step
from .result import TargetError, apply_maps, check_target, limited_depth_scale, result_object

# Below this the image is black for the method: it needs shading to read slants from.
DARK_LIMIT = 1e-4
# Colour spaces whose stored 8-bit values are linear already.
LINEAR_SPACES = {"Linear", "Linear ACES", "Linear ACEScg", "Non-Color", "Raw", "XYZ"}
# Blender stores float properties as float32 and clamps an infinity typed or set to this.
FLOAT_MAX = 3.4028234e38


class InputError(ValueError):
    """Bad input the user can fix; the message says how."""


@dataclass
class Job:
    """Everything the worker thread needs, copied out of Blender's data before it starts."""

    name: str
    image: np.ndarray
    mask: np.ndarray
    light: Optional[np.ndarray]  # None = estimate from the image
    light_origin: str  # how the finish report names the light: "estimated light", "light of Sun 'Sun'"
    albedo: Optional[float]
    options: dict
    source_image: Optional[bpy.types.Image]
    output: dict = field(default_factory=dict)  # how to build the result, read with the rest
    created_image: bool = False  # the source image was loaded by this job: removed if it fails
    image_origin: str = ""  # where an image the panel did not name came from: "the Image Texture node ..."
    fraction: float = 0.0
    stage: str = "starting"
    cancel: bool = False
    result: Optional[api.Reconstruction] = None
    error: Optional[BaseException] = None
    started: float = field(default_factory=time.perf_counter)

    def progress(self, fraction: float, stage: str) -> bool:
        self.fraction, self.stage = fraction, stage
        return not self.cancel

    def run(self) -> None:
        try:
            self.result = api.reconstruct(self.image, self.light, self.mask, self.albedo,
                                          progress=self.progress, **self.options)
        except BaseException as error:  # handed to the main thread, which reports it
            self.error = error


def image_pixels(image: bpy.types.Image) -> tuple[np.ndarray, np.ndarray]:
    """Linear intensity (H, W) and mask (H, W) of a Blender image, row 0 at the top.

    Float buffers hold scene-linear values; byte buffers hold the file's encoded values, decoded
    here according to the image's colour space.
    """
    width, height = image.size
    if width * height == 0:
        raise InputError(f"Image '{image.name}' has no pixels (is its file missing?): reload it or choose another")
    if width < 2 or height < 2:
        raise InputError(f"Image '{image.name}' is {width} x {height} pixels: at least 2 x 2 are needed")
    space = image.colorspace_settings.name
    srgb = not image.is_float and space not in LINEAR_SPACES
    if srgb and space != "sRGB":
        raise InputError(f"Image '{image.name}' is in colour space '{space}': set it to sRGB or Linear")
    rgba = np.empty(width * height * image.channels, dtype=np.float32)
    image.pixels.foreach_get(rgba)
    rgba = rgba.reshape(height, width, image.channels)[::-1]
    if image.channels != 4:
        rgba = np.dstack([np.repeat(rgba[..., :1], 3, axis=2) if image.channels < 3 else rgba[..., :3],
                          np.ones((height, width, 1), np.float32)])
    intensity, mask, _ = imaging.intensity_and_mask(rgba, srgb_encoded=srgb)
    finite = np.isfinite(intensity)
    if not finite[mask].all():
        bad = np.count_nonzero(~finite & mask)
        raise InputError(f"Image '{image.name}' has {bad} NaN or infinite pixel{'s' if bad > 1 else ''}: "
                         "shape from shading needs finite intensities")
    intensity = np.where(finite, intensity, 0.0).astype(np.float32)  # outside the mask: unused
    return intensity, mask


def _load_file(filepath: str) -> tuple[bpy.types.Image, bool]:
    """The image of ``filepath`` and whether this call created its datablock (False when
    ``check_existing`` handed back one the user already had)."""
    path = bpy.path.abspath(filepath)
    if not os.path.exists(path):
        raise InputError(f"Cannot read '{filepath}': there is no such file")
    if os.path.isdir(path):
        raise InputError(f"Cannot read '{filepath}': it is a directory, not an image file")
    existing = {image.as_pointer() for image in bpy.data.images}
    try:
        image = bpy.data.images.load(filepath, check_existing=True)
    except RuntimeError as error:
        reason = str(error).strip()
        reason = reason.removeprefix("Error:").strip().removeprefix(f"Cannot read '{filepath}':").strip()
        raise InputError(f"Cannot read '{filepath}': {reason or 'Blender cannot load it'}") from error
    created = image.as_pointer() not in existing
    if tuple(image.size) == (0, 0):
        if created:
            bpy.data.images.remove(image)
        raise InputError(f"Cannot read '{filepath}': it is not an image file Blender can read")
    return image, created


def _source_image(context, settings, filepath: str) -> tuple[bpy.types.Image, bool, str]:
    """The image to reconstruct, whether this call loaded it (see :func:`_load_file`), and where it
    came from when the panel did not name it ("" otherwise)."""
    if filepath:
        return (*_load_file(filepath), "")
    image, origin = _open_image(context, settings)
    return image, False, origin


def active_texture_node(context) -> Optional[bpy.types.Node]:
    """The active object's active material's active node when it is an Image Texture node with an
    image (what texture add-ons such as DeepBump act on), else None."""
    obj = context.active_object
    material = obj.active_material if obj is not None else None
    if material is None or not material.use_nodes or material.node_tree is None:
        return None
    node = material.node_tree.nodes.active
    if node is None or node.type != "TEX_IMAGE" or node.image is None:
        return None
    return node


def _open_image(context, settings) -> tuple[bpy.types.Image, str]:
    """The panel's image; else the image of the Image Editor the operator runs in; else the image of
    the selected Image Texture node; else the image of any open Image Editor. With where it came from."""
    if settings.image is not None:
        return settings.image, ""
    space = context.space_data
    if space is not None and space.type == "IMAGE_EDITOR" and space.image is not None:
        return space.image, ""
    node = active_texture_node(context)
    if node is not None:
        material = context.active_object.active_material
        return node.image, f"the Image Texture node '{node.name}' of material '{material.name}'"
    for area in context.screen.areas if context.screen else ():
        if area.type == "IMAGE_EDITOR" and area.spaces.active.image is not None:
            return area.spaces.active.image, ""
    raise InputError("No image: choose one in the ShadeCut panel, open one in the Image Editor, select an Image "
                     "Texture node in the active object's material, or pick a file")


def _scene_sun(context) -> bpy.types.Object:
    """The scene's only Sun, which stands in for a Sun not picked in the panel."""
    suns = [obj for obj in context.scene.objects if obj.type == "LIGHT" and obj.data.type == "SUN"]
    if len(suns) == 1:
        return suns[0]
    if not suns:
        raise InputError("No Sun picked, and the scene has none: add a Sun and aim it as the light fell on the image, "
                         "or set Light to Estimate")
    names = ", ".join(f"'{sun.name}'" for sun in suns)
    raise InputError(f"No Sun picked, and the scene has {len(suns)} ({names}): pick one in the ShadeCut panel, "
                     "or set Light to Estimate")


def _sun(context, settings) -> tuple[bpy.types.Object, str]:
    """The Sun to read the light from, and how the finish report names its light."""
    if settings.light_object is None:
        sun = _scene_sun(context)
        return sun, f"light of the scene's only Sun '{sun.name}'"
    sun = settings.light_object
    if sun.type == "LIGHT" and sun.data.type != "SUN":
        raise InputError(f"Light '{sun.name}' is a {sun.data.type.lower()} light: shape from shading needs the "
                         "parallel light of a Sun. Pick a Sun, or set Light to Estimate")
    return sun, f"light of Sun '{sun.name}'"


def _light(context, settings) -> tuple[Optional[np.ndarray], str]:
    """The unit direction toward the light in the camera frame (None = estimate it), and how the
    finish report names it."""
    if settings.light_source == "ESTIMATE":
        return None, "estimated light"
    if settings.light_source == "DIRECTION":
        light, origin = np.array(settings.light_direction, dtype=float), "light"
    else:
        sun, origin = _sun(context, settings)
        context.view_layer.update()  # a script may have just moved the sun or the camera
        camera = None
        if settings.frame == "CAMERA":
            camera = settings.camera or context.scene.camera
            if camera is None:
                raise InputError("No camera: choose one in the ShadeCut panel, add one to the scene, "
                                 "or set Seen from to Top view")
        try:
            light = np.array(light_in_camera_frame(sun, camera))
        except FrameError as error:
            raise InputError(str(error)) from error
    try:
        return api.light_direction(light), origin
    except ValueError as error:
        raise InputError(f"The light ({light[0]:.2f}, {light[1]:.2f}, {light[2]:.2f}) cannot be used: {error}") from error


def _finite(value: float) -> bool:
    return math.isfinite(value) and abs(value) < FLOAT_MAX


def _check_output(settings) -> None:
    """The result's size and scale: cheap checks before any work."""
    if not (_finite(settings.width) and settings.width > 0):
        raise InputError(f"Width must be a finite number > 0 (it is {settings.width:g})")
    if not _finite(settings.depth_scale):
        raise InputError(f"Depth scale must be a finite number (it is {settings.depth_scale:g})")
    if not (_finite(settings.max_height) and settings.max_height >= 0):
        raise InputError(f"Max height must be a finite number >= 0 (it is {settings.max_height:g})")


def _has_face(mask: np.ndarray, step: int) -> bool:
    """Whether sampling ``mask`` every ``step`` pixels leaves four masked neighbours (one quad)."""
    sampled = mask[::step, ::step]
    if min(sampled.shape) < 2:
        return False
    return bool((sampled[:-1, :-1] & sampled[1:, :-1] & sampled[:-1, 1:] & sampled[1:, 1:]).any())


def mesh_step(mask: np.ndarray, density: int, max_vertices: int) -> int:
    """The result's sampling step: ``density``, or with density 0 the finest within ``max_vertices``."""
    return density or vertex_step(mask, max_vertices)


def _check_density(name: str, mask: np.ndarray, density: int, max_vertices: int) -> None:
    """A step that leaves fewer than 2 x 2 samples, or no face, would give an empty mesh."""
    step = mesh_step(mask, density, max_vertices)
    if _has_face(mask, step):
        return
    height, width = mask.shape
    usable = next((smaller for smaller in range(min(min(height, width) - 1, step - 1), 0, -1)
                   if _has_face(mask, smaller)), 0)
    if usable == 0:
        raise InputError(f"Image '{name}' has no 2 x 2 block of masked pixels at its {width} x {height} working "
                         "size: there is no surface to build")
    if density:
        raise InputError(f"Density {density} leaves no face on the {width} x {height} working image of '{name}': "
                         f"the largest usable density is {usable}")
    raise InputError(f"Vertex limit {max_vertices:,} gives density {step}, which leaves no face on the {width} x "
                     f"{height} working image of '{name}': raise the Vertex limit, or set Density to {usable} or less")


def _working_size(name: str, image, mask, max_size: int):
    try:
        return imaging.downsample(image, mask, max_size)[:2]
    except ValueError as error:
        height, width = mask.shape
        smallest = math.ceil(max(height, width) / (min(height, width) // 2))
        raise InputError(f"Max size {max_size} px is too small for the {width} x {height} image '{name}' "
                         f"(fewer than 2 x 2 pixels would remain): use at least {smallest}, or 0 for full size"
                         ) from error


def prepare_job(context, filepath: str = "") -> Job:
    """Reads the settings and the image into a :class:`Job`; raises InputError for bad input.

    An image loaded from ``filepath`` by this call is removed again when the input is refused.
    """
    settings = context.scene.shadecut
    _check_output(settings)
    source, created, origin = _source_image(context, settings, filepath)
    try:
        job = _prepare(context, settings, source, created)
    except BaseException:
        if created:
            bpy.data.images.remove(source)
        raise
    job.image_origin = origin
    return job


def _prepare(context, settings, source: bpy.types.Image, created: bool) -> Job:
    image, mask = image_pixels(source)
    image, mask = _working_size(source.name, image, mask, settings.max_resolution)
    if not mask.any():
        raise InputError(f"Image '{source.name}' is transparent everywhere: its alpha leaves no pixel to reconstruct")
    if not image[mask].max() > DARK_LIMIT:
        raise InputError(f"Image '{source.name}' is black: shape from shading needs a lit, shaded surface")
    if settings.target == "ACTIVE_MATERIAL":
        try:
            check_target(context.active_object, normal_map=settings.normal_map, height_map=settings.height_map)
        except TargetError as error:
            raise InputError(str(error)) from error
    else:
        _check_density(source.name, mask, settings.density, settings.max_vertices)
    light, light_origin = _light(context, settings)

    preferences = addon_preferences(context)
    method = settings.method
    if method == "DEFAULT":
        method = preferences.default_method if preferences else api.ReconstructOptions().method.name
    seamless = settings.seamless and settings.scene == "relief"
    if seamless:
        mask = np.ones_like(mask)  # a tiling surface covers the whole image
    options = dict(scene=settings.scene, method=method, labels=settings.labels, data_weight=settings.data_weight,
                   integrator=settings.integrator, fit_shading=settings.fit_shading, seamless=seamless,
                   threads=preferences.threads if preferences else 0)
    return Job(
        name=Path(source.name).stem or source.name,
        image=image,
        mask=mask,
        light=light,
        light_origin=light_origin,
        albedo=None if settings.auto_albedo or light is None else settings.albedo,
        options=options,
        source_image=source,
        output=_output_settings(settings, context),
        created_image=created,
    )


def _output_settings(settings, context=None) -> dict:
    target = None  # the name of the object whose material gets the maps; None = a new object
    if settings.target == "ACTIVE_MATERIAL" and context is not None and context.active_object is not None:
        target = context.active_object.name
    return dict(width=settings.width, depth_scale=settings.depth_scale, max_height=settings.max_height,
                density=settings.density, max_vertices=settings.max_vertices, displace=settings.output == "DISPLACE",
                normal_map=settings.normal_map, height_map=settings.height_map, target=target)


def _finish_on_target(operator, context, job: Job, out: dict) -> set[str]:
    """Puts the finished job's maps into the target object's material (result.apply_maps)."""
    result = job.result
    obj = context.scene.objects.get(out["target"])
    try:
        material = apply_maps(obj, result.depth, result.normals, result.mask, normal_map=out["normal_map"],
                              height_map=out["height_map"], depth_scale=out["depth_scale"],
                              max_height=out["max_height"])
    except TargetError as error:
        discard_job(job)
        operator.report({"ERROR"}, f"Cannot apply the maps: {error}")
        return {"CANCELLED"}
    maps = " and ".join(kind for kind, wanted in (("normal map", out["normal_map"]), ("height map", out["height_map"]))
                        if wanted)
    light = ", ".join(f"{v:.3f}" for v in result.light)
    operator.report({"INFO"}, f"{maps.capitalize()} of image '{job.source_image.name}' applied to "
                              f"material '{material.name}' of '{obj.name}': {job.options['method']} in "
                              f"{time.perf_counter() - job.started:.1f} s, {job.light_origin} ({light}), "
                              f"albedo {result.albedo:.3f}")
    report_orientation(operator, result)
    return {"FINISHED"}


AMBIGUOUS_WARNING = ("The image cannot tell this shape from its inversion (a dome from a hollow: the light is "
                     "near the viewer); the outline, or for a relief the light from above, chose. If it came out "
                     "the wrong way, click Flip")


def report_orientation(operator, result) -> None:
    """Warns when the image could not choose the result's orientation (stats.orientation_ambiguous)."""
    if result.stats.orientation_ambiguous:
        operator.report({"WARNING"}, AMBIGUOUS_WARNING)


def discard_job(job: Job) -> None:
    """Removes what a failed or cancelled job brought in: the image it loaded itself, if any."""
    if job.created_image and job.source_image is not None:
        try:
            bpy.data.images.remove(job.source_image)
        except ReferenceError:  # already gone (the user removed it meanwhile)
            pass
        job.source_image, job.created_image = None, False


def finish_job(operator, context, job: Job) -> set[str]:
    """Reports the outcome of a finished job and, on success, builds the result object (or, with
    Apply to = Active object, puts the maps into that object's material).

    On failure nothing is added, and an image the job loaded itself is removed again.
    """
    if job.error is not None:
        discard_job(job)
    if isinstance(job.error, api.Cancelled):
        operator.report({"WARNING"}, "Reconstruction cancelled: nothing was added")
        return {"CANCELLED"}
    if isinstance(job.error, ValueError):
        operator.report({"ERROR"}, f"Cannot reconstruct: {job.error}")
        return {"CANCELLED"}
    if job.error is not None:
        operator.report({"ERROR"}, f"Reconstruction failed ({type(job.error).__name__}: {job.error})")
        return {"CANCELLED"}
    out = job.output or _output_settings(context.scene.shadecut, context)
    if out.get("target"):
        return _finish_on_target(operator, context, job, out)
    result = job.result
    step = mesh_step(result.mask, out["density"], out["max_vertices"])
    try:
        obj = result_object(
            context, job.name, result.depth, result.normals, result.mask,
            source_image=job.source_image, width=out["width"],
            depth_scale=limited_depth_scale(result.depth, result.mask, out["width"], out["depth_scale"],
                                            out["max_height"]),
            density=step, displace=out["displace"], normal_map=out["normal_map"], height_map=out["height_map"],
        )
    except MeshError as error:
        discard_job(job)
        operator.report({"ERROR"}, f"Cannot build the result: {error}")
        return {"CANCELLED"}
    light = ", ".join(f"{v:.3f}" for v in result.light)
    source = f"image '{job.source_image.name}' from {job.image_origin}, " if job.image_origin else ""
    operator.report({"INFO"}, f"'{obj.name}': {source}{job.options['method']} in {time.perf_counter() - job.started:.1f} s, "
                              f"{job.light_origin} ({light}), albedo {result.albedo:.3f}, "
                              f"{len(obj.data.vertices):,} vertices (density {step})")
    obj[RESULT_PROPERTY] = True
    report_orientation(operator, result)
    return {"FINISHED"}


class SHADECUT_OT_reconstruct(bpy.types.Operator):
    """Reconstruct a 3-D surface from the shading of an image (Chang, Lee & Lee graph cuts)"""

    bl_idname = "shadecut.reconstruct"
    bl_label = "Reconstruct"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(
        name="Image file", subtype="FILE_PATH", options={"SKIP_SAVE"},
        description="An image file to use instead of the panel's image",
    )
    use_file_browser: bpy.props.BoolProperty(options={"HIDDEN", "SKIP_SAVE"})
    filter_image: bpy.props.BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})

    _job: Optional[Job] = None
    _thread: Optional[threading.Thread] = None
    _timer = None
    _interactive = False

    def invoke(self, context, event):
        self._interactive = True
        if self.use_file_browser and not self.filepath:
            context.window_manager.fileselect_add(self)
            return {"RUNNING_MODAL"}
        return self.execute(context)

    def execute(self, context):
        try:
            job = prepare_job(context, self.filepath)
        except InputError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except ValueError as error:  # any other refusal of the input by the library
            self.report({"ERROR"}, f"Cannot reconstruct: {error}")
            return {"CANCELLED"}
        if not self._interactive or bpy.app.background:
            job.run()
            return finish_job(self, context, job)
        return self._start_modal(context, job)

    def _start_modal(self, context, job: Job):
        self._job = job
        self._thread = threading.Thread(target=job.run, name="shadecut-reconstruct", daemon=True)
        self._thread.start()
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(0.1, window=context.window)
        window_manager.progress_begin(0, 100)
        window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC":
            job.cancel = True
        if event.type != "TIMER" and not job.cancel:
            return {"PASS_THROUGH"}
        if self._thread.is_alive():
            context.window_manager.progress_update(int(100 * job.fraction))
            context.workspace.status_text_set(
                f"ShadeCut: {job.stage} {job.fraction:.0%}" + (" (cancelling)" if job.cancel else "  Esc to cancel"))
            return {"RUNNING_MODAL"}
        self._end_modal(context)
        return finish_job(self, context, job)

    def _end_modal(self, context):
        window_manager = context.window_manager
        window_manager.event_timer_remove(self._timer)
        window_manager.progress_end()
        context.workspace.status_text_set(None)
