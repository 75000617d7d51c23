"""The Blender side of ShadeCut: operators, panels and helpers that need ``bpy``.

Nothing outside this subpackage imports it, so ``import shadecut`` keeps working without Blender.
"""

import bpy

from . import render_operator
from .operators import SHADECUT_OT_reconstruct
from .panels import SHADECUT_PT_reconstruct_image, SHADECUT_PT_reconstruct_view3d, SHADECUT_PT_render_view3d
from .preferences import ShadeCutPreferences
from .properties import ShadeCutSettings

CLASSES = (
    ShadeCutPreferences,
    ShadeCutSettings,
    *render_operator.CLASSES,
    SHADECUT_OT_reconstruct,
    SHADECUT_PT_reconstruct_view3d,
    SHADECUT_PT_reconstruct_image,
    SHADECUT_PT_render_view3d,
)


def register() -> None:
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.shadecut = bpy.props.PointerProperty(type=ShadeCutSettings)
    bpy.types.Scene.shadecut_render = bpy.props.PointerProperty(type=render_operator.ShadeCutRenderSettings)


def unregister() -> None:
    del bpy.types.Scene.shadecut_render
    del bpy.types.Scene.shadecut
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
