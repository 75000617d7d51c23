"""The add-on as it registers when its compiled module cannot load here (built for another Python or
platform, or not built): instead of a traceback on enabling, a report and a sidebar panel that say
what is wrong and what to do. It imports nothing of the package that needs ``_core``.
"""

import textwrap

import bpy

ADDON_ID = __package__  # "shadecut", or "bl_ext.<repository>.shadecut" as an extension
_message = ""


class SHADECUT_OT_unavailable(bpy.types.Operator):
    """Report why ShadeCut cannot run in this Blender"""

    bl_idname = "shadecut.unavailable"
    bl_label = "Why ShadeCut Cannot Run"
    bl_options = {"REGISTER"}

    def execute(self, context):
        self.report({"ERROR"}, _message)
        return {"FINISHED"}


def _draw_message(layout) -> None:
    column = layout.column(align=True)
    column.label(text="ShadeCut cannot run in this Blender", icon="ERROR")
    for line in textwrap.wrap(_message, 44):
        column.label(text=line)


class SHADECUT_PT_unavailable(bpy.types.Panel):
    bl_label = "ShadeCut"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "ShadeCut"

    def draw(self, context):
        _draw_message(self.layout)


class ShadeCutUnavailablePreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON_ID

    def draw(self, context):
        _draw_message(self.layout)


CLASSES = (SHADECUT_OT_unavailable, SHADECUT_PT_unavailable, ShadeCutUnavailablePreferences)


def _report() -> None:
    try:
        bpy.ops.shadecut.unavailable()
    except RuntimeError:  # how an ERROR report reaches a Python caller; the window shows it already
        pass


def register(message: str) -> None:
    global _message
    _message = message
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    # The report appears once the window runs its event loop (a timer), not inside addon_enable.
    bpy.app.timers.register(_report, first_interval=0.1)


def unregister() -> None:
    if bpy.app.timers.is_registered(_report):
        bpy.app.timers.unregister(_report)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
