"""shadecut.image_header: an image's size read from its file's header, as the add-on checks it
before Blender decodes the pixels."""

import struct

import numpy as np
import OpenImageIO as oiio
import pytest

from shadecut.image_header import declared_size
from test_errors import png_declaring

WIDTH, HEIGHT = 37, 23


def write(path, channels=3, kind=oiio.UINT8, **attributes):
    spec = oiio.ImageSpec(WIDTH, HEIGHT, channels, kind)
    for name, value in attributes.items():
        spec.attribute(name, value)
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), np.full((HEIGHT, WIDTH, channels), 0.5, np.float32))
    if not buffer.write(str(path)):
        pytest.skip(f"OpenImageIO cannot write {path.suffix} here: {buffer.geterror()}")
    return path


@pytest.mark.parametrize("name, kind", [("a.png", oiio.UINT16), ("a.jpg", oiio.UINT8), ("a.tif", oiio.FLOAT),
                                        ("a.tiff", oiio.UINT16), ("a.exr", oiio.HALF), ("a.hdr", oiio.FLOAT),
                                        ("a.bmp", oiio.UINT8), ("a.tga", oiio.UINT8), ("a.webp", oiio.UINT8)])
def test_the_size_of_every_format_blender_reads(tmp_path, name, kind):
    assert declared_size(write(tmp_path / name, kind=kind)) == (WIDTH, HEIGHT)


def test_an_exr_whose_data_window_is_offset_and_a_big_endian_tiff(tmp_path):
    exr = tmp_path / "offset.exr"
    spec = oiio.ImageSpec(WIDTH, HEIGHT, 1, oiio.FLOAT)
    spec.x, spec.y = -5, 7
    out = oiio.ImageOutput.create(str(exr))
    assert out.open(str(exr), spec) and out.write_image(np.zeros((HEIGHT, WIDTH, 1), np.float32))
    out.close()
    assert declared_size(exr) == (WIDTH, HEIGHT)
    # A big-endian TIFF (OpenImageIO writes little-endian ones): a SHORT width and a LONG height.
    entries = struct.pack(">HHIHH", 256, 3, 1, WIDTH, 0) + struct.pack(">HHII", 257, 4, 1, HEIGHT)
    (tmp_path / "big.tif").write_bytes(b"MM\x00*" + struct.pack(">IH", 8, 2) + entries + bytes(4))
    assert declared_size(tmp_path / "big.tif") == (WIDTH, HEIGHT)


def test_a_header_declaring_a_huge_image_is_read_without_decoding(tmp_path):
    png_declaring(tmp_path / "huge.png", 100000, 100000)
    assert declared_size(tmp_path / "huge.png") == (100000, 100000)


def test_unknown_or_damaged_files_give_none(tmp_path):
    (tmp_path / "notes.png").write_text("not an image")
    cut = write(tmp_path / "cut.jpg")
    cut.write_bytes(cut.read_bytes()[:40])
    (tmp_path / "empty.exr").write_bytes(b"")
    for name in ("notes.png", "cut.jpg", "empty.exr", "missing.tif"):
        assert declared_size(tmp_path / name) is None, name
