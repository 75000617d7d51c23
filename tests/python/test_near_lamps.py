"""Several photographs under lamps near the subject (option ``light_distance``): the light's direction
and strength change across the frame (docs/method.md, "Near lamps"). The photographs are rendered by
shadecut.synthetic.lit_by_lamps, apart from the reading; tests/cpp/photometric writes the physics out
a third time."""

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

# Four lights 40 degrees from the viewer, from the top, the left, the bottom and the right.
AROUND = np.array([[0.0, 0.64, 0.77], [-0.64, 0.0, 0.77], [0.0, -0.64, 0.77], [0.64, 0.0, 0.77]])


def regions(mask):
    rows, cols = mask.shape
    corner, centre = np.zeros_like(mask), np.zeros_like(mask)
    corner[: rows // 4, : cols // 4] = corner[-rows // 4 :, -cols // 4 :] = True
    centre[3 * rows // 8 : 5 * rows // 8, 3 * cols // 8 : 5 * cols // 8] = True
    return corner & mask, centre & mask


def errors(scene, normals, where):
    return np.degrees(np.arccos(np.clip((normals * scene.normals).sum(-1), -1.0, 1.0)))[where].mean()


def test_lamps_one_frame_width_away_give_the_corners_as_accurately_as_the_centre():
    scene = synthetic.bumps((0, 0, 1), size=128)
    photographs = synthetic.lit_by_lamps(scene, AROUND, 1.0)
    corner, centre = regions(scene.mask)
    near = shadecut.reconstruct(photographs, AROUND, scene.mask, light_distance=1.0)
    read_as_distant = shadecut.reconstruct(photographs, AROUND, scene.mask)
    assert errors(scene, near.normals, corner) < 0.1 and errors(scene, near.normals, centre) < 0.1
    assert errors(scene, read_as_distant.normals, corner) > 10.0  # what the option is for
    np.testing.assert_allclose(near.albedo_map[scene.mask].mean(), 1.0, atol=0.01)
    assert np.median(near.residual[scene.mask]) < 1e-3


def test_a_sphere_and_painted_colour_under_eight_lamps():
    scene = synthetic.sphere((0, 0, 1), size=128, radius_fraction=0.45)
    tilts = np.radians(np.arange(8) * 45.0 + 90.0)
    lights = np.stack([0.64 * np.cos(tilts), 0.64 * np.sin(tilts), np.full(8, 0.77)], axis=-1)
    paint = np.array([0.9, 0.6, 0.3], np.float32)
    photographs = [grey[..., None] * paint for grey in synthetic.lit_by_lamps(scene, lights, 2.0)]
    result = shadecut.reconstruct(photographs, lights, scene.mask, light_distance=2.0)
    assert scene.mean_error(result.normals) < 0.5
    inside = shadecut.erode_mask(scene.mask, 4)
    np.testing.assert_allclose(np.median(result.albedo_colour[inside], axis=0), paint, atol=0.01)


def test_distant_lights_are_read_as_before():
    scene = synthetic.bumps((0, 0, 1), size=64)
    photographs = [shadecut.render(scene.normals, light, 0.8, scene.mask) for light in AROUND]
    default = shadecut.reconstruct(photographs, AROUND, scene.mask)
    zero = shadecut.reconstruct(photographs, AROUND, scene.mask, light_distance=0.0)
    np.testing.assert_array_equal(default.normals, zero.normals)


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda images: shadecut.reconstruct(images[0], AROUND[0], light_distance=1.0), "one photograph"),
        (lambda images: shadecut.reconstruct(images, None, light_distance=1.0), "give their lights"),
        (lambda images: shadecut.reconstruct(images, AROUND, light_distance=-1.0), "light_distance"),
        (lambda images: shadecut.reconstruct(images, AROUND, light_distance=float("inf")), "light_distance"),
    ],
)
def test_near_lamps_refuse_what_they_cannot_read(call, words):
    scene = synthetic.bumps((0, 0, 1), size=32)
    with pytest.raises(ValueError, match=words):
        call(synthetic.lit_by_lamps(scene, AROUND, 1.0))
