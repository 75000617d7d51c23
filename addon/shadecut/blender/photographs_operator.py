"""The panel's Photographs list: several photographs of one view, each under its own light. "Add"
loads the files picked in the file browser (several at once; none picked: every image of the
folder, in name order), one row each; a file name that names a side of the image gives its row that
side, and when every row has one, Light becomes Side of the image (else Estimate, with four or more,
finds their lights). "Remove" takes the active row out of the list (its image stays in the .blend)."""

from __future__ import annotations

import os

import bpy

from .. import api
from .image_input import InputError, load_file
from .light_input import UNPICKED_SIDE


def _image_files_in(directory: str) -> list[str]:
    """The names of the image files (by Blender's image extensions) in ``directory``, sorted."""
    path = bpy.path.abspath(directory)
    if not os.path.isdir(path):
        return []
    return sorted(name for name in os.listdir(path) if os.path.isfile(os.path.join(path, name))
                  and os.path.splitext(name)[1].lower() in bpy.path.extensions_image)


def _light_wording(settings) -> str:
    """Sets Light to Side of the image when every row's file name named its side, and says so; else
    what is left to do."""
    sides = [row.side for row in settings.photographs]
    if UNPICKED_SIDE in sides:
        if settings.light_source == "ESTIMATE" and len(sides) >= api.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS:
            return ("Light is Estimate: Reconstruct finds their lights (set Light slant and First light from), "
                    "or give each its light (a Sun, a typed direction or a side of the image)")
        return "give each its light (a Sun, a typed direction or a side of the image), then Reconstruct"
    settings.light_source = "SIDE"
    return (f"lit from the sides their file names name ({', '.join(sides)}): Light set to Side of the image. "
            "Reconstruct")


class SHADECUT_OT_photographs_add(bpy.types.Operator):
    """Add photographs of one view, each lit from its own direction: select several in the file browser,
    or none to add every image of the folder (in name order)"""

    bl_idname = "shadecut.photographs_add"
    bl_label = "Add Photographs"
    bl_options = {"REGISTER", "UNDO"}

    files: bpy.props.CollectionProperty(type=bpy.types.OperatorFileListElement, options={"HIDDEN", "SKIP_SAVE"})
    directory: bpy.props.StringProperty(subtype="DIR_PATH", options={"HIDDEN", "SKIP_SAVE"})
    filter_image: bpy.props.BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})
    filter_folder: bpy.props.BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        names = [entry.name for entry in self.files if entry.name] or _image_files_in(self.directory)
        if not names:
            self.report({"ERROR"}, f"No file selected, and the folder '{self.directory}' holds no image file: "
                                   "select the photographs (Shift or Ctrl + click for several), or a folder of them")
            return {"CANCELLED"}
        paths = [os.path.join(self.directory, name) for name in names]
        loaded = []
        try:
            for path in paths:
                loaded.append(load_file(path))
        except InputError as error:
            for image, created in loaded:  # all or none: nothing half-added
                if created:
                    bpy.data.images.remove(image)
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        settings = context.scene.shadecut
        for image, _ in loaded:
            settings.photographs.add().image = image  # its Side read from the file name (properties._read_side)
        settings.photograph_index = len(settings.photographs) - 1
        added = f"{len(loaded)} photograph{'s' if len(loaded) > 1 else ''} added ({len(settings.photographs)} in the list)"
        self.report({"INFO"}, f"{added}: {_light_wording(settings)}")
        return {"FINISHED"}


class SHADECUT_OT_photographs_remove(bpy.types.Operator):
    """Take the selected photograph out of the list (its image stays in the .blend)"""

    bl_idname = "shadecut.photographs_remove"
    bl_label = "Remove Photograph"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return len(context.scene.shadecut.photographs) > 0

    def execute(self, context):
        settings = context.scene.shadecut
        index = min(settings.photograph_index, len(settings.photographs) - 1)
        settings.photographs.remove(index)
        settings.photograph_index = max(0, index - 1)
        return {"FINISHED"}
