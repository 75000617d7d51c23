"""The image to reconstruct, and its pixels as the core's linear input.

Which image: the file the operator was given, else the panel's, the Image Editor's, the active
Image Texture node's, or any open Image Editor's. Its pixels: Blender's buffer decoded by the
image's colour space, row 0 at the top.
"""

from __future__ import annotations

import os
from typing import Optional

import bpy
import numpy as np

from .. import imaging
from ..file_kinds import special_file_kind

# Colour spaces whose stored 8-bit values are linear already.
LINEAR_SPACES = {"Linear", "Linear ACES", "Linear ACEScg", "Non-Color", "Raw", "XYZ"}

# Image sources that are not one still picture, as the messages name them.
MOVING_SOURCES = {"SEQUENCE": "an image sequence", "MOVIE": "a movie"}


class InputError(ValueError):
    """Bad input the user can fix; the message says how."""


def image_pixels(image: bpy.types.Image) -> tuple[np.ndarray, np.ndarray]:
    """Linear intensity (H, W) and mask (H, W) of a Blender image, row 0 at the top.

    Float buffers hold scene-linear values; byte buffers hold the file's encoded values, decoded
    here according to the image's colour space.
    """
    if image.source in MOVING_SOURCES:  # their pixels are a frame's, or none: not "a missing file"
        raise InputError(f"Image '{image.name}' is {MOVING_SOURCES[image.source]}: ShadeCut reconstructs one still "
                         "image; set its Source to Single Image, or choose another")
    width, height = image.size
    if width * height == 0:
        raise InputError(f"Image '{image.name}' has no pixels (is its file missing?): reload it or choose another")
    if width < 2 or height < 2:
        raise InputError(f"Image '{image.name}' is {width} x {height} pixels: at least 2 x 2 are needed")
    space = image.colorspace_settings.name
    srgb = not image.is_float and space not in LINEAR_SPACES
    if srgb and space != "sRGB":
        raise InputError(f"Image '{image.name}' is in colour space '{space}': set it to sRGB or Linear")
    rgba = np.empty(width * height * image.channels, dtype=np.float32)
    image.pixels.foreach_get(rgba)
    rgba = rgba.reshape(height, width, image.channels)[::-1]
    if image.channels != 4:
        rgba = np.dstack([np.repeat(rgba[..., :1], 3, axis=2) if image.channels < 3 else rgba[..., :3],
                          np.ones((height, width, 1), np.float32)])
    intensity, mask, _ = imaging.intensity_and_mask(rgba, srgb_encoded=srgb)
    finite = np.isfinite(intensity)
    if not finite[mask].all():
        bad = np.count_nonzero(~finite & mask)
        raise InputError(f"Image '{image.name}' has {bad} NaN or infinite pixel{'s' if bad > 1 else ''}: "
                         "shape from shading needs finite intensities")
    intensity = np.where(finite, intensity, 0.0).astype(np.float32)  # outside the mask: unused
    return intensity, mask


def load_file(filepath: str) -> tuple[bpy.types.Image, bool]:
    """The image of ``filepath`` and whether this call created its datablock (False when
    ``check_existing`` handed back one the user already had)."""
    path = bpy.path.abspath(filepath)
    if not os.path.exists(path):
        raise InputError(f"Cannot read '{filepath}': there is no such file")
    if os.path.isdir(path):
        raise InputError(f"Cannot read '{filepath}': it is a directory, not an image file")
    kind = special_file_kind(path)
    if kind is not None:  # Blender would wait on a pipe forever, and read a device without end
        raise InputError(f"Cannot read '{filepath}': it is {kind}, not an image file")
    existing = {image.as_pointer() for image in bpy.data.images}
    try:
        image = bpy.data.images.load(filepath, check_existing=True)
    except RuntimeError as error:
        reason = str(error).strip()
        reason = reason.removeprefix("Error:").strip().removeprefix(f"Cannot read '{filepath}':").strip()
        raise InputError(f"Cannot read '{filepath}': {reason or 'Blender cannot load it'}") from error
    created = image.as_pointer() not in existing
    if tuple(image.size) == (0, 0):
        if created:
            bpy.data.images.remove(image)
        raise InputError(f"Cannot read '{filepath}': it is not an image file Blender can read")
    return image, created


def image_to_reconstruct(context, settings, filepath: str) -> tuple[bpy.types.Image, bool, str]:
    """The image to reconstruct, whether this call loaded it (see :func:`load_file`), and where it
    came from when the panel did not name it ("" otherwise)."""
    if filepath:
        return (*load_file(filepath), "")
    image, origin = _open_image(context, settings)
    return image, False, origin


def active_texture_node(context) -> Optional[bpy.types.Node]:
    """The active object's active material's active node when it is an Image Texture node with an
    image (what texture add-ons such as DeepBump act on), else None."""
    obj = context.active_object
    material = obj.active_material if obj is not None else None
    if material is None or not material.use_nodes or material.node_tree is None:
        return None
    node = material.node_tree.nodes.active
    if node is None or node.type != "TEX_IMAGE" or node.image is None:
        return None
    return node


def _open_image(context, settings) -> tuple[bpy.types.Image, str]:
    """The panel's image; else the image of the Image Editor the operator runs in; else the image of
    the selected Image Texture node; else the image of any open Image Editor. With where it came from."""
    if settings.image is not None:
        return settings.image, ""
    space = context.space_data
    if space is not None and space.type == "IMAGE_EDITOR" and space.image is not None:
        return space.image, ""
    node = active_texture_node(context)
    if node is not None:
        material = context.active_object.active_material
        return node.image, f"the Image Texture node '{node.name}' of material '{material.name}'"
    for area in context.screen.areas if context.screen else ():
        if area.type == "IMAGE_EDITOR" and area.spaces.active.image is not None:
            return area.spaces.active.image, ""
    raise InputError("No image: choose one in the ShadeCut panel, open one in the Image Editor, select an Image "
                     "Texture node in the active object's material, or pick a file")


