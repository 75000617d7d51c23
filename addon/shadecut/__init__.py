"""ShadeCut: shape from shading using graph cuts (Chang, Lee & Lee, Pattern Recognition 41, 2008).

The conventions (image axes, camera frame, light direction, depth sign) are those of the project
README. Importing this package never needs Blender's ``bpy``.
"""

from .api import (
    Cancelled,
    LoadedImage,
    Reconstruction,
    angular_error,
    angular_error_map,
    erode_mask,
    estimate_albedo,
    integrate,
    load_image,
    normals_from_depth,
    reconstruct,
    render,
    save_depth,
    save_image,
    save_mesh,
    save_normals,
)

__version__ = "0.1.0"

__all__ = [
    "Cancelled",
    "LoadedImage",
    "Reconstruction",
    "angular_error",
    "angular_error_map",
    "erode_mask",
    "estimate_albedo",
    "integrate",
    "load_image",
    "normals_from_depth",
    "reconstruct",
    "render",
    "save_depth",
    "save_image",
    "save_mesh",
    "save_normals",
]
