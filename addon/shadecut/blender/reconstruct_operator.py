"""The "Reconstruct" operator: a Blender image in, a new mesh object at the 3-D cursor out (or, with
Apply to = Active object, its maps in the active object's material). The work is a
:class:`~.reconstruct_job.Job`; this class only starts it, in place or on a worker thread with
progress and Esc, and hands it to :func:`~.reconstruct_job.finish_job`."""

from __future__ import annotations

import threading
from typing import Optional

import bpy

from .image_input import InputError
from .reconstruct_job import Job, finish_job, prepare_job


class SHADECUT_OT_reconstruct(bpy.types.Operator):
    """Reconstruct a 3-D surface from the shading of an image (Chang, Lee & Lee graph cuts)"""

    bl_idname = "shadecut.reconstruct"
    bl_label = "Reconstruct"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(
        name="Image file", subtype="FILE_PATH", options={"SKIP_SAVE"},
        description="An image file to use instead of the panel's image",
    )
    use_file_browser: bpy.props.BoolProperty(options={"HIDDEN", "SKIP_SAVE"})
    filter_image: bpy.props.BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})

    _job: Optional[Job] = None
    _thread: Optional[threading.Thread] = None
    _timer = None
    _interactive = False

    def invoke(self, context, event):
        self._interactive = True
        if self.use_file_browser and not self.filepath:
            context.window_manager.fileselect_add(self)
            return {"RUNNING_MODAL"}
        return self.execute(context)

    def execute(self, context):
        try:
            job = prepare_job(context, self.filepath)
        except InputError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except ValueError as error:  # any other refusal of the input by the library
            self.report({"ERROR"}, f"Cannot reconstruct: {error}")
            return {"CANCELLED"}
        if not self._interactive or bpy.app.background:
            job.run()
            return finish_job(self, context, job)
        return self._start_modal(context, job)

    def _start_modal(self, context, job: Job):
        self._job = job
        self._thread = threading.Thread(target=job.run, name="shadecut-reconstruct", daemon=True)
        self._thread.start()
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(0.1, window=context.window)
        window_manager.progress_begin(0, 100)
        window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC":
            job.cancel = True
        if event.type != "TIMER" and not job.cancel:
            return {"PASS_THROUGH"}
        if self._thread.is_alive():
            context.window_manager.progress_update(int(100 * job.fraction))
            context.workspace.status_text_set(
                f"ShadeCut: {job.stage} {job.fraction:.0%}" + (" (cancelling)" if job.cancel else "  Esc to cancel"))
            return {"RUNNING_MODAL"}
        self._end_modal(context)
        return finish_job(self, context, job)

    def _end_modal(self, context):
        window_manager = context.window_manager
        window_manager.event_timer_remove(self._timer)
        window_manager.progress_end()
        context.workspace.status_text_set(None)
