"""The "ShadeCut" tab in the 3D View's and the Image Editor's sidebars."""

from __future__ import annotations

import textwrap

import bpy

from .. import api
from . import lambertian, light_preview
from .flip_operator import SHADECUT_OT_flip
from .photographs_operator import SHADECUT_OT_photographs_add, SHADECUT_OT_photographs_remove
from .reconstruct_operator import SHADECUT_OT_reconstruct
from .render_operator import SHADECUT_OT_render_lambertian


def _toggled_value(column, settings, toggle: str, value: str, *, heading: str, toggle_text: str,
                   value_when_on: bool = True) -> None:
    """A row "heading [x] toggle_text [value]": the value greyed out while it does not apply, so the
    panel says "Auto" or "Limit" in words where a 0 used to stand for it."""
    row = column.row(heading=heading)
    row.prop(settings, toggle, text=toggle_text)
    sub = row.row()
    sub.active = getattr(settings, toggle) == value_when_on
    sub.prop(settings, value, text="")


class SHADECUT_UL_photographs(bpy.types.UIList):
    """A row of the Photographs list: the image, and its light as the Light setting reads it (a Sun, a
    direction, or a side of the image)."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_property, index=0, flt_flag=0):
        row = layout.row(align=True)
        row.prop(item, "image", text="")
        if data.light_source == "OBJECT":
            row.prop(item, "sun", text="")
        elif data.light_source == "DIRECTION":
            row.prop(item, "direction", text="")
        elif data.light_source == "SIDE":
            row.prop(item, "side", text="")


def _draw_photographs(column, settings) -> None:
    """The Photographs list with its Add (several files at once) and Remove buttons."""
    row = column.row()
    row.template_list(SHADECUT_UL_photographs.__name__, "", settings, "photographs", settings, "photograph_index",
                      rows=2 if not settings.photographs else 4)
    buttons = row.column(align=True)
    buttons.operator(SHADECUT_OT_photographs_add.bl_idname, text="", icon="ADD")
    buttons.operator(SHADECUT_OT_photographs_remove.bl_idname, text="", icon="REMOVE")


def _draw_estimated_lights_hint(column, settings) -> None:
    """Light Estimate with several photographs: the hint the library finds their lights with, and
    a warning while there are too few for it."""
    column.prop(settings, "light_slant")
    column.prop(settings, "first_light_side")
    if len(settings.photographs) < api.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS:
        column.label(text=f"Estimate needs {api.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS} or more photographs", icon="ERROR")


def draw_reconstruct_settings(layout, settings) -> None:
    """Draws the artist's settings and the buttons into a panel's layout."""
    layout.use_property_split = True
    layout.use_property_decorate = False

    column = layout.column()
    column.row().prop(settings, "scene", expand=True)
    if settings.scene == "relief":
        column.prop(settings, "seamless")
        if not settings.seamless:
            if settings.detail_size == 0:
                column.prop(settings, "detail_size", text="Detail size (Auto)")
            else:
                column.prop(settings, "detail_size")
    if not settings.photographs:
        column.prop(settings, "image")
    _draw_photographs(column, settings)
    if settings.scene == "object":
        column.prop(settings, "mask_image")
    column.prop(settings, "max_resolution")
    # The library fits one image's depth, not several photographs' nor a seamless relief's.
    if not settings.photographs and not (settings.scene == "relief" and settings.seamless):
        column.prop(settings, "fit_shading")

    column = layout.column(heading="Light")
    column.prop(settings, "light_source")
    several = bool(settings.photographs)  # each photograph's own Sun or direction is in its row
    if settings.light_source == "OBJECT":
        if not several:
            column.prop(settings, "light_object")
        column.prop(settings, "frame")
        if settings.frame == "CAMERA":
            column.prop(settings, "camera")
    elif settings.light_source == "DIRECTION" and not several:
        column.prop(settings, "light_direction")
    elif settings.light_source == "SIDE" and not several:
        column.prop(settings, "light_side")
    elif settings.light_source == "ESTIMATE" and len(settings.photographs) > 1:  # one is the single image's
        _draw_estimated_lights_hint(column, settings)
    if len(settings.photographs) > 1 and settings.light_source != "ESTIMATE":
        column.prop(settings, "light_distance")
    if not several:
        light_preview.draw(column, bpy.context, settings)

    column = layout.column()
    column.prop(settings, "target")
    new_object = settings.target == "NEW_OBJECT"
    if new_object:
        column.prop(settings, "output")
        column.prop(settings, "width")
    column.prop(settings, "depth_scale")
    _toggled_value(column, settings, "limit_height", "max_height", heading="Max height", toggle_text="Limit")
    if new_object:
        _toggled_value(column, settings, "auto_density", "density", heading="Density", toggle_text="Auto",
                       value_when_on=False)
        sub = column.column()
        sub.active = settings.auto_density
        sub.prop(settings, "max_vertices")
    column.prop(settings, "normal_map")
    column.prop(settings, "height_map")
    column.prop(settings, "residual_map")

    layout.use_property_split = False
    row = layout.row(align=True)
    row.scale_y = 1.5
    row.operator(SHADECUT_OT_reconstruct.bl_idname, icon="MOD_DISPLACE")
    browse = row.operator(SHADECUT_OT_reconstruct.bl_idname, text="", icon="FILEBROWSER")
    browse.use_file_browser = True
    layout.operator(SHADECUT_OT_flip.bl_idname, icon="MOD_MIRROR")


def draw_advanced_settings(layout, settings) -> None:
    """Draws the method's own parameters, which the defaults cover for most images."""
    layout.use_property_split = True
    layout.use_property_decorate = False
    column = layout.column()
    column.prop(settings, "method")
    column.prop(settings, "labels")
    column.prop(settings, "data_weight")
    column.prop(settings, "integrator")
    column.prop(settings, "albedo_method")
    row = column.row(heading="Albedo")
    row.active = settings.light_source != "ESTIMATE"  # Estimate finds the albedo with the light
    row.prop(settings, "auto_albedo", text="Auto")
    sub = row.row()
    sub.active = not settings.auto_albedo
    sub.prop(settings, "albedo", text="")


def draw_render_settings(layout, settings) -> None:
    """Draws the render settings and the button into a panel's layout; where rendering cannot work
    (no OpenImageIO, as from the add-on's zip), says why instead."""
    reason = lambertian.files_unavailable()
    if reason:
        column = layout.column(align=True)
        for line in textwrap.wrap(reason + ". Build ShadeCut from source for it.", 40):
            column.label(text=line)
        return
    column = layout.column()
    column.prop(settings, "objects")
    column.prop(settings, "light_source")
    column.prop(settings, "light_direction" if settings.light_source == "DIRECTION" else "sun")
    column.prop(settings, "camera_source")
    row = column.row(align=True)
    row.prop(settings, "resolution_x")
    row.prop(settings, "resolution_y")
    column.prop(settings, "albedo_source")
    if settings.albedo_source == "UNIFORM":
        column.prop(settings, "albedo")
    column.prop(settings, "shadows")
    column.prop(settings, "indirect")
    column.prop(settings, "samples")
    row = column.row(align=True)
    row.prop(settings, "noise")
    row.prop(settings, "quantization", text="")
    column.prop(settings, "seed")
    column.prop(settings, "output_dir")
    column.operator(SHADECUT_OT_render_lambertian.bl_idname, icon="RENDER_STILL")


class ReconstructPanel:
    bl_label = "Shape from Shading"
    bl_region_type = "UI"
    bl_category = "ShadeCut"

    def draw(self, context):
        draw_reconstruct_settings(self.layout, context.scene.shadecut)


class SHADECUT_PT_reconstruct_view3d(ReconstructPanel, bpy.types.Panel):
    bl_space_type = "VIEW_3D"


class SHADECUT_PT_reconstruct_image(ReconstructPanel, bpy.types.Panel):
    bl_space_type = "IMAGE_EDITOR"


class AdvancedPanel:
    """The research settings, folded away: an artist seldom needs them."""

    bl_label = "Advanced"
    bl_region_type = "UI"
    bl_category = "ShadeCut"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        draw_advanced_settings(self.layout, context.scene.shadecut)


class SHADECUT_PT_advanced_view3d(AdvancedPanel, bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_parent_id = SHADECUT_PT_reconstruct_view3d.__name__


class SHADECUT_PT_advanced_image(AdvancedPanel, bpy.types.Panel):
    bl_space_type = "IMAGE_EDITOR"
    bl_parent_id = SHADECUT_PT_reconstruct_image.__name__


class SHADECUT_PT_render_view3d(bpy.types.Panel):
    bl_label = "Render Lambertian test image"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "ShadeCut"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        draw_render_settings(self.layout, context.scene.shadecut_render)
