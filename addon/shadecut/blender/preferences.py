"""Add-on preferences: the defaults a user sets once (Preferences > Add-ons > ShadeCut)."""

from __future__ import annotations

import bpy

from ..api import MAX_THREADS, METHODS, ReconstructOptions

ADDON_ID = __package__.rpartition(".")[0]  # "shadecut", or "bl_ext.<repository>.shadecut" as an extension

METHOD_DESCRIPTIONS = {
    "graphcut": ("Graph cut", "Chang, Lee & Lee's global energy (eq. 15), alpha-expansion over tilt labels"),
    "graphcut_two": ("Graph cut, two candidates", "The paper's simpler energy (eq. 10): each pixel keeps one of its two local tilts"),
    "lee_rosenfeld": ("Lee & Rosenfeld", "The local method alone, assuming a convex surface"),
    "brooks_horn": ("Brooks & Horn", "Global variational method (brightness, smoothness, unit normals)"),
    "tsai_shah": ("Tsai & Shah", "Local linear approximation of the reflectance map, Newton steps on depth"),
    "upwind": ("Upwind (viscosity)", "The image's PDE solved outward from the outline by upwind sweeps: a convex object"),
    "pentland": ("Pentland (linear, reliefs)", "The slope along the light read from a nearly flat relief; leans flat where the image says little"),
}

METHOD_ITEMS = tuple((name, *METHOD_DESCRIPTIONS.get(name, (name, name))) for name in METHODS)


class ShadeCutPreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON_ID

    default_method: bpy.props.EnumProperty(
        name="Default method", items=METHOD_ITEMS, default=ReconstructOptions().method.name,
        description="The method the panel's 'Default' choice stands for",
    )
    threads: bpy.props.IntProperty(
        name="Threads", default=ReconstructOptions().threads, min=0, max=MAX_THREADS,
        description="CPU threads for the reconstruction (0 = all cores)",
    )

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "default_method")
        layout.prop(self, "threads")


def addon_preferences(context) -> ShadeCutPreferences | None:
    """The preferences, or None when the classes were registered without enabling the add-on
    (scripts and tests that call ``shadecut.register()`` directly)."""
    addon = context.preferences.addons.get(ADDON_ID)
    return addon.preferences if addon else None
