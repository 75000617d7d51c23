"""The "Reconstruct from shading" operator: a Blender image in, a new mesh object out."""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import bpy
import numpy as np

from .. import api, imaging
from .frames import FrameError, light_in_camera_frame
from .preferences import addon_preferences
from .result import limited_depth_scale, result_object

# Below this the image is black for the method: it needs shading to read slants from.
DARK_LIMIT = 1e-4
# Colour spaces whose stored 8-bit values are linear already.
LINEAR_SPACES = {"Linear", "Linear ACES", "Linear ACEScg", "Non-Color", "Raw", "XYZ"}


class InputError(ValueError):
    """Bad input the user can fix; the message says how."""


@dataclass
class Job:
    """Everything the worker thread needs, copied out of Blender's data before it starts."""

    name: str
    image: np.ndarray
    mask: np.ndarray
    light: Optional[np.ndarray]  # None = estimate from the image
    albedo: Optional[float]
    options: dict
    source_image: Optional[bpy.types.Image]
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
    return intensity, mask


def _source_image(context, settings, filepath: str) -> bpy.types.Image:
    if filepath:
        try:
            return bpy.data.images.load(filepath, check_existing=True)
        except RuntimeError as error:
            raise InputError(f"Cannot read '{filepath}': {error}") from error
    if settings.image is not None:
        return settings.image
    space = context.space_data
    if space is not None and space.type == "IMAGE_EDITOR" and space.image is not None:
        return space.image
    for area in context.screen.areas if context.screen else ():
        if area.type == "IMAGE_EDITOR" and area.spaces.active.image is not None:
            return area.spaces.active.image
    raise InputError("No image: choose one in the ShadeCut panel, open one in the Image Editor, or pick a file")


def _light(context, settings) -> Optional[np.ndarray]:
    if settings.light_source == "ESTIMATE":
        return None
    if settings.light_source == "DIRECTION":
        light = np.array(settings.light_direction, dtype=float)
    else:
        context.view_layer.update()  # a script may have just moved the sun or the camera
        camera = None
        if settings.frame == "CAMERA":
            camera = settings.camera or context.scene.camera
            if camera is None:
                raise InputError("No camera: choose one in the ShadeCut panel, add one to the scene, "
                                 "or read the light in the image plane")
        try:
            light = np.array(light_in_camera_frame(settings.light_object, camera))
        except FrameError as error:
            raise InputError(str(error)) from error
    try:
        return api.light_direction(light)
    except ValueError as error:
        raise InputError(f"The light ({light[0]:.2f}, {light[1]:.2f}, {light[2]:.2f}) cannot be used: {error}") from error


def prepare_job(context, filepath: str = "") -> Job:
    """Reads the settings and the image into a :class:`Job`; raises InputError for bad input."""
    settings = context.scene.shadecut
    source = _source_image(context, settings, filepath)
    image, mask = image_pixels(source)
    image, mask, _ = imaging.downsample(image, mask, settings.max_resolution)
    if not mask.any():
        raise InputError(f"Image '{source.name}' is transparent everywhere: its alpha leaves no pixel to reconstruct")
    if not image[mask].max() > DARK_LIMIT:
        raise InputError(f"Image '{source.name}' is black: shape from shading needs a lit, shaded surface")
    light = _light(context, settings)

    preferences = addon_preferences(context)
    method = settings.method
    if method == "DEFAULT":
        method = preferences.default_method if preferences else api.ReconstructOptions().method.name
    options = dict(scene=settings.scene, method=method, labels=settings.labels, data_weight=settings.data_weight,
                   integrator=settings.integrator, threads=preferences.threads if preferences else 0)
    return Job(
        name=Path(source.name).stem or source.name,
        image=image,
        mask=mask,
        light=light,
        albedo=None if settings.auto_albedo or light is None else settings.albedo,
        options=options,
        source_image=source,
    )


def finish_job(operator, context, job: Job) -> set[str]:
    """Reports the outcome of a finished job and, on success, builds the result object."""
    if isinstance(job.error, api.Cancelled):
        operator.report({"WARNING"}, "Reconstruction cancelled: nothing was added")
        return {"CANCELLED"}
    if isinstance(job.error, ValueError):
        operator.report({"ERROR"}, f"Cannot reconstruct: {job.error}")
        return {"CANCELLED"}
    if job.error is not None:
        operator.report({"ERROR"}, f"Reconstruction failed ({type(job.error).__name__}: {job.error})")
        return {"CANCELLED"}
    settings = context.scene.shadecut
    result = job.result
    obj = result_object(
        context, job.name, result.depth, result.normals, result.mask,
        source_image=job.source_image, width=settings.width,
        depth_scale=limited_depth_scale(result.depth, result.mask, settings.width, settings.depth_scale,
                                        settings.max_height),
        density=settings.density, displace=settings.output == "DISPLACE", normal_map=settings.normal_map,
    )
    light = ", ".join(f"{v:.3f}" for v in result.light)
    light_kind = "estimated light" if job.light is None else "light"
    operator.report({"INFO"}, f"'{obj.name}': {job.options['method']} in {time.perf_counter() - job.started:.1f} s, "
                              f"{light_kind} ({light}), albedo {result.albedo:.3f}")
    return {"FINISHED"}


class SHADECUT_OT_reconstruct(bpy.types.Operator):
    """Reconstruct a 3-D surface from the shading of an image (Chang, Lee & Lee graph cuts)"""

    bl_idname = "shadecut.reconstruct"
    bl_label = "Reconstruct from shading"
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
