"""The reconstruction settings, one PropertyGroup on the scene (``scene.shadecut``)."""

from __future__ import annotations

import bpy

from ..api import MIN_LABELS, Integrator, ReconstructOptions
from .preferences import METHOD_ITEMS

# The library's defaults, held once in C++; the panel starts from them.
DEFAULTS = ReconstructOptions()
INTEGRATOR_DESCRIPTIONS = {
    "poisson": ("Poisson", "Least squares on the mask"),
    "frankot_chellappa": ("Frankot-Chellappa", "Fourier projection on the whole image"),
}
INTEGRATOR_ITEMS = tuple((name, *INTEGRATOR_DESCRIPTIONS.get(name, (name, name))) for name in Integrator.__members__)


def _is_light(_settings, obj) -> bool:
    return obj.type == "LIGHT"


def _is_camera(_settings, obj) -> bool:
    return obj.type == "CAMERA"


class ShadeCutSettings(bpy.types.PropertyGroup):
    image: bpy.props.PointerProperty(
        name="Image", type=bpy.types.Image,
        description="The shaded image; empty = the image shown in the Image Editor",
    )
    max_resolution: bpy.props.IntProperty(
        name="Max size", default=512, min=0, soft_max=4096, subtype="PIXEL",
        description="Downsample so that neither side exceeds this many pixels (0 = full size). graphcut takes "
                    "about 0.7 s at 512 px and about 4 s at 1024 px on two cores",
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
    density: bpy.props.IntProperty(
        name="Density", default=1, min=1, soft_max=16,
        description="One vertex every this many pixels (1 = one per pixel)",
    )
    normal_map: bpy.props.BoolProperty(
        name="Normal map", default=False, description="Also store the normals as a new image",
    )
