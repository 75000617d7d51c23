"""scene="relief": a surface that fills the frame and on average faces the viewer (a brick wall)."""

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

# Oblique lights from three sides; none is used by the parameter tuning.
LIGHTS = [(0.6, 0.3, 1.0), (-0.5, 0.7, 1.0), (1.0, -0.2, 0.8)]


def plane_slope(depth: np.ndarray) -> float:
    """The gradient magnitude (pixels of depth per pixel) of the depth's least-squares plane."""
    rows, cols = np.mgrid[0:depth.shape[0], 0:depth.shape[1]]
    basis = np.column_stack([cols.ravel(), -rows.ravel(), np.ones(depth.size)])
    a, b, _ = np.linalg.lstsq(basis, depth.ravel().astype(float), rcond=None)[0]
    return float(np.hypot(a, b))


def pentland(image: np.ndarray, light, albedo: float) -> np.ndarray:
    """Pentland's linear shape from shading, the classic for shallow reliefs, as he solved it: the
    first-order solve alone, with next to no weight on the slope across the light."""
    return shadecut.reconstruct(image, light, None, albedo, scene="relief", method="pentland", smoothness=1e-4,
                                iterations=1).depth


def correlation(a, b) -> float:
    return float(np.corrcoef(np.ravel(a), np.ravel(b))[0, 1])


@pytest.fixture(scope="module")
def walls():
    measured = []
    for light in LIGHTS:
        wall = synthetic.bricks(light)
        result = shadecut.reconstruct(wall.image, light, scene="relief")
        reference = correlation(pentland(wall.image, light, wall.albedo), wall.depth)
        measured.append((light, wall, result, reference))
        print(f"bricks under {light}: albedo {result.albedo:.3f} (true mean {wall.albedo}), slope "
              f"{plane_slope(result.depth):.5f}, range {np.ptp(result.depth):.2f} (true {np.ptp(wall.depth):.2f}), "
              f"correlation {correlation(result.depth, wall.depth):.3f} (Pentland {reference:.3f})")
    return measured


def test_a_relief_sits_flat_and_beats_pentland(walls):
    for light, wall, result, reference in walls:
        assert plane_slope(result.depth) <= 0.01, light
        assert result.albedo == pytest.approx(wall.albedo, rel=0.05), light  # the median pixel faces the viewer
        assert correlation(result.depth, wall.depth) > reference, light


@pytest.mark.xfail(strict=True, reason="measured: range 8.39 / 4.89 / 12.49 px against 4 true, correlation "
                                        "0.53 / 0.76 / 0.56: graphcut's normals are 21-35 deg off on the bevels")
def test_a_relief_keeps_its_height_and_shape(walls):
    for light, wall, result, _ in walls:
        assert np.ptp(result.depth) <= 2 * np.ptp(wall.depth), light
        assert correlation(result.depth, wall.depth) >= 0.7, light


def test_a_reliefs_normals_are_its_depths():
    # What the mesh shows: the labelling's own normals carry convex/concave creases on flat ground,
    # which the integration smooths away (test_grid.py measures what that did to the block grid).
    for light in LIGHTS:
        scene = synthetic.bumps(light, 128)
        relief = shadecut.reconstruct(scene.image, light, scene="relief")
        whole = np.ones(scene.image.shape, bool)
        np.testing.assert_allclose(relief.normals, shadecut.normals_from_depth(relief.depth, whole), atol=1e-6)


def test_an_object_scene_keeps_the_ramp_that_a_relief_removes():
    wall = synthetic.bricks(LIGHTS[0], size=96)
    as_object = shadecut.reconstruct(wall.image, LIGHTS[0], scene="object")
    assert plane_slope(as_object.depth) > 0.01
    with pytest.raises(ValueError, match="scene kind"):
        shadecut.reconstruct(wall.image, LIGHTS[0], scene="landscape")


def test_seamless_output_tiles_and_is_refused_where_it_cannot():
    wall = synthetic.bricks((0.6, 0.3, 1.0), size=128)
    result = shadecut.reconstruct(wall.image, light=wall.light, scene="relief", seamless=True)
    z = result.depth
    seam = max(np.abs(z[:, 0] - z[:, -1]).max(), np.abs(z[0] - z[-1]).max())
    inner = max(np.abs(np.diff(z, axis=1)).max(), np.abs(np.diff(z, axis=0)).max())
    assert seam <= inner
    with pytest.raises(ValueError, match="seamless output is for reliefs"):
        shadecut.reconstruct(wall.image, light=wall.light, seamless=True)
    with pytest.raises(ValueError, match="seamless output tiles the whole image"):
        shadecut.reconstruct(wall.image, light=wall.light, mask=np.tri(128, dtype=bool), scene="relief", seamless=True)


def slant_degrees(light) -> float:
    light = np.asarray(light, float)
    return float(np.degrees(np.arccos(light[2] / np.linalg.norm(light))))


def tilt_axis_error(estimate, truth) -> float:
    """Degrees between the lights' tilt axes (directions in the image plane modulo 180)."""
    difference = np.degrees(np.arctan2(estimate[1], estimate[0]) - np.arctan2(truth[1], truth[0])) % 180
    return float(min(difference, 180 - difference))


def test_without_a_light_a_relief_gets_the_relief_estimator_and_sits_flat():
    """The sphere estimators read a wall as lit from the front, which makes its relief several times
    too deep; the relief estimator finds the slant from the wall's median and brightest pixels."""
    for light in LIGHTS:
        wall = synthetic.bricks(light, size=128)
        relief_light, _ = shadecut.estimate_light(wall.image, scene="relief")
        sphere_light, _ = shadecut.estimate_light(wall.image, method="zheng_chellappa")
        # Paint lines off: with them, every stage (the light too) reads the lines as shadow.
        result = shadecut.reconstruct(wall.image, scene="relief", paint_line_width=0)
        print(f"bricks under {light}: slant {slant_degrees(light):.1f} true, relief estimator "
              f"{slant_degrees(relief_light):.1f} (tilt axis {tilt_axis_error(relief_light, light):.1f} off), "
              f"zheng_chellappa {slant_degrees(sphere_light):.1f}; "
              f"range {np.ptp(result.depth):.2f} px (true {np.ptp(wall.depth):.2f})")
        np.testing.assert_allclose(result.light, relief_light, atol=1e-9)
        assert relief_light[1] >= 0  # the light from above: a relief and its inverse look alike
        relief_error = abs(slant_degrees(relief_light) - slant_degrees(light))
        assert relief_error <= 5, light  # measured 1.4, 2.0, 2.4
        assert relief_error < abs(slant_degrees(sphere_light) - slant_degrees(light)) - 10, light  # 22.8, 12.3, 36.6
        assert plane_slope(result.depth) <= 0.01, light
