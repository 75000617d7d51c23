"""shadecut.image_header's checks of a whole file, which the add-on makes because Blender decodes a
damaged image without a word (issue 48): a JPEG or PNG cut short (finding 12)."""

import numpy as np
import OpenImageIO as oiio
import pytest

import shadecut
from shadecut.image_header import cut_short, cut_short_bytes


def noisy(path, channels=3):
    """A noisy image (so that its coded data is long) written by OpenImageIO."""
    pixels = np.random.default_rng(0).random((64, 48, channels)).astype(np.float32)
    buffer = oiio.ImageBuf(oiio.ImageSpec(48, 64, channels, oiio.UINT8))
    buffer.set_pixels(oiio.ROI(), pixels)
    assert buffer.write(str(path)), buffer.geterror()
    return path


@pytest.mark.parametrize("name", ["a.jpg", "a.png"])
def test_a_file_cut_in_half_is_cut_short_and_a_whole_one_is_not(tmp_path, name):
    whole = noisy(tmp_path / name)
    data = whole.read_bytes()
    half = tmp_path / f"half_{name}"
    half.write_bytes(data[: len(data) // 2])
    assert not cut_short(whole) and not cut_short_bytes(data)
    assert cut_short(half) and cut_short_bytes(data[: len(data) // 2])
    with pytest.raises(OSError):  # the library's reader agrees
        shadecut.load_image(half)


def test_data_after_the_end_of_a_jpeg_is_not_a_cut(tmp_path):
    """Phones append a video or a second image after the JPEG's end (motion photos): still whole."""
    path = noisy(tmp_path / "motion.jpg")
    path.write_bytes(path.read_bytes() + b"\x00\x00\x00\x18ftypmp42" + bytes(5000))
    assert not cut_short(path)


@pytest.mark.parametrize("content", [b"", b"not an image", b"\xff\xd8"])
def test_other_files_are_left_to_the_decoder(tmp_path, content):
    path = tmp_path / "x.jpg"
    path.write_bytes(content)
    assert cut_short(path) == (content == b"\xff\xd8")
    assert not cut_short(tmp_path / "missing.jpg")


def test_a_named_pipe_is_not_opened(tmp_path):
    import os

    os.mkfifo(tmp_path / "pipe.jpg")
    assert not cut_short(tmp_path / "pipe.jpg")  # returns at once: a reader would wait for a writer
