"""Objects without alpha: cut out of a plain background (issue 29, item 5), measured against the truth."""

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

LIGHT = (0.3, 0.4, 0.866)


def iou(a, b):
    return float(np.logical_and(a, b).sum() / max(1, np.logical_or(a, b).sum()))


def sphere_on_white(size=256, albedo=0.8):
    scene = synthetic.sphere(LIGHT, size=size, albedo=albedo)
    return scene, np.where(scene.mask, scene.image, 1.0).astype(np.float32)


def test_rendered_sphere_on_white_is_cut_out_and_reconstructed_as_with_its_true_mask():
    scene, image = sphere_on_white()
    cut = shadecut.cut_out(image)
    assert cut.found, cut.message
    assert iou(cut.mask, scene.mask) >= 0.97
    auto = shadecut.reconstruct(image, LIGHT)  # scene="object", no mask: cut out by default
    assert auto.stats.cut_out == shadecut.CutOutOutcome.found
    assert iou(auto.mask, scene.mask) >= 0.97
    assert not auto.mask[0].any() and not auto.mask[:, 0].any()  # the background is not a surface
    truth = shadecut.reconstruct(scene.image, LIGHT, scene.mask)
    both = np.logical_and(auto.mask, scene.mask)
    error_cut = shadecut.angular_error(auto.normals, scene.normals, shadecut.erode_mask(both, 3))
    error_true = shadecut.angular_error(truth.normals, scene.normals, shadecut.erode_mask(both, 3))
    assert error_cut <= error_true + 1.0, (error_cut, error_true)


def test_the_whole_frame_is_kept_when_asked_or_when_no_object_is_found():
    scene, image = sphere_on_white(size=96)
    assert shadecut.reconstruct(image, LIGHT, cut_out=False).mask.all()
    assert shadecut.reconstruct(image, LIGHT, scene="relief").stats.cut_out == shadecut.CutOutOutcome.not_tried
    given = shadecut.reconstruct(image, LIGHT, scene.mask)
    assert given.stats.cut_out == shadecut.CutOutOutcome.not_tried
    white = shadecut.reconstruct(np.ones((40, 40), np.float32), LIGHT)
    assert white.stats.cut_out == shadecut.CutOutOutcome.no_object and white.mask.all()
    assert "nothing" in white.stats.cut_out_message


def test_colour_object_on_a_graded_background():
    scene = synthetic.sphere(LIGHT, size=160, albedo=0.6)
    rows = np.linspace(0.3, 0.7, 160, dtype=np.float32)[:, None, None]
    background = rows * np.array([0.6, 0.7, 1.0], np.float32) + np.zeros((1, 160, 1), np.float32)
    object_colour = scene.image[..., None] * np.array([1.0, 0.5, 0.3], np.float32)
    image = np.where(scene.mask[..., None], object_colour, background)
    cut = shadecut.cut_out(image)
    assert cut.found, cut.message
    assert iou(cut.mask, scene.mask) >= 0.95


@pytest.mark.parametrize("image", [np.ones((64, 64), np.float32), np.full((2, 2), 0.5, np.float32),
                                   np.zeros((30, 30), np.float32)])
def test_plain_images_have_no_object(image):
    cut = shadecut.cut_out(image)
    assert cut.outcome == shadecut.CutOutOutcome.no_object and not cut.mask.any()


def test_texture_has_no_plain_background():
    rng = np.random.default_rng(1)
    cut = shadecut.cut_out(rng.uniform(0.2, 0.9, (120, 120)).astype(np.float32))
    assert cut.outcome == shadecut.CutOutOutcome.busy_border and "relief" in cut.message


def test_bad_input_and_options():
    with pytest.raises(ValueError):
        shadecut.cut_out(np.full((8, 8), np.nan, np.float32))
    with pytest.raises(ValueError):
        shadecut.cut_out(np.ones((8, 8, 2), np.float32))
    with pytest.raises(ValueError):
        shadecut.cut_out(np.ones((8, 8), np.float32), border=0.9)
    with pytest.raises(TypeError):
        shadecut.cut_out(np.ones((8, 8), np.float32), no_such_option=1)
    assert shadecut.CutOutOptions().smoothness == 50.0  # GrabCut's gamma, held in C++


def skimage_data():
    return pytest.importorskip("skimage.data", reason="python3-skimage (scripts/install_dependencies.sh) is absent: "
                               "the real photographs are its CC0 images")


def linear(photo):
    return shadecut.api._core.srgb_to_linear(photo.astype(np.float64) / 255.0).astype(np.float32)


def test_real_photo_of_an_object_on_black_is_cut_out():
    # skimage's retina (a fundus photograph, CC0): a lit disc on a plain black background, a JPEG
    # without alpha. Its truth: the pixels whose red is well above the black, holes filled (a
    # threshold that only this photo's strong contrast allows).
    photo = skimage_data().retina()[::2, ::2]
    image = linear(photo)
    from scipy import ndimage
    truth = ndimage.binary_fill_holes(photo[..., 0] > 40)
    cut = shadecut.cut_out(image)
    assert cut.found, cut.message
    assert iou(cut.mask, truth) >= 0.97
    result = shadecut.reconstruct(image[::2, ::2])  # the disc reaches the top and bottom edges; the corners are black
    assert result.stats.cut_out == shadecut.CutOutOutcome.found
    assert iou(result.mask, truth[::2, ::2]) >= 0.97
    assert not result.mask[:20, :20].any() and not result.mask[-20:, -20:].any()


def test_real_photo_on_a_wooden_table_has_no_plain_background():
    # skimage's coffee: a cup on a grained wooden table that runs round the whole border.
    cut = shadecut.cut_out(linear(skimage_data().coffee()))
    assert cut.outcome == shadecut.CutOutOutcome.busy_border, cut.message


def test_a_long_cut_out_reports_its_rounds_and_stops_when_told():
    """cut_out(iterations=10**6) could not be stopped: it had no progress and ignored Ctrl+C (issue 48, 7)."""
    sphere = synthetic.sphere((0.3, 0.4, 0.866), size=64, albedo=0.8)
    photo = np.where(sphere.mask, sphere.image, 1.0)
    seen = []

    def stop_after_three(fraction, stage):
        seen.append((fraction, stage))
        return len(seen) < 3

    with pytest.raises(shadecut.Cancelled):
        shadecut.cut_out(photo, iterations=10**6, progress=stop_after_three)
    assert len(seen) == 3 and {stage for _, stage in seen} == {"cut_out"}
    assert [fraction for fraction, _ in seen] == sorted(fraction for fraction, _ in seen)
