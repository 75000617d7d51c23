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


def stored_with(path, pixels, orientation):
    """Writes ``pixels`` as stored rows with the file declaring EXIF ``orientation``."""
    height, width, channels = pixels.shape
    spec = oiio.ImageSpec(width, height, channels, oiio.UINT8)
    spec.attribute("Orientation", orientation)
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), pixels)
    assert buffer.write(str(path)), buffer.geterror()
    return path


def upright_by_pillow(path):
    """The reference: Pillow's reading of the EXIF rule (OpenImageIO 2.4's ImageBufAlgo.reorient swaps
    orientations 5 and 7 against it: 5 puts the stored top-left pixel at the bottom right, where the
    rule's "row 0 is the left side, column 0 the top" puts it at the top left)."""
    from PIL import Image, ImageOps

    with Image.open(path) as image:
        return np.asarray(ImageOps.exif_transpose(image), dtype=np.float32) / 255


@pytest.mark.parametrize("orientation", range(1, 9))
def test_exif_orientation_is_read_and_applied_as_the_rule_says(tmp_path, orientation):
    """Issue 48, finding 9: a phone's portrait is stored sideways with orientation 6."""
    from shadecut.dataset import read_image_channels
    from shadecut.image_header import exif_orientation_bytes, oriented

    stored = np.random.default_rng(orientation).random((5, 8, 3)).astype(np.float32)
    for name in ("a.jpg", "a.tif"):
        path = stored_with(tmp_path / name, stored, orientation)
        assert exif_orientation_bytes(path.read_bytes()) == orientation
    jpeg = tmp_path / "a.jpg"  # Pillow turns a JPEG by the rule (a TIFF it hands to libtiff, which differs)
    reference = upright_by_pillow(jpeg)
    raw = oiio.ImageInput.open(str(jpeg))
    decoded = raw.read_image(oiio.FLOAT)
    raw.close()
    assert reference.shape == (oriented(decoded, orientation).shape)
    np.testing.assert_allclose(oriented(decoded, orientation), reference, atol=2 / 255)  # two decoders
    np.testing.assert_allclose(read_image_channels(jpeg)[0], reference, atol=2 / 255)


def test_a_file_without_orientation_is_upright():
    from shadecut.image_header import exif_orientation_bytes

    assert exif_orientation_bytes(b"\xff\xd8\xff\xdb\x00\x04\x00\x00") == 1
    assert exif_orientation_bytes(b"\x89PNG\r\n\x1a\n") == 1
    assert exif_orientation_bytes(b"II*\x00\xff\xff\xff\x7f") == 1  # a directory past the end


def pages(path, count):
    """A file of ``count`` grey pages or frames (50, 100, ...), written by Pillow."""
    from PIL import Image

    images = [Image.fromarray(np.full((4, 6), 50 * (index + 1), np.uint8)) for index in range(count)]
    images[0].save(path, save_all=True, append_images=images[1:])
    return path


@pytest.mark.parametrize("name", ["pages.tif", "frames.gif"])
def test_a_file_of_several_images_is_refused_not_read_as_its_first(tmp_path, name):
    """Issue 48, finding 14: a multi-page TIFF or an animated GIF silently read its first page."""
    from shadecut.dataset import read_image_channels
    from shadecut.image_header import tiff_pages

    path = pages(tmp_path / name, 2)
    with pytest.raises(OSError, match="it holds several images"):
        read_image_channels(path)
    if name.endswith(".tif"):
        assert tiff_pages(path.read_bytes()) == 2
        assert tiff_pages(pages(tmp_path / "one.tif", 1).read_bytes()) == 1


@pytest.mark.parametrize("names, alpha, undeclared", [(("R", "G"), None, True), (("Y", "A"), 1, False),
                                                      (("R", "G", "B"), None, False), (("R", "G", "B", "X"), None, True),
                                                      (("R", "G", "B", "A"), 3, False)])
def test_a_tiff_sample_beyond_its_colour_is_an_alpha_only_when_declared(tmp_path, names, alpha, undeclared):
    """Issue 48, finding 14: Blender 4.3 and 5.2 read an undeclared second channel as the alpha."""
    from shadecut.image_header import tiff_extra_sample_undeclared

    spec = oiio.ImageSpec(4, 3, len(names), oiio.UINT8)
    spec.channelnames = names
    spec.alpha_channel = -1 if alpha is None else alpha  # OpenImageIO takes a 4th channel for alpha unless told
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), np.full((3, 4, len(names)), 0.5, np.float32))
    assert buffer.write(str(tmp_path / "a.tif"))
    assert tiff_extra_sample_undeclared((tmp_path / "a.tif").read_bytes()) == undeclared
    assert not tiff_extra_sample_undeclared(noisy(tmp_path / "a.png").read_bytes())


@pytest.mark.parametrize("names", [("foo", "bar"), ("Y", "A"), ("R", "G", "B", "A"), ("layer.R", "layer.G", "layer.B")])
def test_the_channel_names_of_an_exr_are_read_from_its_header(tmp_path, names):
    from shadecut.image_header import exr_channel_names, mapped

    spec = oiio.ImageSpec(4, 3, len(names), oiio.FLOAT)
    spec.channelnames = names
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), np.full((3, 4, len(names)), 0.5, np.float32))
    assert buffer.write(str(tmp_path / "a.exr"))
    assert sorted(exr_channel_names((tmp_path / "a.exr").read_bytes())) == sorted(names)
    with mapped(tmp_path / "a.exr") as data:  # as the add-on reads it: a mapped file, not bytes
        assert sorted(exr_channel_names(data)) == sorted(names)
    assert exr_channel_names(noisy(tmp_path / "a.png").read_bytes()) is None


@pytest.mark.parametrize("orientation", range(1, 9))
def test_load_image_turns_a_file_upright_by_its_exif_orientation(tmp_path, orientation):
    """Issue 48, finding 9, in the library's reader (the CLI and load_image): as the add-on does."""
    from shadecut.image_header import oriented

    stored = np.random.default_rng(orientation).random((5, 8, 3)).astype(np.float32)
    path = stored_with(tmp_path / "a.tif", stored, orientation)
    raw = oiio.ImageInput.open(str(path))
    decoded = raw.read_image(oiio.FLOAT)
    raw.close()
    loaded = shadecut.load_image(path, color_space="linear")
    np.testing.assert_allclose(loaded.colour, oriented(decoded, orientation), atol=1e-6)


def test_load_image_takes_only_a_declared_alpha_and_channels_that_are_a_photograph(tmp_path):
    """Issue 48, finding 14, in the library's reader: an undeclared second channel was the mask, a file
    of several pages was read as its first, an EXR of channels foo, bar as a grey photograph."""
    two = np.random.default_rng(0).random((6, 7, 2)).astype(np.float32)
    spec = oiio.ImageSpec(7, 6, 2, oiio.FLOAT)
    spec.channelnames = ("R", "G")
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), two)
    assert buffer.write(str(tmp_path / "rg.tif"))
    assert not shadecut.load_image(tmp_path / "rg.tif").has_alpha
    spec.channelnames = ("foo", "bar")
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), two)
    assert buffer.write(str(tmp_path / "foo.exr"))
    with pytest.raises(OSError, match="none of its channels is named as colour or grey"):
        shadecut.load_image(tmp_path / "foo.exr")
    pages = oiio.ImageOutput.create(str(tmp_path / "pages.tif"))
    page = oiio.ImageSpec(7, 6, 1, oiio.FLOAT)
    assert pages.open(str(tmp_path / "pages.tif"), [page, page])
    pages.write_image(two[..., 0].copy())
    pages.open(str(tmp_path / "pages.tif"), page, "AppendSubimage")
    pages.write_image(two[..., 1].copy())
    pages.close()
    with pytest.raises(OSError, match="holds several images"):
        shadecut.load_image(tmp_path / "pages.tif")
