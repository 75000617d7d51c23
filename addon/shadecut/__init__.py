"""ShadeCut: shape from shading using graph cuts (Chang, Lee & Lee, Pattern Recognition 41, 2008).

The conventions (image axes, camera frame, light direction, depth sign) are those of the project
README. Importing this package never needs Blender's ``bpy``: the add-on's own modules (the
``blender`` subpackage, or ``unavailable`` where the compiled module cannot load) are imported only
when Blender calls :func:`register`.
"""

bl_info = {
    "name": "ShadeCut",
    "author": "ShadeCut developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View / Image Editor > Sidebar > ShadeCut",
    "description": "Reconstruct a 3-D surface from one shaded image (shape from shading by graph cuts)",
    "category": "3D View",
}

import sys

from .compatibility import core_problem

# In Blender, a _core that cannot load here leaves the add-on a notice (see register) rather than a
# traceback; anywhere else `import shadecut` fails with the same sentence (raised by api).
_CORE_PROBLEM = core_problem()
if _CORE_PROBLEM is None or "bpy" not in sys.modules:
    from .api import (
        AMBIGUOUS_RESIDUAL_RATIO,
        LIGHT_METHODS,
        METHODS,
        MAX_THREADS,
        MAX_VERTICES,
        MIN_LABELS,
        OPTION_NAMES,
        option_fields,
        SceneKind,
        AlbedoMethod,
        Cancelled,
        CutOut,
        CutOutOptions,
        CutOutOutcome,
        Integrator,
        LightMethod,
        LoadedImage,
        Method,
        MethodDefaults,
        Reconstruction,
        ReconstructOptions,
        ReconstructStats,
        angular_error,
        angular_error_map,
        cut_out,
        erode_mask,
        mask_components,
        estimate_albedo,
        estimate_light,
        estimate_reflectance,
        flip,
        height_field_mesh,
        fold_back_facing,
        integrate,
        light_direction,
        method_defaults,
        load_image,
        light_from_side,
        LIGHT_SIDES,
        LUMINANCE_WEIGHTS,
        SIDE_LIGHT_SLANT_DEGREES,
        FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS,
        normals_from_depth,
        reconstruct,
        render,
        save_depth,
        save_image,
        save_mesh,
        save_normals,
        vertex_step,
    )

__version__ = "0.1.0"


def register() -> None:
    """Called by Blender when the add-on is enabled."""
    if _CORE_PROBLEM is not None:
        from . import unavailable

        unavailable.register(_CORE_PROBLEM)
        return
    from . import blender

    blender.register()


def unregister() -> None:
    if _CORE_PROBLEM is not None:
        from . import unavailable

        unavailable.unregister()
        return
    from . import blender

    blender.unregister()

__all__ = [
    "AMBIGUOUS_RESIDUAL_RATIO",
    "LIGHT_METHODS",
    "METHODS",
    "MAX_THREADS",
    "MAX_VERTICES",
    "MIN_LABELS",
    "OPTION_NAMES",
    "option_fields",
    "SceneKind",
    "AlbedoMethod",
    "Cancelled",
    "Integrator",
    "LightMethod",
    "LoadedImage",
    "Method",
    "MethodDefaults",
    "Reconstruction",
    "ReconstructOptions",
    "ReconstructStats",
    "angular_error",
    "angular_error_map",
    "erode_mask",
    "mask_components",
    "estimate_albedo",
    "estimate_light",
    "estimate_reflectance",
    "flip",
    "height_field_mesh",
    "fold_back_facing",
    "integrate",
    "light_direction",
    "method_defaults",
    "load_image",
    "light_from_side",
    "LIGHT_SIDES",
    "LUMINANCE_WEIGHTS",
    "SIDE_LIGHT_SLANT_DEGREES",
    "FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS",
    "normals_from_depth",
    "reconstruct",
    "render",
    "save_depth",
    "save_image",
    "save_mesh",
    "save_normals",
    "vertex_step",
]
