"""The Blender side of ShadeCut: operators, panels and helpers that need ``bpy``.

Nothing outside this subpackage imports it, so ``import shadecut`` keeps working without Blender.
The modules: one per operator (``reconstruct_operator``, ``render_operator``, ``flip_operator``,
``photographs_operator``), the reconstruction's job (``reconstruct_job``: checks, worker, result) and
its input (``image_input``, ``light_input``), their settings on
the scene (``properties``), the sidebar (``panels``, with its ``light_preview``), the add-on's
``preferences``, and the helpers the operators use (``frames``, ``lambertian``, ``mesh``,
``result``). Every class is registered from :data:`CLASSES` below.
"""

import bpy

from . import light_preview
from .flip_operator import SHADECUT_OT_flip
from .panels import (SHADECUT_PT_advanced_image, SHADECUT_PT_advanced_view3d, SHADECUT_PT_reconstruct_image,
                     SHADECUT_PT_reconstruct_view3d, SHADECUT_PT_render_view3d, SHADECUT_UL_photographs)
from .photographs_operator import SHADECUT_OT_photographs_add, SHADECUT_OT_photographs_remove
from .preferences import ShadeCutPreferences
from .properties import ShadeCutPhotograph, ShadeCutReconstructSettings, ShadeCutRenderSettings
from .reconstruct_operator import SHADECUT_OT_reconstruct
from .render_operator import SHADECUT_OT_render_lambertian

# In registration order: the PropertyGroups before the pointers to them, the operators before the
# panels that show their buttons, a parent panel before its sub-panel.
CLASSES = (
    ShadeCutPreferences,
    ShadeCutPhotograph,
    ShadeCutReconstructSettings,
    ShadeCutRenderSettings,
    SHADECUT_OT_reconstruct,
    SHADECUT_OT_render_lambertian,
    SHADECUT_OT_flip,
    SHADECUT_OT_photographs_add,
    SHADECUT_OT_photographs_remove,
    SHADECUT_UL_photographs,
    SHADECUT_PT_reconstruct_view3d,
    SHADECUT_PT_reconstruct_image,
    SHADECUT_PT_advanced_view3d,
    SHADECUT_PT_advanced_image,
    SHADECUT_PT_render_view3d,
)


def register() -> None:
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.shadecut = bpy.props.PointerProperty(type=ShadeCutReconstructSettings)
    bpy.types.Scene.shadecut_render = bpy.props.PointerProperty(type=ShadeCutRenderSettings)
    light_preview.register()


def unregister() -> None:
    light_preview.unregister()
    del bpy.types.Scene.shadecut_render
    del bpy.types.Scene.shadecut
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
