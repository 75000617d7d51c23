"""The panel's Photographs list: several photographs of one view, each under its own light. "Add"
loads the files picked in the file browser (several at once), one row each; "Remove" takes the
active row out of the list (its image stays in the .blend)."""

from __future__ import annotations

import os

import bpy

from .image_input import InputError, load_file


class SHADECUT_OT_photographs_add(bpy.types.Operator):
    """Add photographs of one view, each lit from its own direction: select several in the file browser"""

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
        paths = [os.path.join(self.directory, entry.name) for entry in self.files if entry.name]
        if not paths:
            self.report({"ERROR"}, "No file selected: select the photographs (Shift or Ctrl + click for several)")
            return {"CANCELLED"}
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
        photographs = context.scene.shadecut.photographs
        for image, _ in loaded:
            photographs.add().image = image
        context.scene.shadecut.photograph_index = len(photographs) - 1
        self.report({"INFO"}, f"{len(loaded)} photograph{'s' if len(loaded) > 1 else ''} added ({len(photographs)} "
                              "in the list): give each its light (a Sun, or a typed direction), then Reconstruct")
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
