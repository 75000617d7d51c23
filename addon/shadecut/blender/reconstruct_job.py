"""A reconstruction as a job: prepared from the scene (settings, image or Photographs, light; every
check that can refuse the input), run on a worker thread or in place, and finished into the result object or
the target's material (or nothing, when it failed or was cancelled)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import bpy
import numpy as np

from .. import api
from .flip_operator import RESULT_PROPERTY, report_orientation
from .image_input import (InputError, image_orientation, image_pixels, image_to_reconstruct, picked_mask,
                          read_photographs, show_mask)
from .light_input import photograph_lights, side_light, side_origin, side_tilt, sun_light, unit_light
from .preferences import addon_preferences
from .mesh import MeshError
from .result import (TargetError, apply_maps, check_collection, check_target, limited_depth_scale, residual_image,
                     result_object)
from .wording import short_number, with_article

# Below this the image is black for the method: it needs shading to read slants from.
DARK_LIMIT = 1e-4
# Blender stores float properties as float32 and clamps an infinity typed or set to this.
FLOAT_MAX = 3.4028234e38


@dataclass
class Job:
    """Everything the worker thread needs, copied out of Blender's data before it starts."""

    name: str
    image: np.ndarray  # (H, W) linear intensity; several photographs: (K, H, W)
    colour: Optional[np.ndarray]  # (H, W, 3) linear RGB of a colour image (K of them: (K, H, W, 3))
    mask: Optional[np.ndarray]  # None = an object without alpha: cut out of its background by reconstruct()
    light: Optional[np.ndarray]  # None = estimate from the image; several photographs: K x 3
    light_origin: str  # how the finish report names the light: "estimated light", "light of Sun 'Sun'"
    albedo: Optional[float]
    options: dict
    source_image: Optional[bpy.types.Image]
    output: dict = field(default_factory=dict)  # how to build the result, read with the rest
    created_image: bool = False  # the source image was loaded by this job: removed if it fails
    image_origin: str = ""  # where an image the panel did not name came from: "the Image Texture node ..."
    shrunk: str = ""  # how Max size shrank the image, for the finish report: ", worked at 512 x 384 (...)"
    turned: bool = False  # the file is stored turned (EXIF orientation): its pixels were turned upright
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
            image = self.image if self.colour is None else self.colour
            if self.image.ndim == 3:  # several photographs: as a list, which needs no lights to be read as such
                image = list(image)
            self.result = api.reconstruct(image, self.light, self.mask, self.albedo,
                                          progress=self.progress, **self.options)
        except BaseException as error:  # handed to the main thread, which reports it
            self.error = error


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
        raise InputError(f"Light '{sun.name}' is {with_article(sun.data.type)} light: shape from shading needs the "
                         "parallel light of a Sun. Pick a Sun, or set Light to Estimate")
    return sun, f"light of Sun '{sun.name}'"


def _light(context, settings) -> tuple[Optional[np.ndarray], str]:
    """The unit direction toward the light in the camera frame (None = estimate it), and how the
    finish report names it."""
    if settings.light_source == "ESTIMATE":
        return None, "estimated light"
    if settings.light_source == "DIRECTION":
        return unit_light(settings.light_direction), "light"
    if settings.light_source == "SIDE":
        return side_light(settings.light_side, "The image"), side_origin([settings.light_side])
    sun, origin = _sun(context, settings)
    return unit_light(sun_light(context, settings, sun)), origin


def _finite(value: float) -> bool:
    return math.isfinite(value) and abs(value) < FLOAT_MAX


def _check_output(settings) -> None:
    """The result's size and scale: cheap checks before any work."""
    if not (_finite(settings.width) and settings.width > 0):
        raise InputError(f"Width must be a finite number > 0 (it is {settings.width:g})")
    if not _finite(settings.depth_scale):
        raise InputError(f"Depth scale must be a finite number (it is {settings.depth_scale:g})")
    if settings.limit_height and not (_finite(settings.max_height) and settings.max_height > 0):
        raise InputError(f"Max height must be a finite number > 0 (it is {settings.max_height:g})")


def _density(settings) -> int:
    """The density asked for: 0 = automatic (Auto density), as mesh_step takes it."""
    return 0 if settings.auto_density else settings.density


def _height_limit(settings) -> float:
    """The height limit asked for: 0 = none (Limit height off), as limited_depth_scale takes it."""
    return settings.max_height if settings.limit_height else 0.0


def _has_face(mask: np.ndarray, step: int) -> bool:
    """Whether sampling ``mask`` every ``step`` pixels leaves four masked neighbours (one quad)."""
    sampled = mask[::step, ::step]
    if min(sampled.shape) < 2:
        return False
    return bool((sampled[:-1, :-1] & sampled[1:, :-1] & sampled[:-1, 1:] & sampled[1:, 1:]).any())


def mesh_step(mask: np.ndarray, density: int, max_vertices: int) -> int:
    """The result's sampling step: ``density``, or with density 0 the finest within ``max_vertices``."""
    return density or api.vertex_step(mask, max_vertices)


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
                     f"{height} working image of '{name}': raise the Vertex limit, or turn Auto density off and "
                     f"set Density to {usable} or less")


def prepare_job(context, filepath: str = "") -> Job:
    """Reads the settings and the image (or the panel's Photographs) into a :class:`Job`; raises
    InputError for bad input.

    An image loaded from ``filepath`` by this call is removed again when the input is refused.
    """
    settings = context.scene.shadecut
    _check_output(settings)
    if settings.photographs and not filepath:
        return _prepare_photographs(context, settings)
    source, created, origin = image_to_reconstruct(context, settings, filepath)
    try:
        job = _prepare(context, settings, source, created)
    except BaseException:
        if created:
            bpy.data.images.remove(source)
        raise
    job.image_origin = origin
    return job


def _check_lit(named: str, image: np.ndarray, mask: np.ndarray) -> None:
    """InputError for an image (``named``: "Image 'x.png'") with no opaque pixel, or none lit."""
    if not mask.any():
        raise InputError(f"{named} is transparent everywhere: its alpha leaves no pixel to reconstruct")
    if not image[mask].max() > DARK_LIMIT:
        raise InputError(f"{named} is black: shape from shading needs a lit, shaded surface")


def _check_target_of(context, settings) -> None:
    if settings.target == "ACTIVE_MATERIAL":
        try:
            check_target(context.active_object, normal_map=settings.normal_map, height_map=settings.height_map)
        except TargetError as error:
            raise InputError(str(error)) from error


def _prepare(context, settings, source: bpy.types.Image, created: bool) -> Job:
    image, mask, factor, colour = image_pixels(source, settings.max_resolution)
    _check_lit(f"Image '{source.name}'", image, mask)
    _check_target_of(context, settings)
    light, light_origin = _light(context, settings)
    job = _job(context, settings, source, image, colour, mask, light)
    job.light_origin, job.created_image = light_origin, created
    job.shrunk = _shrunk(source, image.shape, factor, settings.max_resolution)
    job.turned = image_orientation(source) != 1
    return job


def _prepare_photographs(context, settings) -> Job:
    """The Job of the panel's Photographs: one row is exactly the single image's call with its light."""
    photographs = read_photographs(settings.photographs, settings.max_resolution)
    first = photographs.sources[0]
    _check_lit("Every photograph" if len(photographs.sources) > 1 else f"Image '{first.name}'",
               photographs.images.max(axis=0), photographs.mask)
    _check_target_of(context, settings)
    lights, light_origin = photograph_lights(context, settings, settings.photographs)
    images, colours = photographs.images, photographs.colours
    if len(photographs.sources) == 1:  # the single image's own call
        images, colours = images[0], None if colours is None else colours[0]
        lights = None if lights is None else lights[0]
    job = _job(context, settings, first, images, colours, photographs.mask, lights)
    job.light_origin = light_origin
    job.shrunk = _shrunk(first, photographs.mask.shape, photographs.factor, settings.max_resolution)
    job.turned = image_orientation(first) != 1
    return job


def _job(context, settings, source: bpy.types.Image, image: np.ndarray, colour: Optional[np.ndarray],
         mask: np.ndarray, light: Optional[np.ndarray]) -> Job:
    """The Job of pixels already read (one image (H, W), or a stack (K, H, W) with K x 3 lights):
    the method, the mask the Subject asks for, the checks of the result's place and density."""
    preferences = addon_preferences(context)
    several = image.ndim == 3  # the albedo is then fitted per pixel
    method = settings.method
    if method == "DEFAULT":
        method = preferences.default_method if preferences else api.ReconstructOptions().method.name
    seamless = settings.seamless and settings.scene == "relief"
    shape = mask.shape
    if seamless:
        mask = np.ones_like(mask)  # a tiling surface covers the whole image
    elif settings.scene == "object" and settings.mask_image is not None:
        mask = picked_mask(settings.mask_image, source, settings.max_resolution)
    elif settings.scene == "object" and mask.all():
        mask = None  # no alpha: reconstruct() cuts the object out of a plain background
    if settings.target != "ACTIVE_MATERIAL":
        try:
            check_collection(context.collection)  # before the work, not after it
        except MeshError as error:
            raise InputError(f"Cannot add the result: {error}") from error
        _check_density(source.name, np.ones(shape, dtype=bool) if mask is None else mask, _density(settings),
                       settings.max_vertices)
    options = dict(scene=settings.scene, method=method, labels=settings.labels, data_weight=settings.data_weight,
                   integrator=settings.integrator, fit_shading=settings.fit_shading, seamless=seamless,
                   albedo_method=settings.albedo_method, detail_size=settings.detail_size,
                   light_slant=settings.light_slant, first_light_tilt=side_tilt(settings.first_light_side),
                   light_distance=settings.light_distance if several and light is not None else 0.0,
                   threads=preferences.threads if preferences else 0)
    return Job(
        name=Path(source.name).stem or source.name,
        image=image,
        colour=colour,
        mask=mask,
        light=light,
        light_origin="",
        albedo=None if settings.auto_albedo or light is None or several else settings.albedo,
        options=options,
        source_image=source,
        output=_output_settings(settings, context, several),
    )


def _shrunk(source: bpy.types.Image, working: tuple[int, int], factor: int, max_size: int) -> str:
    """What the finish report says of the working size: nothing at full size."""
    if factor == 1:
        return ""
    width, height = source.size
    return f", worked at {working[1]} x {working[0]} (1/{factor} of {width} x {height}: Max size {max_size} px)"


def _output_settings(settings, context=None, several: bool = False) -> dict:
    """How to build the result; several photographs always give the normal map, what they measure best."""
    target = None  # the name of the object whose material gets the maps; None = a new object
    if settings.target == "ACTIVE_MATERIAL" and context is not None and context.active_object is not None:
        target = context.active_object.name
    return dict(width=settings.width, depth_scale=settings.depth_scale, max_height=_height_limit(settings),
                density=_density(settings), max_vertices=settings.max_vertices, displace=settings.output == "DISPLACE",
                normal_map=settings.normal_map or (several and target is None), height_map=settings.height_map,
                residual_map=settings.residual_map, target=target)


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
    operator.report({"INFO"}, f"{maps.capitalize()} of image '{job.source_image.name}' applied to "
                              f"material '{material.name}' of '{obj.name}': {job.options['method']} in "
                              f"{time.perf_counter() - job.started:.1f} s, {_lights_used(job)}, "
                              f"albedo {result.albedo:.3f}{job.shrunk}{report_cut_out(operator, job)}"
                              f"{_residual_map(job, out)}")
    report_orientation(operator, result)
    report_albedo(operator, result)
    return {"FINISHED"}


def _lights_used(job: Job) -> str:
    """What the finish report says of the light: its direction; of several photographs, how many, their
    lights' origin, how many pixels fewer than three of them lit and where the graph cut chose which
    of four to leave out."""
    stats = job.result.stats
    if stats.photographs == 1:
        return f"{job.light_origin} ({_direction_text(job.result.light)})"
    origin = _estimated_lights(job) if stats.light_estimated else job.light_origin
    four = (f"; {stats.four_fit_pixels:,} where one of four disagreed (a highlight or a cast shadow): the graph "
            "cut chose which to leave out" if stats.four_fit_pixels else "")
    return (f"{stats.photographs} photographs under {origin} ({stats.pair_pixels:,} pixels lit in only two "
            f"of them, {stats.single_pixels + stats.dark_pixels:,} in fewer: filled from around{four})")


def _direction_text(direction) -> str:
    """"0.639, 0.000, 0.769": three decimals, a component that rounds to zero without its sign."""
    return ", ".join(f"{round(float(v), 3) + 0.0:.3f}" for v in direction)


def _estimated_lights(job: Job) -> str:
    """What the finish report says of the lights the library found for several photographs: each
    direction, the slant they were found at (Light slant, which the depth's scale follows) and how far
    their turn about the viewer is uncertain."""
    stats = job.result.stats
    found = "; ".join(_direction_text(light) for light in job.result.lights)
    uncertain = (f", their turn about the viewer uncertain by {stats.light_uncertainty:.1f} degrees"
                 if np.isfinite(stats.light_uncertainty) else "")
    turned = (", turned by half a circle from First light's side: the object's outline showed it inside out"
              if stats.lights_turned_by_outline else "")
    return (f"lights estimated from them ({found}) at {short_number(job.options['light_slant'])} degrees from the "
            f"viewer (Light slant, which the depth's scale follows){uncertain}{turned}")


def _residual_map(job: Job, out: dict) -> str:
    """With Residual map on, the image '<name> residual' (result.residual_image) and what the finish
    report says of it; else nothing."""
    if not out.get("residual_map"):
        return ""
    result = job.result
    image = residual_image(f"{job.name} residual", result.residual, result.albedo_map, result.mask)
    return f", the residual map: image '{image.name}'"


def report_albedo(operator, result) -> None:
    """A warning when the albedo typed in lies below much of the image (``stats.albedo_message``)."""
    if result.stats.albedo_message:
        operator.report({"WARNING"}, result.stats.albedo_message)


def report_cut_out(operator, job: Job) -> str:
    """What the finish report adds about a cut-out (the mask shown as the image '<name> mask'); a
    warning when none was found, which says why and what to do."""
    stats = job.result.stats
    if stats.cut_out == api.CutOutOutcome.found:
        return f", {stats.cut_out_message} (the mask: image '{show_mask(job.name, job.result.mask).name}')"
    if stats.cut_out != api.CutOutOutcome.not_tried:
        operator.report({"WARNING"}, f"No object cut out of image '{job.source_image.name}', which has no alpha: "
                                     f"{stats.cut_out_message}. The whole image was reconstructed: pick a Mask image, "
                                     "or set Subject to Relief for a surface that fills the frame")
    return ""


def discard_job(job: Job) -> None:
    """Removes what a failed or cancelled job brought in: the image it loaded itself, if any."""
    if job.created_image and job.source_image is not None:
        try:
            bpy.data.images.remove(job.source_image)
        except ReferenceError:  # already gone (the user removed it meanwhile)
            pass
        job.source_image, job.created_image = None, False


def _shown_colour(job: Job) -> Optional[np.ndarray]:
    """What the result's material shows in place of the source image: the de-lit colour when there is
    one; for a file stored turned, else, its upright pixels (the stored file would lie turned on the
    result's UVs); None: the source image itself."""
    result = job.result
    shown = result.albedo_map if result.albedo_colour is None else result.albedo_colour
    if shown is None and job.turned:
        shown = job.image if job.colour is None else job.colour
    return shown


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
            albedo=_shown_colour(job),
        )
    except MeshError as error:
        discard_job(job)
        operator.report({"ERROR"}, f"Cannot build the result: {error}")
        return {"CANCELLED"}
    source = f"image '{job.source_image.name}' from {job.image_origin}, " if job.image_origin else ""
    operator.report({"INFO"}, f"'{obj.name}': {source}{job.options['method']} in {time.perf_counter() - job.started:.1f} s, "
                              f"{_lights_used(job)}, albedo {result.albedo:.3f}, "
                              f"{len(obj.data.vertices):,} vertices (density {step}){job.shrunk}"
                              f"{report_cut_out(operator, job)}{_residual_map(job, out)}")
    obj[RESULT_PROPERTY] = True
    report_orientation(operator, result)
    report_albedo(operator, result)
    return {"FINISHED"}

