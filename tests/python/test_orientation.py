"""Issue 27: right side out. Under a light near the viewer the image cannot tell a surface from its
inversion (z -> -z); the outline decides for an object, the result does not flip as the light nears
the viewer, and the stats say when the image could not choose. Measured on synthetic surfaces with
exact ground truth (none of them the training surfaces' under their lights).

A result is *inverted* when its normals are further from the truth than the same normals with
(nx, ny) negated, the inversion's."""

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

from pathlib import Path

MOZART = Path(__file__).resolve().parents[2] / "data" / "mozart" / "moz256.depth"
SLANTS = (0, 2, 5, 10)
TILTS = tuple(range(0, 360, 45))


def light(slant: float, tilt: float) -> tuple:
    s, t = np.radians(slant), np.radians(tilt)
    return (np.sin(s) * np.cos(t), np.sin(s) * np.sin(t), np.cos(s))


def inverted(normals: np.ndarray) -> np.ndarray:
    return normals * np.array([-1.0, -1.0, 1.0], np.float32)


def errors(truth, given: bool, **options) -> tuple[float, float, shadecut.Reconstruction]:
    """(error, error of the inversion, result) of graphcut with the defaults, the light given or not."""
    result = shadecut.reconstruct(truth.image, truth.light if given else None, truth.mask, **options)
    return truth.mean_error(result.normals), truth.mean_error(inverted(result.normals)), result


SHAPES = {
    "sphere": lambda l: synthetic.sphere(l, 96),
    "torus": lambda l: synthetic.torus(l, 96),
    # The bust at its own resolution (256 px): the figures are there.
    "mozart": lambda l: synthetic.mozart(MOZART, l),
}


@pytest.mark.parametrize("given", [True, False], ids=["light given", "light estimated"])
@pytest.mark.parametrize("shape", SHAPES)
def test_no_object_comes_back_inverted_near_the_viewer(shape, given):
    worst = []
    for slant in SLANTS:
        for tilt in TILTS if slant else (0,):
            scene = SHAPES[shape](light(slant, tilt))
            error, flipped, _ = errors(scene, given)
            worst.append((error - flipped, slant, tilt, error, flipped))
    print(f"{shape}, light {'given' if given else 'estimated'}: error - inverted's error at most "
          f"{max(worst)[0]:.1f} deg (slant {max(worst)[1]}, tilt {max(worst)[2]}: {max(worst)[3]:.1f} against "
          f"{max(worst)[4]:.1f}); errors {min(w[3] for w in worst):.1f}-{max(w[3] for w in worst):.1f} deg")
    assert max(worst)[0] < 0


@pytest.mark.parametrize("given, bound", [(True, 3.0), (False, 6.0)], ids=["light given", "light estimated"])
def test_the_sphere_near_the_viewer(given, bound):
    measured = [errors(SHAPES["sphere"](light(slant, tilt)), given)[0]
                for slant in SLANTS for tilt in (TILTS if slant else (0,))]
    print(f"sphere, light {'given' if given else 'estimated'}: at most {max(measured):.2f} deg")
    assert max(measured) <= bound


@pytest.mark.parametrize("given", [True, False], ids=["light given", "light estimated"])
def test_mozart_near_the_viewer_is_as_good_as_at_twenty_degrees(given):
    ratios = []
    for tilt in TILTS:
        reference = errors(SHAPES["mozart"](light(20, tilt)), given)[0]
        for slant in SLANTS:
            ratios.append((errors(SHAPES["mozart"](light(slant, tilt)), given)[0] / reference, slant, tilt))
    print(f"Mozart, light {'given' if given else 'estimated'}: error / error at slant 20 at most "
          f"{max(ratios)[0]:.2f} (slant {max(ratios)[1]}, tilt {max(ratios)[2]})")
    assert max(ratios)[0] <= 1.3


@pytest.mark.parametrize("shape", ["sphere", "mozart"])
def test_nothing_flips_as_the_light_nears_the_viewer(shape):
    """Slant 0, 1 and 3 degrees (same tilt): the results agree with one another far better than with
    one another's inversion."""
    for tilt in (0, 135, 270):
        results = [errors(SHAPES[shape](light(slant, tilt)), True)[2] for slant in (0, 1, 3)]
        inner = shadecut.erode_mask(results[0].mask, 2)
        for other in results[1:]:
            apart = shadecut.angular_error(results[0].normals, other.normals, inner)
            flipped = shadecut.angular_error(results[0].normals, inverted(other.normals), inner)
            assert apart < 0.5 * flipped, (tilt, apart, flipped)


def test_a_bowl_stays_a_bowl_where_the_light_tells():
    for slant in (25, 45):
        for tilt in TILTS:
            bowl = synthetic.sphere(light(slant, tilt), 96, bowl=True)
            error, flipped, result = errors(bowl, True)
            assert error < 5.0 and not result.stats.orientation_ambiguous, (slant, tilt, error, flipped)


def test_near_the_viewer_a_bowl_is_read_as_a_dome_and_said_to_be_ambiguous():
    """The outline's choice (docs/method.md): under lights nearer the viewer than kRimSlant (20
    degrees) a bowl seen from above reads as a dome; the stats say the image could not tell, and
    flip gives the bowl."""
    for slant in (0, 2, 5, 10):
        bowl = synthetic.sphere(light(slant, 60), 96, bowl=True)
        error, flipped, result = errors(bowl, True)
        assert flipped < error and result.stats.orientation_ambiguous, (slant, error, flipped)
        _, normals = shadecut.flip(result.depth, result.normals, result.mask)
        assert bowl.mean_error(normals) == pytest.approx(flipped, abs=1e-3)


def test_the_stats_say_how_much_the_orientation_beats_its_inversion():
    frontal = synthetic.sphere((0.0, 0.0, 1.0), 96)
    result = shadecut.reconstruct(frontal.image, frontal.light, frontal.mask)
    stats = result.stats
    # The outline prefers the dome; the image cannot: both render alike.
    assert stats.inverted_energy > stats.orientation_energy > 0
    assert stats.inverted_residual == pytest.approx(stats.orientation_residual, rel=0.05)
    assert stats.orientation_ambiguous
    oblique = synthetic.sphere(light(10, 45), 96)
    stats = shadecut.reconstruct(oblique.image, oblique.light, oblique.mask).stats
    assert stats.inverted_residual > shadecut.AMBIGUOUS_RESIDUAL_RATIO * stats.orientation_residual
    assert not stats.orientation_ambiguous
    upwind = shadecut.reconstruct(oblique.image, oblique.light, oblique.mask, method="upwind").stats
    assert upwind.orientation_energy == 0 and upwind.inverted_residual > upwind.orientation_residual > 0


def test_the_orientation_is_judged_before_the_fit():
    """fit_shading refines the surface, not its inversion: judged after the fit, a frontal sphere's dome
    rendered 1.7 times closer than its bowl, which the image cannot tell apart. Judged before it, the
    stats are those of the same call without the fit."""
    for scene in (synthetic.sphere((0.0, 0.0, 1.0), 96), synthetic.sphere(light(10, 45), 96)):
        plain = shadecut.reconstruct(scene.image, scene.light, scene.mask).stats
        fitted = shadecut.reconstruct(scene.image, scene.light, scene.mask, fit_shading=True).stats
        assert fitted.fit_steps > 0
        assert (fitted.orientation_residual, fitted.inverted_residual, fitted.orientation_ambiguous) == (
            plain.orientation_residual, plain.inverted_residual, plain.orientation_ambiguous)


def test_flip_inverts_depth_and_normals_and_keeps_each_part_at_zero():
    mask = np.zeros((20, 30), bool)
    mask[2:9, 2:12] = True
    mask[11:18, 15:28] = True
    rows, cols = np.mgrid[0:20, 0:30].astype(np.float32)
    depth = np.where(mask, 0.1 * rows + 0.3 * cols + np.where(cols > 14, 5.0, 0.0), 0).astype(np.float32)
    normals = shadecut.normals_from_depth(depth, mask)
    flipped_depth, flipped_normals = shadecut.flip(depth, normals, mask)
    labels, count = shadecut.mask_components(mask)
    for part in range(count):
        inside = labels == part
        assert flipped_depth[inside].min() == pytest.approx(0.0)
        np.testing.assert_allclose(flipped_depth[inside], depth[inside].max() - depth[inside], atol=1e-5)
    np.testing.assert_array_equal(flipped_normals[..., :2], -normals[..., :2])
    np.testing.assert_array_equal(flipped_normals[..., 2], normals[..., 2])
    np.testing.assert_allclose(shadecut.normals_from_depth(flipped_depth, mask), flipped_normals, atol=1e-6)
    again_depth, again_normals = shadecut.flip(flipped_depth, flipped_normals, mask)
    for part in range(count):
        inside = labels == part
        np.testing.assert_allclose(again_depth[inside], depth[inside] - depth[inside].min(), atol=1e-5)
    np.testing.assert_array_equal(again_normals, normals)
    with pytest.raises(ValueError):
        shadecut.flip(depth, normals[:10], mask)


def test_the_contour_light_estimator_near_the_viewer():
    """light_method='contour' (not the default: docs/comparison_methods.md): never exactly frontal by
    indecision, within a degree on the sphere and the torus at slants up to 10 degrees, its
    uncertainty reported."""
    for shape in ("sphere", "torus"):
        for slant in (2, 5, 10):
            for tilt in (30, 200):
                scene = SHAPES[shape](light(slant, tilt))
                result = shadecut.reconstruct(scene.image, None, scene.mask, light_method="contour")
                truth = np.asarray(scene.light) / np.linalg.norm(scene.light)
                off = np.degrees(np.arccos(np.clip(result.light @ truth, -1, 1)))
                assert off < 1.0 and result.light[2] < 1.0, (shape, slant, tilt, off)
                assert 0 < result.stats.light_uncertainty < 5.0
    given = shadecut.reconstruct(scene.image, scene.light, scene.mask)
    assert np.isnan(given.stats.light_uncertainty)
    relief = synthetic.bumps(light(10, 30), 64)  # no outline: zheng_chellappa's estimate, no uncertainty
    result = shadecut.reconstruct(relief.image, None, light_method="contour")
    assert np.isnan(result.stats.light_uncertainty)
    np.testing.assert_allclose(result.light, shadecut.estimate_light(relief.image, method="zheng_chellappa")[0])


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Measured (128 px, light given): a bump field near the viewer is a coin toss per bump: under a "
    "frontal light every bump and dent can be inverted alone and the image stays the same, and a relief "
    "has no outline to decide; errors 19.4-25.7 deg against 21.9-27.7 for the inversions, 4 of 25 "
    "inverted: slant 5 tilt 180 (25.7 against 25.6), slant 10 tilts 45, 135, 180 (23.2 against 22.8, "
    "25.3 against 22.1, 22.0 against 21.9)"))
def test_no_relief_comes_back_inverted_with_the_light_given():
    measured = []
    for slant in SLANTS:
        for tilt in TILTS if slant else (0,):
            scene = synthetic.bumps(light(slant, tilt), 128)
            error, flipped, _ = errors(scene, True, scene="relief")
            measured.append((error - flipped, slant, tilt, error, flipped))
    inverted_ones = [m for m in measured if m[0] >= 0]
    print(f"bumps, light given: errors {min(m[3] for m in measured):.1f}-{max(m[3] for m in measured):.1f} deg, "
          f"inversions {min(m[4] for m in measured):.1f}-{max(m[4] for m in measured):.1f}; inverted: "
          + ", ".join(f"slant {m[1]} tilt {m[2]} ({m[3]:.1f} against {m[4]:.1f})" for m in inverted_ones))
    assert not inverted_ones


def test_a_relief_without_a_light_keeps_its_rule():
    """Estimated, a relief's light comes from above (S_y >= 0): its inversion lit from below is the
    same image (docs/method.md, "Scenes")."""
    for tilt in TILTS:
        scene = synthetic.bumps(light(10, tilt), 96)
        result = shadecut.reconstruct(scene.image, None, scene="relief")
        assert result.light[1] >= 0
