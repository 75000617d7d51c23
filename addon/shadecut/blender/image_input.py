"""The image to reconstruct, and its pixels as the core's linear input.

Which image: the file the operator was given, else the panel's, the Image Editor's, the active
Image Texture node's, or any open Image Editor's; or the panel's several Photographs. Its pixels:
Blender's buffer decoded by the image's colour space, row 0 at the top.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Optional

import bpy
import numpy as np

from .. import _core, imaging
from ..file_kinds import special_file_kind
from ..image_header import (SEARCH_LIMIT, cut_short_bytes, declared_size, exif_orientation_bytes, exr_channel_names,
                            mapped, oriented, tiff_extra_sample_undeclared, tiff_pages)
from .capabilities import linear_colour_spaces
from .orientation_probe import blender_turns_tiffs
from .wording import short_bytes

# Bytes per pixel while an image file is read: Blender's own buffer (float RGBA for 16-bit and float
# files, which the header check does not tell apart from 8-bit ones) and the float RGBA copy that
# bpy hands to Python (it offers no smaller one). Measured: 660 MB above the start for a 16-bit
# 4096 x 4096 PNG with Max size 2048, the bands' temporaries included (930 MB when whole-image copies
# were made).
READ_BYTES_PER_PIXEL = 16 + 16
# Pixels converted at a time: bounds the temporary copies of a band.
BAND_PIXELS = 1 << 22
# Image sources that are not one still picture, as the messages name them.
MOVING_SOURCES = {"SEQUENCE": "an image sequence", "MOVIE": "a movie"}


# The channel names (the last part of a layered EXR's "layer.R") that say a channel holds the picture.
IMAGE_CHANNELS = {"R", "G", "B", "Y"}
CUT_SHORT = ("the file is cut short (its data stops before the end of the image, as after an interrupted copy or "
             "download): copy it again")


class InputError(ValueError):
    """Bad input the user can fix; the message says how."""


def image_pixels(image: bpy.types.Image, max_size: int = 0) -> tuple[np.ndarray, np.ndarray, int, np.ndarray | None]:
    """Linear intensity (h, w) and mask (h, w) of a Blender image, row 0 at the top, shrunk by the
    whole factor that Max size ``max_size`` asks for (imaging.shrink_factor; 0 = full size), that
    factor, and the linear RGB (h, w, 3) of a colour image (None for a grey one), shrunk alike; all
    turned upright as the file's EXIF orientation says (:func:`image_orientation`).

    Float buffers hold scene-linear values; byte buffers hold the file's encoded values, decoded
    here according to the image's colour space. A file Blender has not decoded yet is first checked
    by its header (:func:`check_declared_size`). The pixels are converted and shrunk in bands of
    whole blocks, so that the float copy bpy hands over is the only full-size array.
    """
    if image.source in MOVING_SOURCES:  # their pixels are a frame's, or none: not "a missing file"
        raise InputError(f"Image '{image.name}' is {MOVING_SOURCES[image.source]}: ShadeCut reconstructs one still "
                         "image; set its Source to Single Image, or choose another")
    if image.source == "FILE" and not image.has_data and image.packed_file is None:
        check_declared_size(f"Image '{image.name}'", bpy.path.abspath(image.filepath, library=image.library))
    if image.source == "FILE":
        _check_whole(image)
    width, height = image.size
    if width * height == 0:
        raise InputError(f"Image '{image.name}' has no pixels (is its file missing?): reload it or choose another")
    if width < 2 or height < 2:
        raise InputError(f"Image '{image.name}' is {width} x {height} pixels: at least 2 x 2 are needed")
    srgb = not image.is_float and _stored_as_srgb(image)
    factor = _shrink_factor(image.name, width, height, max_size)
    stored = np.empty(width * height * image.channels, dtype=np.float32)
    image.pixels.foreach_get(stored)
    stored = stored.reshape(height, width, image.channels)  # row 0 at the bottom, as Blender keeps it
    kept = height - height % factor  # the top rows: the bottom ones that fill no block are dropped
    band = factor * max(1, BAND_PIXELS // (width * factor))
    in_colour = image.channels >= 3
    intensities, masks, colours, bad, bad_outside = [], [], [], 0, 0
    opaque = tiff_extra_sample_undeclared(_file_start(image))  # a second channel that is not an alpha
    for top in range(0, kept, band):
        rows = min(band, kept - top)
        rgba = _rgba(stored[height - top - rows:height - top][::-1])
        if opaque:
            rgba[..., 3] = 1.0
        intensity, mask, colour = imaging.decode_rgba(rgba, srgb_encoded=srgb)
        finite = np.isfinite(intensity)
        bad += np.count_nonzero(~finite)
        bad_outside += np.count_nonzero(~finite & ~mask)
        intensity[~finite] = 0.0  # refused below: the band is shrunk first, so the count covers every band
        small, small_mask = imaging.shrink(intensity, mask, factor)
        intensities.append(small)
        masks.append(small_mask)
        if in_colour:
            colour[~finite] = 0.0
            colours.append(np.dstack([imaging.shrink(np.ascontiguousarray(colour[..., k]), mask, factor)[0]
                                      for k in range(3)]))
    if bad:  # anywhere, even under a transparent alpha: the library and the command line refuse the same file
        outside = f" ({bad_outside} of them where its alpha is transparent)" if bad_outside else ""
        raise InputError(f"Image '{image.name}' has {bad} NaN or infinite pixel{'s' if bad > 1 else ''}{outside}: "
                         "shape from shading needs finite intensities")
    turn = image_orientation(image)  # the file's EXIF orientation, which Blender does not apply
    return (oriented(np.concatenate(intensities), turn), oriented(np.concatenate(masks), turn), factor,
            oriented(np.concatenate(colours), turn) if in_colour else None)


def image_orientation(image: bpy.types.Image) -> int:
    """The EXIF orientation (1 to 8, 1 = upright) still to apply to the pixels Blender decoded of
    ``image``: a phone's portrait is stored sideways (6 or 8), every viewer shows it upright, and the
    light the user gives is the one seen upright. Blender ignores a JPEG's orientation (3.4, 4.3 and
    5.2 alike), so it is applied here, as a TIFF's where Blender ignores that too (4.3, 5.2). Where
    Blender turns a TIFF itself (3.4: :func:`~.orientation_probe.blender_turns_tiffs`), it applies
    the mirrors and the half turn (1 to 4) but only mirrors a quarter turn (5 to 8): InputError for
    those, which no reading here can undo for certain."""
    start = _file_start(image)
    orientation = exif_orientation_bytes(start)
    if orientation == 1 or start[:2] == b"\xff\xd8" or not blender_turns_tiffs():
        return orientation
    if orientation > 4:  # a TIFF turned by a quarter
        raise InputError(f"Image '{image.name}' is stored turned by a quarter (its Orientation tag is {orientation}), "
                         "which Blender reads only in part: save it upright in an image editor first")
    return 1


def _file_start(image: bpy.types.Image) -> bytes:
    """The first bytes of the file (or packed file) behind ``image``, where its header lies; b"" for a
    generated image or a file that cannot be read (a pipe is never opened)."""
    if image.source != "FILE":
        return b""
    if image.packed_file is not None:
        return image.packed_file.data[:SEARCH_LIMIT]
    with mapped(bpy.path.abspath(image.filepath, library=image.library)) as data:
        return b"" if data is None else data[:SEARCH_LIMIT]


def upright_size(image: bpy.types.Image) -> tuple[int, int]:
    """(width, height) of ``image`` as shown upright: a file stored turned by a quarter swaps them."""
    width, height = image.size
    return (height, width) if image_orientation(image) > 4 else (width, height)


def _check_whole(image: bpy.types.Image) -> None:
    """InputError for an image whose file (or packed copy) is cut short (a JPEG, a PNG) or holds more
    pages than the one Blender reads (a TIFF): Blender shows grey rows, or the first page, without
    a word, and that would be reconstructed."""
    if image.packed_file is not None:
        problem = file_problem(image.packed_file.data)
    else:
        with mapped(bpy.path.abspath(image.filepath, library=image.library)) as data:
            problem = None if data is None else file_problem(data)
    if problem:
        raise InputError(f"Image '{image.name}': {problem}")


def file_problem(data) -> Optional[str]:
    """What makes a file's bytes unfit though Blender decodes them, in words; None when nothing does."""
    if cut_short_bytes(data):
        return CUT_SHORT
    if tiff_pages(data) > 1:
        return ("the file is a TIFF of several pages, of which Blender reads only the first: save the page to "
                "reconstruct as a file of its own")
    channels = exr_channel_names(data)
    if channels is not None and not {name.rsplit(".", 1)[-1] for name in channels} & IMAGE_CHANNELS:
        return (f"the file is an EXR whose channels ({', '.join(channels)}) name no colour (R, G, B) or grey (Y): "
                "which of them holds the picture is unknown (Blender reads one as it likes); name them so")
    return None


def _stored_as_srgb(image: bpy.types.Image) -> bool:
    """Whether the 8-bit values of ``image`` are sRGB-encoded (True) or linear (False), by its colour
    space; InputError for one that is neither, naming the spaces this Blender has that would do."""
    space = image.colorspace_settings.name
    linear = linear_colour_spaces()
    if space in linear or space == "sRGB":
        return space == "sRGB"
    raise InputError(f"Image '{image.name}' is in colour space '{space}', which ShadeCut cannot decode: set its "
                     f"Color Space to sRGB or to a linear one ({', '.join(sorted(linear))})")


def picked_mask(mask_image: bpy.types.Image, source: bpy.types.Image, max_size: int) -> np.ndarray:
    """The object's pixels (h, w) from the panel's Mask image at the working size of ``source``: its
    alpha where it has transparency, else its pixels brighter than half its brightest (white = object)."""
    (mask_width, mask_height), (width, height) = upright_size(mask_image), upright_size(source)
    if (mask_width, mask_height) != (width, height):
        raise InputError(f"Mask '{mask_image.name}' is {mask_width} x {mask_height} pixels and image "
                         f"'{source.name}' {width} x {height}: the mask must be as large as the image")
    intensity, alpha, _, _ = image_pixels(mask_image, max_size)
    mask = alpha if not alpha.all() else intensity > 0.5 * float(intensity.max())
    if not mask.any():
        raise InputError(f"Mask '{mask_image.name}' marks no pixel: paint the object white (or opaque) on black")
    return mask


def show_mask(name: str, mask: np.ndarray) -> bpy.types.Image:
    """The mask used, as the grey image '<name> mask' (white = reconstructed), made or replaced."""
    title = f"{name} mask"
    height, width = mask.shape
    image = bpy.data.images.get(title)
    if image is not None and tuple(image.size) != (width, height):
        bpy.data.images.remove(image)
        image = None
    if image is None:
        image = bpy.data.images.new(title, width, height, alpha=False)
    value = np.ascontiguousarray(mask[::-1], dtype=np.float32)  # Blender keeps row 0 at the bottom
    image.pixels.foreach_set(np.dstack([value, value, value, np.ones_like(value)]).ravel())
    image.update()
    return image


def _rgba(pixels: np.ndarray) -> np.ndarray:
    """(rows, W, C) pixels of any channel count as contiguous RGBA: grey spread to R, G and B, opaque
    when there is no alpha."""
    channels = pixels.shape[2]
    if channels == 4:
        return np.ascontiguousarray(pixels)
    colour = np.repeat(pixels[..., :1], 3, axis=2) if channels < 3 else pixels[..., :3]
    return np.dstack([colour, np.ones((*pixels.shape[:2], 1), np.float32)])


def _shrink_factor(name: str, width: int, height: int, max_size: int) -> int:
    try:
        return imaging.shrink_factor(height, width, max_size)
    except ValueError as error:
        smallest = math.ceil(max(height, width) / (min(height, width) // 2))
        raise InputError(f"Max size {max_size} px is too small for the {width} x {height} image '{name}' "
                         f"(fewer than 2 x 2 pixels would remain): use at least {smallest}, or 0 for full size"
                         ) from error


def check_declared_size(label: str, path: str) -> None:
    """InputError before Blender decodes the file at ``path`` when the size its header declares needs
    more memory to read than this machine has available, or is more pixels than the library reads
    from a file (``load_image``'s default ``max_pixels``) (``label`` names it in the message)."""
    size, available = declared_size(path), available_memory()
    if size is None:
        return
    width, height = size
    needed = width * height * READ_BYTES_PER_PIXEL
    if available is not None and needed > available:
        raise InputError(f"{label} is {width:,} x {height:,} pixels (its file's header says so): reading it takes "
                         f"about {short_bytes(needed)}, more than the {short_bytes(available)} of memory available. "
                         "Shrink it in an image editor first")
    if width * height > _core.DEFAULT_MAX_PIXELS:
        raise InputError(f"{label} is {width:,} x {height:,} pixels (its file's header says so), more than the "
                         f"{_core.DEFAULT_MAX_PIXELS:,} ShadeCut reads from a file. Shrink it in an image editor first")


def available_memory() -> Optional[int]:
    """Bytes of memory available for new allocations (Linux's MemAvailable), or None where unknown."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError):
        pass
    return None


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
    with mapped(path) as data:
        problem = None if data is None else file_problem(data)
    if problem:
        raise InputError(f"Cannot read '{filepath}': {problem}")
    check_declared_size(f"Image file '{filepath}'", path)
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




@dataclass
class Photographs:
    """The pixels of several photographs of one view at one working size (see :func:`image_pixels`)."""

    sources: list  # the Blender images, in the list's order
    images: np.ndarray  # (K, H, W) linear intensity
    colours: Optional[np.ndarray]  # (K, H, W, 3) linear RGB when every photograph has colour, else None
    mask: np.ndarray  # (H, W): opaque in every photograph
    factor: int  # the Max size shrink factor, the same for all


def read_photographs(rows, max_size: int) -> Photographs:
    """The pixels of the panel's Photographs rows; InputError for a row without an image, or images
    of different sizes (several photographs must be of one view)."""
    sources = []
    for index, row in enumerate(rows):
        if row.image is None:
            raise InputError(f"Photograph {index + 1} has no image: pick one, or remove its row")
        sources.append(row.image)
    first = upright_size(sources[0])
    for index, source in enumerate(sources[1:], start=2):
        if upright_size(source) != first:
            raise InputError(f"Photograph {index} ('{source.name}') is {' x '.join(map(str, upright_size(source)))} "
                             f"pixels but the first ('{sources[0].name}') is {first[0]} x {first[1]}: several "
                             "photographs must be of one view from one place, all of one size")
    read = [image_pixels(source, max_size) for source in sources]
    colours = [colour for _, _, _, colour in read]
    mask = np.logical_and.reduce([mask for _, mask, _, _ in read])
    if len(sources) > 1 and not mask.any() and all(mask.any() for _, mask, _, _ in read):
        raise InputError("No pixel is opaque in every photograph: their alphas do not overlap, but photographs of "
                         "one view share one outline")
    return Photographs(
        sources=sources,
        images=np.stack([image for image, _, _, _ in read]),
        colours=None if any(colour is None for colour in colours) else np.stack(colours),
        mask=mask,
        factor=read[0][2],
    )
