"""The settings on the scene, one PropertyGroup per operator: ``scene.shadecut`` (reconstruction)
and ``scene.shadecut_render`` (the Lambertian test render)."""

from __future__ import annotations

import bpy
import numpy as np

from ..api import (LIGHT_SIDES, MAX_VERTICES, SIDE_LIGHT_SLANT_DEGREES, AlbedoMethod, Integrator, ReconstructOptions,
                   SceneKind, option_fields)
from . import lambertian
from .light_input import UNPICKED_SIDE, side_of_image, side_tilt
from .preferences import METHOD_ITEMS

# The library's defaults and ranges, held once in C++ (its option table); the panel starts from them.
DEFAULTS = ReconstructOptions()
OPTION_FIELDS = {field["name"]: field for field in option_fields()}


def option_bounds(name: str) -> dict:
    """The hard min and max of the option's table range, as property keywords; an open end (the
    library refuses the bound itself) is brought inside, so that the slider's end is a value it takes."""
    field = OPTION_FIELDS[name]
    whole = field["kind"] == "whole"
    bounds = {}
    if field["low"] is not None:
        bounds["min"] = _held_inside(field["low"], field["low_open"], +1, whole)
    if field["high"] is not None:
        bounds["max"] = _held_inside(field["high"], field["high_open"], -1, whole)
    return bounds


def _held_inside(bound: float, is_open: bool, inward: int, whole: bool):
    """``bound``, or for an open one the nearest value inside that the property holds: a whole number
    one step in, a float the next 32-bit float in (Blender stores FloatProperty values and limits in
    32 bits, so the next 64-bit one would round back onto the bound)."""
    if whole:
        return int(bound) + (inward if is_open else 0)
    if not is_open:
        return float(bound)
    return float(np.nextafter(np.float32(bound), np.float32(np.inf * inward)))

INTEGRATOR_DESCRIPTIONS = {
    "poisson": ("Poisson", "Joins the slopes inside the mask only (least squares)"),
    "frankot_chellappa": ("Frankot-Chellappa", "Joins the slopes over the whole image at once (Fourier): fast, "
                                               "but the edges wrap around"),
}
SCENE_DESCRIPTIONS = {
    "object": ("Object", "One thing seen whole against a background (a statue, a toy): its outline is the silhouette"),
    "relief": ("Relief", "A surface that fills the frame (a wall, a coin, bark): it comes out flat, with its bumps"),
}
SCENE_ITEMS = tuple((name, *SCENE_DESCRIPTIONS.get(name, (name, name))) for name in SceneKind.__members__)
INTEGRATOR_ITEMS = tuple((name, *INTEGRATOR_DESCRIPTIONS.get(name, (name, name))) for name in Integrator.__members__)
PAINT_DESCRIPTIONS = {
    "top_fit": ("One colour", "The object has one paint: every change of brightness is shape"),
    "brightest": ("One colour, brightest", "One paint, read from the brightest pixel (no highlights in the photo)"),
    "retinex": ("Painted", "Paint, print or stains: changes of colour (and sharp changes of brightness) are paint, "
                           "not shape; the de-lit colour becomes the material's colour. A glossy object of one "
                           "colour is better read as One colour: its highlight would pass for white paint"),
}
PAINT_ITEMS = tuple((name, *PAINT_DESCRIPTIONS.get(name, (name, name))) for name in AlbedoMethod.__members__)


def _is_light(_settings, obj) -> bool:
    return obj.type == "LIGHT"


def _is_camera(_settings, obj) -> bool:
    return obj.type == "CAMERA"


def _is_sun(_settings, ob) -> bool:
    return ob.type == "LIGHT" and ob.data.type == "SUN"


# Toward the light, as first typed: from the right and the viewer (a photograph row's too).
DEFAULT_DIRECTION = (1.0, 0.0, 1.0)


def _side_item(side: str, slant: str = f", {SIDE_LIGHT_SLANT_DEGREES:g} degrees from the viewer"
               ) -> tuple[str, str, str]:
    """The Side menu's item of one of the library's sides ('above' and 'below' are 'top' and 'bottom'),
    lit at ``slant`` (as the description ends)."""
    same = {"above": "top", "below": "bottom"}.get(side)
    where = f"{side}: the {same} of the image (the same light)" if same else f"the {side} of the image"
    return side, side.capitalize(), f"Lit from {where}{slant}"


# The library's sides of the image, each a light at its one slant; first, none picked yet.
SIDE_ITEMS = ((UNPICKED_SIDE, "Pick a side", "No side picked yet: pick the side of the image the light came from"),
              *(_side_item(side) for side in LIGHT_SIDES))
# The side the first of several photographs is lit from when their lights are estimated, at Light slant.
FIRST_LIGHT_ITEMS = tuple(_side_item(side, " (at Light slant)") for side in LIGHT_SIDES)
# The side nearest the library's default first_light_tilt (top for 90 degrees).
FIRST_LIGHT_DEFAULT = min(LIGHT_SIDES, key=lambda side: abs((side_tilt(side) - DEFAULTS.first_light_tilt + 180) % 360
                                                            - 180))
SIDE_DESCRIPTION = (f"The side of the image the light came from, at {SIDE_LIGHT_SLANT_DEGREES:g} degrees from the "
                    "viewer (an unmeasured lamp: that slant only scales the depth)")


def _read_side(row, _context) -> None:
    """A photograph whose file name names a side of the image ('above.jpg', 'rug_left.png') is lit from it."""
    side = side_of_image(row.image)
    if side is not None:
        row.side = side


class ShadeCutPhotograph(bpy.types.PropertyGroup):
    """One of several photographs of one view (the panel's Photographs list), with its own light."""

    image: bpy.props.PointerProperty(
        name="Image", type=bpy.types.Image,
        description="A photograph of the view, taken from the same place as the others under its own light. "
                    "A file name that names a side of the image ('above.jpg', 'rug_left.png') sets its Side",
        update=_read_side,
    )
    sun: bpy.props.PointerProperty(
        name="Sun", type=bpy.types.Object, poll=_is_sun,
        description="The Sun aimed as the light fell on this photograph; empty in every row = the scene's Suns, "
                    "one per photograph in name order",
    )
    direction: bpy.props.FloatVectorProperty(
        name="Direction", size=3, default=DEFAULT_DIRECTION, subtype="XYZ",
        description="Toward this photograph's light, as seen in it: x right, y up, z toward you",
    )
    side: bpy.props.EnumProperty(name="Side", items=SIDE_ITEMS, default=UNPICKED_SIDE, description=SIDE_DESCRIPTION)


class ShadeCutReconstructSettings(bpy.types.PropertyGroup):
    """Settings of the reconstruction (see reconstruct_operator.SHADECUT_OT_reconstruct).

    The names are short enough for the default sidebar width; the descriptions (tooltips) explain.
    """

    scene: bpy.props.EnumProperty(
        name="Subject", items=SCENE_ITEMS, default=DEFAULTS.scene.name,
        description="What the image shows: one object seen whole, or a relief that fills the frame",
    )
    seamless: bpy.props.BoolProperty(
        name="Seamless", default=DEFAULTS.seamless,
        description="Relief: a surface, height and normal map that tile (left edge meets right, top meets "
                    "bottom), for a repeating texture. The whole image is used, transparency too",
    )
    detail_size: bpy.props.FloatProperty(
        name="Detail size", default=DEFAULTS.detail_size, min=0.0, soft_max=512.0, subtype="PIXEL",
        description="Relief: forms larger than this many pixels are carrier, not detail, and are flattened away "
                    "(a wall's bow, a photo's uneven light). 0 = Auto: read from the image, about 1.5 times "
                    "the size of its shading's detail",
    )
    image: bpy.props.PointerProperty(
        name="Image", type=bpy.types.Image,
        description="The picture to turn into a surface; empty = the image open in the Image Editor, else the "
                    "image of the selected Image Texture node of the active object's material. "
                    "Its transparent parts, if any, are left out",
    )
    mask_image: bpy.props.PointerProperty(
        name="Mask", type=bpy.types.Image,
        description="Object: the pixels to reconstruct, an image of the same size (its alpha where it has "
                    "transparency, else white = the object); empty = the image's own alpha, or without one the "
                    "object cut out of a plain background (shown as the image '<name> mask')",
    )
    photographs: bpy.props.CollectionProperty(
        type=ShadeCutPhotograph, name="Photographs",
        description="Several photographs of one view, each under its own light (a camera on a tripod, one lamp "
                    "moved around the subject): when there are any, they are reconstructed instead of the Image",
    )
    photograph_index: bpy.props.IntProperty(name="Selected", default=0, min=0,
                                            description="The photograph selected in the list")
    max_resolution: bpy.props.IntProperty(
        name="Max size", default=2048, min=0, soft_max=4096, subtype="PIXEL",
        description="A larger image shrinks by a whole factor until neither side exceeds this (0 = full size). "
                    "The time grows with the pixels: 2048 px has four times those of 1024 px, and a photo at "
                    "2048 px takes from seconds to tens of seconds (the status bar shows the progress; Esc cancels)",
    )

    # Estimate comes first and is the default: it needs nothing from the scene, so the first
    # click succeeds with any image.
    light_source: bpy.props.EnumProperty(
        name="Light",
        items=(
            ("ESTIMATE", "Estimate", "Work out the light's direction, and the surface's brightness, from the image"),
            ("OBJECT", "Sun", "Use a Sun lamp of the scene that lights the image as the light did"),
            ("DIRECTION", "Direction", "Type the direction toward the light as seen in the image: "
                                       "x right, y up, z toward you"),
            ("SIDE", "Side of the image", "Name the side of the image the light came from (top, left, ...) "
                                          "when nobody measured it: the photographs' file names can name it"),
        ),
        default="ESTIMATE",
        description="Where the light that shaded the image came from",
    )
    light_object: bpy.props.PointerProperty(
        name="Sun", type=bpy.types.Object, poll=_is_light,
        description="The Sun lamp (it shines along its local -Z); empty = the scene's only Sun",
    )
    light_direction: bpy.props.FloatVectorProperty(
        name="Direction", size=3, default=DEFAULT_DIRECTION, subtype="XYZ",
        description="Toward the light, as seen in the image: x right, y up, z toward you",
    )
    light_side: bpy.props.EnumProperty(name="Side", items=SIDE_ITEMS, default=UNPICKED_SIDE,
                                       description=SIDE_DESCRIPTION)
    light_slant: bpy.props.FloatProperty(
        name="Light slant", default=DEFAULTS.light_slant, **option_bounds("light_slant"),
        description="Several photographs with Light Estimate: how many degrees from the viewer their lamp stood, "
                    "about the same for each (1 to 89). The photographs fix where around the "
                    "viewer each light was; this slant only scales the depth",
    )
    light_distance: bpy.props.FloatProperty(
        name="Lamp distance", default=DEFAULTS.light_distance, **option_bounds("light_distance"),
        description="Several photographs with their lights given: how far the lamp stood from the middle of the "
                    "picture, in picture widths (a desk lamp or flash, whose light comes from another direction at "
                    "each corner). 0 = distant, like the sun",
    )
    first_light_side: bpy.props.EnumProperty(
        name="First light", items=FIRST_LIGHT_ITEMS, default=FIRST_LIGHT_DEFAULT,
        description="Several photographs with Light Estimate: the side of the image the first photograph in the "
                    "list is lit from, give or take 90 degrees; it tells a bump from a dent",
    )
    frame: bpy.props.EnumProperty(
        name="Seen from",
        items=(
            ("IMAGE_PLANE", "Top view", "The image is the ground seen from above (Top view): "
                                        "the Sun lights it as it lights the floor"),
            ("CAMERA", "Camera", "The image is what a camera sees: the chosen one, or else the scene's"),
        ),
        default="IMAGE_PLANE",
        description="Where the image was seen from, to read the Sun's direction in it",
    )
    camera: bpy.props.PointerProperty(
        name="Camera", type=bpy.types.Object, poll=_is_camera,
        description="The camera that saw the image; empty = the scene's camera",
    )

    method: bpy.props.EnumProperty(
        name="Method",
        items=(("DEFAULT", "Default", "The method chosen in the add-on's preferences"), *METHOD_ITEMS),
        default="DEFAULT",
        description="The shape-from-shading algorithm",
    )
    labels: bpy.props.IntProperty(
        name="Tilt steps", default=DEFAULTS.labels, **option_bounds("labels"),
        description="How many slope directions the graph cut chooses among (its labels): "
                    "more is finer and slower",
    )
    data_weight: bpy.props.FloatProperty(
        name="Image trust", default=DEFAULTS.data_weight, **option_bounds("data_weight"), soft_max=5.0,
        description="How closely the surface follows the image's shading rather than staying smooth "
                    "(the graph cut's data weight): higher keeps more detail, and more noise",
    )
    integrator: bpy.props.EnumProperty(
        name="Solver", items=INTEGRATOR_ITEMS, default=DEFAULTS.integrator.name,
        description="How the slopes are joined into heights (the integrator)",
    )
    albedo_method: bpy.props.EnumProperty(
        name="Paint", items=PAINT_ITEMS, default=DEFAULTS.albedo_method.name,
        description="Whether the object has one colour or is painted (the albedo read from the image)",
    )
    fit_shading: bpy.props.BoolProperty(
        name="Fit to image", default=DEFAULTS.fit_shading,
        description="After the graph cut, refine the heights until the surface's shading matches the image: "
                    "more detail and no blocks on objects of one colour, in about the time again; painted "
                    "objects and materials can come out worse",
    )
    auto_albedo: bpy.props.BoolProperty(
        name="Auto albedo", default=True,
        description="Work out the surface's brightness (albedo) from the image; off = the value beside",
    )
    albedo: bpy.props.FloatProperty(
        name="Albedo", default=1.0, min=1e-3, soft_max=1.0,
        description="The image's brightness where the surface faces the light squarely (1 = white). "
                    "Estimate works it out itself",
    )

    target: bpy.props.EnumProperty(
        name="Apply to",
        items=(
            ("NEW_OBJECT", "New object", "Build a new object with the reconstructed shape at the 3-D cursor"),
            ("ACTIVE_MATERIAL", "Active object", "Put the Normal map and/or Height map into the active object's "
                                                 "active material (a flat plane textured with the image, say), "
                                                 "wired and live, following its UV map. No new mesh"),
        ),
        default="NEW_OBJECT",
        description="Where the result goes: a new object, or maps in the selected object's material",
    )
    output: bpy.props.EnumProperty(
        name="Output",
        items=(
            ("MESH", "Mesh", "A mesh with one vertex per sampled pixel"),
            ("DISPLACE", "Displaced plane", "A flat grid with a Displace modifier and a height image (light preview)"),
        ),
        default="MESH",
        description="What to build: real geometry, or a flat grid pushed up by a modifier",
    )
    width: bpy.props.FloatProperty(
        name="Width", default=2.0, min=1e-4, soft_max=100.0, unit="LENGTH",
        description="Width of the result in scene units; its heights follow in proportion",
    )
    depth_scale: bpy.props.FloatProperty(
        name="Depth scale", default=1.0, soft_min=0.0, soft_max=10.0,
        description="Multiplies the reconstructed heights. 1 = as reconstructed, a pixel of height as long as "
                    "a pixel of width; shading says little about overall depth, so a relief can come out far "
                    "deeper or flatter than the real one: lower this (0.5 = half as deep) or limit the height",
    )
    limit_height: bpy.props.BoolProperty(
        name="Limit height", default=False,
        description="Scale the heights down so that the result is at most Max height high; "
                    "off = the heights as Depth scale makes them",
    )
    max_height: bpy.props.FloatProperty(
        name="Max height", default=0.2, min=1e-4, soft_max=10.0, unit="LENGTH",
        description="With Limit height on, the result's greatest height from its lowest to its highest point, "
                    "in scene units (a result that is lower keeps its heights)",
    )
    auto_density: bpy.props.BoolProperty(
        name="Auto density", default=True,
        description="Choose the density itself: the finest that keeps within the Vertex limit "
                    "(every pixel a vertex when that fits); off = the density beside",
    )
    density: bpy.props.IntProperty(
        name="Density", default=1, min=1, soft_max=16,
        description="With Auto density off, one vertex every this many pixels (1 = every pixel: a 2048 px "
                    "result has 4.2 million vertices, slow to build and to draw)",
    )
    max_vertices: bpy.props.IntProperty(
        name="Vertex limit", default=MAX_VERTICES, min=4, soft_max=4_000_000,
        description="Vertex budget of the automatic density. 250,000 (half a million triangles) keeps Material "
                    "Preview interactive on a modest GPU and the result quick to build",
    )
    normal_map: bpy.props.BoolProperty(
        name="Normal map", default=False,
        description="Also make a tangent-space normal map of the surface, '<result> normals', wired into the "
                    "result's material through a Normal Map node and packed into the .blend",
    )
    residual_map: bpy.props.BoolProperty(
        name="Residual map", default=False,
        description="Also make a grey image, '<result> residual': how far the photograph is from the result, as "
                    "a share of the albedo (black: the result renders it; white: off by the whole albedo). Shadows, "
                    "highlights and paint the surface does not explain stand out: where to trust it less",
    )
    height_map: bpy.props.BoolProperty(
        name="Height map", default=False,
        description="Also make a height image, '<result> height' (0 to 1), wired into the result's material "
                    "through a Displacement node whose Scale gives the result's heights in scene units; "
                    "packed into the .blend. The Displaced plane's own height image is reused",
    )


class ShadeCutRenderSettings(bpy.types.PropertyGroup):
    """Settings of the Lambertian test render (see shadecut.blender.lambertian.render_lambertian)."""

    objects: bpy.props.EnumProperty(
        name="Objects",
        items=(("SELECTED", "Selected", "The selected mesh objects"),
               ("VISIBLE", "Visible", "Every mesh visible in the view layer")),
        default="SELECTED",
        description="Which meshes to render",
    )
    light_source: bpy.props.EnumProperty(
        name="Light",
        items=(("DIRECTION", "Direction", "A direction toward the light in the camera frame (x right, y up, "
                                          "z toward the viewer)"),
               ("SUN", "Sun", "The direction of a Sun light of the scene")),
        default="DIRECTION",
        description="Where the light comes from: a typed direction or a Sun of the scene",
    )
    light_direction: bpy.props.FloatVectorProperty(
        name="Direction", size=3, default=(1.0, 0.0, 1.0), subtype="XYZ",
        description="Toward the light, camera frame; z must be > 0",
    )
    sun: bpy.props.PointerProperty(name="Sun", type=bpy.types.Object, poll=_is_sun,
                                   description="The Sun light whose direction lights the render")
    camera_source: bpy.props.EnumProperty(
        name="Camera",
        items=(("FIT", "Fitted orthographic", "An orthographic camera fitted to the objects, front view"),
               ("SCENE", "Scene camera", "The scene's active camera")),
        default="FIT",
        description="The camera that sees the meshes",
    )
    resolution_x: bpy.props.IntProperty(name="Width", default=256, min=2, max=16384, subtype="PIXEL",
                                        description="Width of the rendered image")
    resolution_y: bpy.props.IntProperty(name="Height", default=256, min=2, max=16384, subtype="PIXEL",
                                        description="Height of the rendered image")
    albedo_source: bpy.props.EnumProperty(
        name="Albedo",
        items=(("UNIFORM", "Uniform", "One diffuse albedo for every object"),
               ("OWN", "Own colours", "Each material's base colour (luminance), textures included")),
        default="UNIFORM",
        description="The surfaces' brightness (albedo): one value, or each material's own",
    )
    albedo: bpy.props.FloatProperty(name="Albedo", default=0.8, min=0.001, max=1.0,
                                    description="Brightness of a surface facing the light squarely (1 = white)")
    shadows: bpy.props.BoolProperty(name="Cast shadows", default=False,
                                    description="Off: the Lambertian model of the paper, which has no shadows")
    indirect: bpy.props.BoolProperty(name="Indirect light", default=False,
                                     description="Light bouncing between surfaces (needs many samples)")
    samples: bpy.props.IntProperty(
        name="Samples", default=0, min=0, max=65536,
        description=f"Cycles samples per pixel; 0 = automatic (1 without indirect light, which is exact, "
                    f"{lambertian.INDIRECT_SAMPLES} with it)",
    )
    noise: bpy.props.FloatProperty(name="Noise", default=0.0, min=0.0, max=1.0, precision=4,
                                   description="Standard deviation of Gaussian noise added to the linear image")
    quantization: bpy.props.EnumProperty(
        name="Quantization",
        items=(("FLOAT", "Float", "No quantization"), ("8", "8-bit", "8-bit sRGB codes"),
               ("16", "16-bit", "16-bit sRGB codes")),
        default="FLOAT",
        description="How the image's values are stored, as a camera or a file format would",
    )
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0, description="Seed of the noise")
    output_dir: bpy.props.StringProperty(
        name="Output", default="//shadecut_render", subtype="DIR_PATH",
        description="Folder that receives image.exr/.png, normals.exr, depth.exr, mask.png and meta.json",
    )
