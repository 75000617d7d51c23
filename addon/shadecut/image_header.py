"""An image file's width and height read from its header, without decoding any pixel; and what else
its bytes tell that Blender's decoders pass over: a JPEG or PNG cut short, a TIFF of several pages or
with an undeclared extra sample, an EXR's channel names, the EXIF orientation.

For the Blender add-on, whose zip has no OpenImageIO: it must know how large an image is before
Blender decodes it (a few hundred kilobytes of PNG can declare 16000 x 16000 pixels, gigabytes once
decoded). The formats are those Blender reads and users bring: PNG, JPEG, TIFF, OpenEXR, Radiance
HDR, BMP, Targa and WebP. Anything else, or a header this module cannot make sense of, gives None:
the caller then learns the size from the decoder, as before. No ``bpy`` here.
"""

from __future__ import annotations

import contextlib
import mmap
import os
import struct
from typing import BinaryIO, Iterator, Optional

from .file_kinds import special_file_kind

# The header fields sought lie within this many bytes of the start (JPEG: after the EXIF and ICC segments).
SEARCH_LIMIT = 1 << 20
_JPEG_FRAMES = {0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF}


def declared_size(path: str | os.PathLike) -> Optional[tuple[int, int]]:
    """(width, height) as the file's header declares them, or None when the format is not one of the
    module's or the header is unreadable."""
    try:
        with open(path, "rb") as file:
            start = file.read(64)
            for reader in (_png, _jpeg, _tiff, _exr, _hdr, _bmp, _webp):
                size = reader(start, file)
                if size is not None:
                    break
            else:
                size = _tga(start) if os.fspath(path).lower().endswith(".tga") else None
    except (OSError, ValueError, struct.error):
        return None
    if size is None or min(size) < 1:
        return None
    return size


def _png(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    if not start.startswith(b"\x89PNG\r\n\x1a\n") or start[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", start[16:24])


def _jpeg(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    if not start.startswith(b"\xff\xd8"):
        return None
    file.seek(2)
    while file.tell() < SEARCH_LIMIT:
        marker = file.read(2)
        while marker[:1] == b"\xff" and marker[1:] == b"\xff":  # fill bytes before a marker
            marker = marker[1:] + file.read(1)
        if len(marker) < 2 or marker[0] != 0xFF:
            return None
        if marker[1] in _JPEG_FRAMES:
            _length, _precision, height, width = struct.unpack(">HBHH", file.read(7))
            return width, height
        (length,) = struct.unpack(">H", file.read(2))
        file.seek(length - 2, os.SEEK_CUR)
    return None


def _tiff(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    order = {b"II*\x00": "<", b"MM\x00*": ">"}.get(start[:4])
    if order is None:
        return None
    (offset,) = struct.unpack(order + "I", start[4:8])
    file.seek(offset)
    (count,) = struct.unpack(order + "H", file.read(2))
    found = {}
    for _ in range(count):
        tag, kind, _items, value = struct.unpack(order + "HHI4s", file.read(12))
        if tag in (256, 257):  # ImageWidth, ImageLength: a SHORT or a LONG held in the entry itself
            found[tag] = struct.unpack(order + ("H" if kind == 3 else "I"), value[:2 if kind == 3 else 4])[0]
    return (found[256], found[257]) if len(found) == 2 else None


def _exr(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    if not start.startswith(b"\x76\x2f\x31\x01"):
        return None
    file.seek(8)
    while file.tell() < SEARCH_LIMIT:
        name, kind = _c_string(file), _c_string(file)
        if not name:  # the end of the (first part's) header
            return None
        (length,) = struct.unpack("<i", file.read(4))
        value = file.read(length)
        if name == b"dataWindow" and kind == b"box2i":
            x_min, y_min, x_max, y_max = struct.unpack("<iiii", value)
            return x_max - x_min + 1, y_max - y_min + 1
    return None


def _c_string(file: BinaryIO) -> bytes:
    text = b""
    while len(text) < 256:
        char = file.read(1)
        if char in (b"", b"\x00"):
            return text
        text += char
    raise ValueError("not a header attribute name")


def _hdr(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    if not (start.startswith(b"#?RADIANCE") or start.startswith(b"#?RGBE")):
        return None
    file.seek(0)
    lines = file.read(SEARCH_LIMIT // 16).split(b"\n")
    blank = lines.index(b"")  # the header ends with an empty line; the resolution line follows it
    first_axis, first, _second_axis, second = lines[blank + 1].split()[:4]
    return (int(second), int(first)) if first_axis[1:] == b"Y" else (int(first), int(second))


def _bmp(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    if not start.startswith(b"BM"):
        return None
    (info_size,) = struct.unpack("<I", start[14:18])
    if info_size == 12:  # the old OS/2 header: 16-bit sizes
        return struct.unpack("<HH", start[18:22])
    width, height = struct.unpack("<ii", start[18:26])
    return width, abs(height)  # a negative height stores the rows top-down


def _webp(start: bytes, file: BinaryIO) -> Optional[tuple[int, int]]:
    if start[:4] != b"RIFF" or start[8:12] != b"WEBP":
        return None
    chunk = start[12:16]
    if chunk == b"VP8 ":
        width, height = struct.unpack("<HH", start[26:30])
        return width & 0x3FFF, height & 0x3FFF
    if chunk == b"VP8L":
        (bits,) = struct.unpack("<I", start[21:25])
        return (bits & 0x3FFF) + 1, ((bits >> 14) & 0x3FFF) + 1
    if chunk == b"VP8X":
        return int.from_bytes(start[24:27], "little") + 1, int.from_bytes(start[27:30], "little") + 1
    return None


def _tga(start: bytes) -> Optional[tuple[int, int]]:
    return struct.unpack("<HH", start[12:16])


@contextlib.contextmanager
def mapped(path: str | os.PathLike) -> Iterator[Optional[mmap.mmap]]:
    """The bytes of the file at ``path``, mapped rather than read; None for a pipe or device (never
    opened: its reader refuses it by name), an empty, missing or unreadable file (its decoder says)."""
    if special_file_kind(path) is not None:
        yield None
        return
    try:
        file = open(path, "rb")
    except OSError:
        yield None
        return
    with file:
        try:
            data = mmap.mmap(file.fileno(), 0, access=mmap.ACCESS_READ)
        except (OSError, ValueError):  # mmap refuses a length of 0
            yield None
            return
        with data:
            yield data


def cut_short(path: str | os.PathLike) -> bool:
    """True when ``path`` is a JPEG or PNG whose data stops before the format's end: a copy or download
    cut short. Blender decodes such a file without a word (grey or missing rows); the library's
    reader refuses it. False for other formats, for what :func:`mapped` gives None, or a whole file."""
    with mapped(path) as data:
        return data is not None and _cut_short(data)


def cut_short_bytes(data: bytes) -> bool:
    """:func:`cut_short` for a file's bytes held in memory (a packed image)."""
    return _cut_short(data)


def _cut_short(data) -> bool:
    if data[:2] == b"\xff\xd8":
        return _jpeg_cut_short(data)
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return _png_cut_short(data)
    return False


def tiff_pages(data) -> int:
    """How many pages (image directories) a TIFF's bytes hold, counted up to 2: Blender reads the
    first of a multi-page TIFF without a word. 1 for anything else or a damaged chain."""
    directory = _tiff_directory(data)
    return 2 if directory is not None and 0 < directory[1] < len(data) else 1


def _tiff_directory(data) -> Optional[tuple[dict[int, int], int]]:
    """The first directory of a TIFF structure's bytes: the value of its entries that hold a SHORT or a
    LONG (tag -> the first value) and the offset of the next directory (0: none); None when not a TIFF
    or cut short."""
    order = {b"II*\x00": "<", b"MM\x00*": ">"}.get(bytes(data[:4]))
    if order is None:
        return None
    values = {}
    try:
        (offset,) = struct.unpack(order + "I", data[4:8])
        (count,) = struct.unpack(order + "H", data[offset:offset + 2])
        for index in range(count):
            start = offset + 2 + 12 * index
            tag, kind, items = struct.unpack(order + "HHI", data[start:start + 8])
            if kind == 3 and items <= 2:  # SHORTs held in the entry itself: the first one
                (values[tag],) = struct.unpack(order + "H", data[start + 8:start + 10])
            elif kind == 4 and items == 1:  # a LONG held in the entry itself
                (values[tag],) = struct.unpack(order + "I", data[start + 8:start + 12])
        (following,) = struct.unpack(order + "I", data[offset + 2 + 12 * count:offset + 6 + 12 * count])
    except struct.error:
        return None
    return values, following


def _jpeg_cut_short(data) -> bool:
    """The segments are walked to the first scan; from there the end-of-image marker must follow (the
    scans' coded bytes never hold it; an EXIF thumbnail's own, inside its segment, is skipped)."""
    offset = 2
    while offset + 4 <= len(data):
        if data[offset] != 0xFF:
            return False  # not a layout this check knows: the decoder judges
        marker = data[offset + 1]
        if marker == 0xFF:  # a fill byte
            offset += 1
            continue
        if marker == 0xDA:  # start of scan
            return data.find(b"\xff\xd9", offset) < 0
        (length,) = struct.unpack(">H", data[offset + 2:offset + 4])
        offset += 2 + length
    return True  # the headers themselves end early


def _png_cut_short(data) -> bool:
    """The chunks are walked to IEND; a chunk running past the end of the data means cut short."""
    offset = 8
    while offset + 8 <= len(data):
        (length,) = struct.unpack(">I", data[offset:offset + 4])
        if data[offset + 4:offset + 8] == b"IEND":
            return False
        offset += 12 + length  # length, type, data, CRC
    return True


# EXIF's Orientation tag (0x0112, TIFF's 274): how the stored rows are turned against what viewers show.
ORIENTATION_TAG = 0x0112


def exif_orientation_bytes(data: bytes) -> int:
    """The Orientation (1 to 8) declared by a JPEG's EXIF or a TIFF's first directory, given the file's
    first bytes (the EXIF segment lies near the start); 1 (as stored) when it declares none or the
    file is neither. Phones store portraits sideways with 6 or 8."""
    if data[:4] in (b"II*\x00", b"MM\x00*"):
        return _tiff_orientation(data)
    if data[:2] != b"\xff\xd8":
        return 1
    offset = 2
    while offset + 4 <= len(data) and data[offset] == 0xFF:
        marker = data[offset + 1]
        if marker in (0xDA, 0xD9):  # the scan starts: no EXIF after it
            break
        (length,) = struct.unpack(">H", data[offset + 2:offset + 4])
        if marker == 0xE1 and data[offset + 4:offset + 10] == b"Exif\x00\x00":
            return _tiff_orientation(data[offset + 10:offset + 2 + length])
        offset += 2 + length
    return 1


def _tiff_orientation(tiff: bytes) -> int:
    """The Orientation of a TIFF structure's first directory (EXIF's IFD0), 1 when absent or damaged."""
    directory = _tiff_directory(tiff)
    value = 1 if directory is None else directory[0].get(ORIENTATION_TAG, 1)
    return value if 1 <= value <= 8 else 1


def exr_channel_names(data) -> Optional[list[str]]:
    """The channel names an OpenEXR file's (first part's) header lists, from its bytes; None for
    another format or a header this cannot read."""
    if bytes(data[:4]) != b"\x76\x2f\x31\x01":
        return None
    offset = 8
    try:
        while offset < min(len(data), SEARCH_LIMIT):
            name_end = _index(data, offset)
            if name_end == offset:  # the end of the header: no channel list
                return None
            kind_end = _index(data, name_end + 1)
            (length,) = struct.unpack("<i", data[kind_end + 1:kind_end + 5])
            value = bytes(data[kind_end + 5:kind_end + 5 + length])
            if bytes(data[offset:name_end]) == b"channels" and bytes(data[name_end + 1:kind_end]) == b"chlist":
                names, position = [], 0
                while value[position:position + 1] not in (b"", b"\x00"):
                    end = value.index(b"\x00", position)
                    names.append(value[position:end].decode("utf-8", "replace"))
                    position = end + 1 + 16  # pixel type, pLinear and reserved, x and y sampling
                return names
            offset = kind_end + 5 + length
    except (ValueError, struct.error):
        return None
    return None


def _index(data, start: int) -> int:
    """Where the next NUL byte from ``start`` lies in bytes or a mapped file (which has no index());
    ValueError when none does."""
    found = data.find(b"\x00", start)
    if found < 0:
        raise ValueError("no end of a name")
    return found


def tiff_extra_sample_undeclared(data) -> bool:
    """True for a TIFF whose first directory holds a sample beyond its grey or RGB ones without saying
    what it is (no ExtraSamples tag, or 0 = unspecified): not an alpha by the TIFF rule, which Blender
    4.3 and 5.2 read as one all the same (Blender 3.4 does not). False for anything else."""
    directory = _tiff_directory(data)
    if directory is None:
        return False
    tags = directory[0]  # PhotometricInterpretation 262, SamplesPerPixel 277, ExtraSamples 338
    colour_samples = {0: 1, 1: 1, 2: 3}.get(tags.get(262))
    return colour_samples is not None and tags.get(277, 1) > colour_samples and tags.get(338, 0) == 0


def oriented(pixels, orientation: int):
    """``pixels`` (H, W[, C]) as viewers show a file of EXIF ``orientation``: its stored rows turned
    and mirrored upright (6: turned 90 degrees clockwise; 8: counter-clockwise; 3: 180 degrees)."""
    import numpy as np  # here: the header readers above need no numpy

    turned = {1: lambda p: p, 2: lambda p: p[:, ::-1], 3: lambda p: p[::-1, ::-1], 4: lambda p: p[::-1],
              5: lambda p: np.swapaxes(p, 0, 1), 6: lambda p: np.rot90(p, -1),
              7: lambda p: np.swapaxes(p[::-1, ::-1], 0, 1), 8: lambda p: np.rot90(p, 1)}[orientation](pixels)
    return np.ascontiguousarray(turned)
