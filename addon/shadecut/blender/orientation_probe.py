"""Whether this Blender turns a TIFF by its Orientation tag when it loads it, found by loading one.

Blender 3.4 reads TIFFs through libtiff's RGBA interface, which applies the tag's mirrors and half turn
(1 to 4) and only mirrors a quarter turn (5 to 8); Blender 4.3 and 5.2 read them through OpenImageIO,
which applies nothing (checked by loading TIFFs of each orientation in Debian's 3.4.1, 4.3.2 and
5.2.2). Rather than trust a version number, a 2 x 1 TIFF declaring orientation 3 (a half turn) is
written and loaded once per session: if its white pixel comes back on the other side, Blender turned it.
"""

from __future__ import annotations

import functools
import os
import shutil
import struct
import tempfile

import bpy
import numpy as np

# A little-endian, uncompressed, 8-bit grey TIFF of 2 x 1 pixels, white then black, Orientation 3.
_ENTRIES = ((256, 3, 2), (257, 3, 1), (258, 3, 8), (259, 3, 1), (262, 3, 1), (273, 4, 0), (274, 3, 3),
            (277, 3, 1), (278, 3, 1), (279, 4, 2))


def _half_turned_tiff() -> bytes:
    data_offset = 8 + 2 + 12 * len(_ENTRIES) + 4
    directory = struct.pack("<H", len(_ENTRIES))
    for tag, kind, value in _ENTRIES:
        value = data_offset if tag == 273 else value
        directory += struct.pack("<HHI", tag, kind, 1) + struct.pack("<I" if kind == 4 else "<HH",
                                                                      *((value,) if kind == 4 else (value, 0)))
    return b"II*\x00" + struct.pack("<I", 8) + directory + struct.pack("<I", 0) + bytes((255, 0))


@functools.cache
def blender_turns_tiffs() -> bool:
    """True when this Blender applies a TIFF's Orientation tag itself (mirrors and half turn)."""
    folder = tempfile.mkdtemp(prefix="shadecut_orientation_")
    path = os.path.join(folder, "half_turned.tif")
    image = None
    try:
        with open(path, "wb") as file:
            file.write(_half_turned_tiff())
        image = bpy.data.images.load(path)
        pixels = np.empty(len(image.pixels), dtype=np.float32)
        image.pixels.foreach_get(pixels)
        first, second = pixels.reshape(-1, image.channels)[:2, 0]
        return bool(second > first)  # the white pixel moved to the right: turned
    except (OSError, RuntimeError, ValueError):  # cannot tell: as Blender 4 and 5, which turn nothing
        return False
    finally:
        if image is not None:
            bpy.data.images.remove(image)
        shutil.rmtree(folder, ignore_errors=True)
