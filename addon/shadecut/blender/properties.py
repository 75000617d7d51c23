"""The settings on the scene, one PropertyGroup per operator: ``scene.shadecut`` (reconstruction)
and ``scene.shadecut_render`` (the Lambertian test render)."""

from __future__ import annotations

import bpy

from ..api import MIN_LABELS, Integrator, ReconstructOptions, SceneKind
from . import lambertian
from .preferences import METHOD_ITEMS

# The library's defaults, held once in C++; the panel starts from them.
DEFAULTS = ReconstructOptions()
INTEGRATOR_DESCRIPTIONS = {
    "poisson": ("Poisson", "Least squares on the mask"),
    "frankot_chellappa": ("Frankot-Chellappa", "Fourier projection on the whole image"),
}
SCENE_DESCRIPTIONS = {
    "object": ("Object", "An object seen whole against a background (a statue, a toy): its outline is a silhouette"),
    "relief": ("Relief", "A surface that fills the frame (a wall, a coin, bark): it sits flat, with no ramp"),
}
SCENE_ITEMS = tuple((name, *SCENE_DESCRIPTIONS.get(name, (name, name))) for name in SceneKind.__members__)
INTEGRATOR_ITEMS = tuple((name, *INTEGRATOR_DESCRIPTIONS.get(name, (name, name))) for name in Integrator.__members__)


def _is_light(_settings, obj) -> bool:
    return obj.type == "LIGHT"


def _is_camera(_settings, obj) -> bool:
    return obj.type == "CAMERA"


def _is_sun(_settings, ob) -> bool:
    return ob.type == "LIGHT" and ob.data.type == "SUN"


class ShadeCutReconstructSettings(bpy.types.PropertyGroup):
    """Settings of the reconstruction (see reconstruct_operator.SHADECUT_OT_reconstruct)."""

    image: bpy.props.PointerProperty(
        name="Image", type=bpy.types.Image,
        description="The shaded image; empty = the image shown in the Image Editor",
    )
    max_resolution: bpy.props.IntProperty(
        name="Max size", default=2048, min=0, soft_max=4096, subtype="PIXEL",
        description="A larger image shrinks by a whole factor until neither side exceeds this (0 = full size). "
                    "Reconstructing a 2048 px image takes about 5 s on two cores (graphcut), 1024 px about 1.3 s",
    )

    light_source: bpy.props.EnumProperty(
        name="Light",
        items=(
            ("OBJECT", "Sun", "The direction of a Sun light in the scene"),
            ("DIRECTION", "Direction", "A direction typed in the image's camera frame (x right, y up, z toward the viewer)"),
            ("ESTIMATE", "Estimate", "Estimate the light (and the albedo) from the image"),
        ),
        default="OBJECT",
    )
    light_object: bpy.props.PointerProperty(
        name="Sun", type=bpy.types.Object, poll=_is_light, description="A Sun light: it shines along its local -Z",
    )
    light_direction: bpy.props.FloatVectorProperty(
        name="Direction", size=3, default=(1.0, 0.0, 1.0), subtype="XYZ",
        description="Toward the light, in the camera frame: x right, y up, z toward the viewer",
    )
    frame: bpy.props.EnumProperty(
        name="Frame",
        items=(
            ("IMAGE_PLANE", "Image plane", "The image lies in the world XY plane, seen from +Z"),
            ("CAMERA", "Camera", "The image was taken by a camera: the chosen one, or else the scene's"),
        ),
        default="IMAGE_PLANE",
        description="The frame in which the Sun's direction is read",
    )
    camera: bpy.props.PointerProperty(
        name="Camera", type=bpy.types.Object, poll=_is_camera, description="Empty = the scene's camera",
    )

    scene: bpy.props.EnumProperty(
        name="Scene", items=SCENE_ITEMS, default=DEFAULTS.scene.name,
        description="What the image shows: an object seen whole, or a relief that fills the frame",
    )
    method: bpy.props.EnumProperty(
        name="Method",
        items=(("DEFAULT", "Default", "The default method of the add-on's preferences"), *METHOD_ITEMS),
        default="DEFAULT",
    )
    labels: bpy.props.IntProperty(
        name="Labels", default=DEFAULTS.labels, min=MIN_LABELS, max=360, description="Number of discrete tilts (graph-cut methods)",
    )
    data_weight: bpy.props.FloatProperty(
        name="Data weight", default=DEFAULTS.data_weight, min=0.0, soft_max=5.0, description="Lambda of the paper's eq. (15)",
    )
    integrator: bpy.props.EnumProperty(
        name="Integrator",
        items=INTEGRATOR_ITEMS,
        default=DEFAULTS.integrator.name,
    )
    auto_albedo: bpy.props.BoolProperty(
        name="Auto albedo", default=True, description="Take the albedo from the brightest part of the image",
    )
    albedo: bpy.props.FloatProperty(name="Albedo", default=1.0, min=1e-3, soft_max=1.0)

    output: bpy.props.EnumProperty(
        name="Output",
        items=(
            ("MESH", "Mesh", "A mesh with one vertex per sampled pixel"),
            ("DISPLACE", "Displaced plane", "A flat grid with a Displace modifier and a height image (light preview)"),
        ),
        default="MESH",
    )
    width: bpy.props.FloatProperty(
        name="Width", default=2.0, min=1e-4, soft_max=100.0, unit="LENGTH",
        description="Width of the result in scene units",
    )
    depth_scale: bpy.props.FloatProperty(
        name="Depth scale", default=1.0, soft_min=0.0, soft_max=10.0,
        description="Multiplies the reconstructed heights (1 = true proportions)",
    )
    max_height: bpy.props.FloatProperty(
        name="Max height", default=0.0, min=0.0, soft_max=10.0, unit="LENGTH",
        description="Scale the heights down so that the result is at most this high (0 = no limit)",
    )
    density: bpy.props.IntProperty(
        name="Density", default=0, min=0, soft_max=16,
        description="One vertex every this many pixels; 0 = automatic, the finest within Max vertices. "
                    "At 1, a 2048 px result has 4.2 million vertices and takes about 2.4 s to build",
    )
    max_vertices: bpy.props.IntProperty(
        name="Max vertices", default=250_000, min=4, soft_max=4_000_000,
        description="Vertex budget of the automatic density. 250,000 (half a million triangles) keeps Material "
                    "Preview interactive on a modest GPU; a 2048 px result then builds in under 0.5 s",
    )
    normal_map: bpy.props.BoolProperty(
        name="Normal map", default=False, description="Also store the normals as a new image",
    )


class ShadeCutRenderSettings(bpy.types.PropertyGroup):
    """Settings of the Lambertian test render (see shadecut.blender.lambertian.render_lambertian)."""

    objects: bpy.props.EnumProperty(
        name="Objects",
        items=(("SELECTED", "Selected", "The selected mesh objects"),
               ("VISIBLE", "Visible", "Every mesh visible in the view layer")),
        default="SELECTED",
    )
    light_source: bpy.props.EnumProperty(
        name="Light",
        items=(("DIRECTION", "Direction", "A direction toward the light in the camera frame (x right, y up, "
                                          "z toward the viewer)"),
               ("SUN", "Sun", "The direction of a Sun light of the scene")),
        default="DIRECTION",
    )
    light_direction: bpy.props.FloatVectorProperty(
        name="Direction", size=3, default=(1.0, 0.0, 1.0), subtype="XYZ",
        description="Toward the light, camera frame; z must be > 0",
    )
    sun: bpy.props.PointerProperty(name="Sun", type=bpy.types.Object, poll=_is_sun)
    camera_source: bpy.props.EnumProperty(
        name="Camera",
        items=(("FIT", "Fitted orthographic", "An orthographic camera fitted to the objects, front view"),
               ("SCENE", "Scene camera", "The scene's active camera")),
        default="FIT",
    )
    resolution_x: bpy.props.IntProperty(name="Width", default=256, min=2, max=16384, subtype="PIXEL")
    resolution_y: bpy.props.IntProperty(name="Height", default=256, min=2, max=16384, subtype="PIXEL")
    albedo_source: bpy.props.EnumProperty(
        name="Albedo",
        items=(("UNIFORM", "Uniform", "One diffuse albedo for every object"),
               ("OWN", "Own colours", "Each material's base colour (luminance), textures included")),
        default="UNIFORM",
    )
    albedo: bpy.props.FloatProperty(name="Albedo", default=0.8, min=0.001, max=1.0)
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
    )
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0, description="Seed of the noise")
    output_dir: bpy.props.StringProperty(
        name="Output", default="//shadecut_render", subtype="DIR_PATH",
        description="Folder that receives image.exr/.png, normals.exr, depth.exr, mask.png and meta.json",
    )
