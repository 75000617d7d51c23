"""The "Render Lambertian test image" operator: the meshes rendered by Cycles with exact ground truth.

Its settings are ``scene.shadecut_render`` (properties.ShadeCutRenderSettings), drawn by
panels.draw_render_settings; the rendering itself is lambertian.render_lambertian.
"""

from pathlib import Path

import bpy

from . import lambertian


class SHADECUT_OT_render_lambertian(bpy.types.Operator):
    """Render a Lambertian image of the meshes with exact normals, depth and mask (Cycles)"""

    bl_idname = "shadecut.render_lambertian"
    bl_label = "Render Lambertian test image"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        reason = lambertian.files_unavailable()
        if reason:
            cls.poll_message_set(reason)
        return reason is None

    def execute(self, context):
        settings = context.scene.shadecut_render
        output = settings.output_dir
        if output.startswith("//") and not bpy.data.filepath:
            self.report({"ERROR"}, "Save the .blend file first, or choose an absolute output folder")
            return {"CANCELLED"}
        folder = Path(bpy.path.abspath(output))
        light = settings.light_direction[:]
        if settings.light_source == "SUN":
            if settings.sun is None:
                self.report({"ERROR"}, "Choose a Sun light, or give a light direction")
                return {"CANCELLED"}
            light = settings.sun
        camera = None
        if settings.camera_source == "SCENE":
            camera = context.scene.camera
            if camera is None:
                self.report({"ERROR"}, "The scene has no camera; add one or use the fitted camera")
                return {"CANCELLED"}
        try:
            render = lambertian.render_lambertian(
                lambertian.mesh_objects(context, settings.objects == "SELECTED"),
                light=light,
                camera=camera,
                resolution=(settings.resolution_x, settings.resolution_y),
                albedo=settings.albedo if settings.albedo_source == "UNIFORM" else None,
                shadows=settings.shadows,
                indirect=settings.indirect,
                noise=settings.noise,
                bits=None if settings.quantization == "FLOAT" else int(settings.quantization),
                seed=settings.seed,
                samples=settings.samples or None,
                frame=context.scene.frame_current,
            )
            render.write(folder)
        except (RuntimeError, ValueError, OSError) as error:  # RenderError, Cycles, unwritable folder
            self.report({"ERROR"}, f"ShadeCut render: {error}")
            return {"CANCELLED"}
        except Exception as error:  # anything else is a bug, still reported in the UI, not as a traceback
            self.report({"ERROR"}, f"ShadeCut render failed ({type(error).__name__}): {error}")
            return {"CANCELLED"}
        image = use_for_reconstruction(context, folder, render.light)
        mean = float(render.image[render.mask].mean()) if render.mask.any() else 0.0
        self.report({"INFO"}, f"Rendered {settings.resolution_x} x {settings.resolution_y}, mean intensity "
                              f"{mean:.3f}, into {folder}; image '{image.name}' and its light are set for "
                              "Reconstruct")
        return {"FINISHED"}


def use_for_reconstruction(context, folder: Path, light) -> bpy.types.Image:
    """Opens the rendered image.exr and makes it, with its light, the reconstruction's input, so
    that rendering a test image and reconstructing it are two clicks."""
    image = bpy.data.images.load(str(folder / "image.exr"), check_existing=True)
    image.reload()  # a re-render overwrote the file behind an already open datablock
    settings = context.scene.shadecut
    settings.image = image
    settings.light_source, settings.light_direction = "DIRECTION", tuple(float(v) for v in light)
    return image
