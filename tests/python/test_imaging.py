"""The conversions the add-on applies to Blender's pixel buffers, checked without Blender."""

import numpy as np
import pytest

from shadecut import imaging, synthetic


def test_srgb_decoding_matches_the_standard():
    # Reference points of IEC 61966-2-1: the linear segment, its joint, mid grey and white.
    encoded = np.array([0.0, 0.02, 0.04045, 0.5, 1.0])
    expected = np.array([0.0, 0.02 / 12.92, 0.04045 / 12.92, 0.21404114, 1.0])
    np.testing.assert_allclose(imaging.srgb_to_linear(encoded), expected, rtol=1e-5, atol=1e-7)


def test_intensity_is_rec709_luminance_and_alpha_the_mask():
    rgba = np.zeros((2, 3, 4), np.float32)
    rgba[..., 0], rgba[..., 1], rgba[..., 2] = 0.5, 0.25, 1.0
    rgba[..., 3] = [[1, 0.6, 0.4], [1, 1, 0]]
    intensity, mask, has_alpha = imaging.intensity_and_mask(rgba, srgb_encoded=False)
    np.testing.assert_allclose(intensity, 0.2126 * 0.5 + 0.7152 * 0.25 + 0.0722, rtol=1e-6)
    np.testing.assert_array_equal(mask, [[True, True, False], [True, True, False]])
    assert has_alpha


def test_luminance_of_an_array_is_the_cores_intensity_and_grey_stays_grey():
    rng = np.random.default_rng(0)
    rgb = rng.uniform(0.0, 1.0, (5, 7, 3)).astype(np.float32)
    rgba = np.concatenate([rgb, np.ones((5, 7, 1), np.float32)], axis=-1)
    intensity, _, _ = imaging.intensity_and_mask(rgba, srgb_encoded=False)
    np.testing.assert_allclose(imaging.luminance(rgb), intensity, rtol=1e-6)
    grey = rgb[..., 0]
    np.testing.assert_array_equal(imaging.luminance(grey), grey)
    assert imaging.luminance(grey).dtype == np.float64


def test_opaque_image_has_no_mask():
    rgba = np.ones((4, 4, 4), np.float32)
    _, mask, has_alpha = imaging.intensity_and_mask(rgba, srgb_encoded=True)
    assert mask.all() and not has_alpha


def test_downsample_averages_masked_blocks():
    scene = synthetic.sphere(light=(1, 0, 1), size=100)
    small, mask, factor = imaging.downsample(scene.image, scene.mask, 30)
    assert factor == 4 and small.shape == mask.shape == (25, 25)
    block = scene.image[40:44, 48:52]
    assert small[10, 12] == pytest.approx(block.mean(), rel=1e-5)
    assert mask.sum() == pytest.approx(scene.mask.sum() / 16, rel=0.05)


def test_downsample_leaves_small_images_alone():
    image, mask = np.ones((8, 6), np.float32), np.ones((8, 6), bool)
    assert imaging.downsample(image, mask, 0)[2] == 1
    assert imaging.downsample(image, mask, 8)[2] == 1
    with pytest.raises(ValueError, match="fewer than 2 x 2"):
        imaging.downsample(image, mask, 1)


def test_rejects_buffers_without_four_channels():
    with pytest.raises(ValueError, match="RGBA"):
        imaging.intensity_and_mask(np.ones((4, 4, 3)), srgb_encoded=False)
