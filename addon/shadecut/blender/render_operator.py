"""The "Render Lambertian test image" operator, its settings and their panel drawing.

The add-on's registration registers ``CLASSES`` (the PropertyGroup first), attaches the settings as
``bpy.types.Scene.shadecut_render`` and calls :func:`draw_render_settings` from the ShadeCut panel.
"""

from pathlib import Path

import bpy

from . import lambertian


def _is_sun(_settings, ob) -> bool:
    return ob.type == "LIGHT" and ob.data.type == "SUN"


class ShadeCutRenderSettings(bpy.types.PropertyGroup):
    """Settings of the Lambertian test render (see shadecut.blender.lambertian.render_lambertian)."""

    objects: bpy.props.EnumProperty(
        name="Objects",
        items=(("SELECTED", "Selected", "The selected mesh objects"),
               ("VISIBLE", "Visible", "Every mesh visible in the view layer")),
        default="SELECTED",
    )
    light_source: bpy.props.EnumProperty(
        name="Light",
        items=(("DIRECTION", "Direction", "A direction toward the light in the camera frame (x right, y up, "
                                          "z toward the viewer)"),
               ("SUN", "Sun", "The direction of a Sun light of the scene")),
        default="DIRECTION",
    )
    light_direction: bpy.props.FloatVectorProperty(
        name="Direction", size=3, default=(1.0, 0.0, 1.0), subtype="XYZ",
        description="Toward the light, camera frame; z must be > 0",
    )
    sun: bpy.props.PointerProperty(name="Sun", type=bpy.types.Object, poll=_is_sun)
    camera_source: bpy.props.EnumProperty(
        name="Camera",
        items=(("FIT", "Fitted orthographic", "An orthographic camera fitted to the objects, front view"),
               ("SCENE", "Scene camera", "The scene's active camera")),
        default="FIT",
    )
    resolution_x: bpy.props.IntProperty(name="Width", default=256, min=2, max=16384, subtype="PIXEL")
    resolution_y: bpy.props.IntProperty(name="Height", default=256, min=2, max=16384, subtype="PIXEL")
    albedo_source: bpy.props.EnumProperty(
        name="Albedo",
        items=(("UNIFORM", "Uniform", "One diffuse albedo for every object"),
               ("OWN", "Own colours", "Each material's base colour (luminance), textures included")),
        default="UNIFORM",
    )
    albedo: bpy.props.FloatProperty(name="Albedo", default=0.8, min=0.001, max=1.0)
    shadows: bpy.props.BoolProperty(name="Cast shadows", default=False,
                                    description="Off: the Lambertian model of the paper, which has no shadows")
    indirect: bpy.props.BoolProperty(name="Indirect light", default=False,
                                     description="Light bouncing between surfaces (needs many samples)")
    samples: bpy.props.IntProperty(
        name="Samples", default=0, min=0, max=65536,
        description=f"Cycles samples per pixel; 0 = automatic (1 without indirect light, which is exact, "
                    f"{lambertian.INDIRECT_SAMPLES} with it)",
    )
    noise: bpy.props.FloatProperty(name="Noise", default=0.0, min=0.0, max=1.0, precision=4,
                                   description="Standard deviation of Gaussian noise added to the linear image")
    quantization: bpy.props.EnumProperty(
        name="Quantization",
        items=(("FLOAT", "Float", "No quantization"), ("8", "8-bit", "8-bit sRGB codes"),
               ("16", "16-bit", "16-bit sRGB codes")),
        default="FLOAT",
    )
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0, description="Seed of the noise")
    output_dir: bpy.props.StringProperty(
        name="Output", default="//shadecut_render", subtype="DIR_PATH",
        description="Folder that receives image.exr/.png, normals.exr, depth.exr, mask.png and meta.json",
    )


class SHADECUT_OT_render_lambertian(bpy.types.Operator):
    """Render a Lambertian image of the meshes with exact normals, depth and mask (Cycles)"""

    bl_idname = "shadecut.render_lambertian"
    bl_label = "Render Lambertian test image"
    bl_options = {"REGISTER", "UNDO"}

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
                              "Reconstruct from shading")
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


def draw_render_settings(layout, context) -> None:
    """Draws the render settings and the button into a panel's layout."""
    settings = context.scene.shadecut_render
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
    column.operator("shadecut.render_lambertian", icon="RENDER_STILL")


CLASSES = (ShadeCutRenderSettings, SHADECUT_OT_render_lambertian)
