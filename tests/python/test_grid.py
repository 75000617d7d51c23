"""Issue 29, "no grid in the output": the normal maps of reliefs and objects carry no steps on the block
grid of coarse to fine (rows and columns at multiples of 8-64 px), measured by
shadecut.evaluation.grid_step_ratio (within 1.1 of the step elsewhere)."""

from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import synthetic
from shadecut.evaluation import grid_step_ratio
from shadecut.imaging import srgb_to_linear

REPO = Path(__file__).resolve().parents[2]

# test_relief.py's lights: oblique, from three sides, none used by the parameter tuning.
LIGHTS = [(0.6, 0.3, 1.0), (-0.5, 0.7, 1.0), (1.0, -0.2, 0.8)]
BOUND = 1.1
# Debian's python3-skimage ships these photographs under CC0 (skimage/data/README.txt).
PHOTOGRAPHS = ("brick", "gravel", "grass", "coins")


def smooth_normals(size: int = 128) -> np.ndarray:
    return synthetic.egg_crate((0.0, 0.0, 1.0), size, periods=1.5).normals


def test_grid_step_ratio_is_about_one_without_blocks_and_large_with_them():
    smooth = smooth_normals()
    assert grid_step_ratio(smooth) == pytest.approx(1.0, abs=0.02)
    # The same normals held constant over 8 x 8 blocks: every step lies on the grid.
    blocky = np.repeat(np.repeat(smooth[::8, ::8], 8, axis=0), 8, axis=1)
    blocky = blocky + 0.01 * smooth  # a little change inside the blocks, so that "elsewhere" is not zero
    assert grid_step_ratio(blocky) > 5.0
    # The periods are where the blocks are: blocks of 8 seen with a period of 12 are not a grid.
    assert grid_step_ratio(blocky, periods=(12,)) < grid_step_ratio(blocky)


def test_grid_step_ratio_reads_only_the_mask():
    smooth = smooth_normals()
    mask = np.zeros(smooth.shape[:2], bool)
    mask[20:100, 10:90] = True
    outside = smooth.copy()
    outside[~mask] = (1.0, 0.0, 0.0)  # whatever lies outside the mask does not count
    assert grid_step_ratio(outside, mask) == pytest.approx(grid_step_ratio(smooth, mask))


def test_grid_step_ratio_refuses_what_it_cannot_measure():
    with pytest.raises(ValueError, match="H x W x 3"):
        grid_step_ratio(np.zeros((16, 16)))
    flat = np.zeros((32, 32, 3))
    flat[..., 2] = 1.0
    with pytest.raises(ValueError, match="do not change"):
        grid_step_ratio(flat)
    with pytest.raises(ValueError, match="no steps"):
        grid_step_ratio(smooth_normals(8))


def relief_case(kind: str, light) -> synthetic.Scene:
    if kind == "bricks":
        # Bricks of 30 x 13 px, whose joints do not fall on the grid (the default 32 x 12 puts every
        # vertical joint on a multiple of 16: the truth's own ratio is 1.39).
        return synthetic.bricks(light, 256, brick=(30, 13))
    return synthetic.egg_crate(light, 256)


@pytest.mark.parametrize("light", LIGHTS)
@pytest.mark.parametrize("kind", ["bricks", "egg_crate"])
@pytest.mark.parametrize("given", [True, False], ids=["light given", "light estimated"])
def test_relief_renders_have_no_block_grid(kind, light, given):
    scene = relief_case(kind, light)
    result = shadecut.reconstruct(scene.image, scene.light if given else None, scene="relief")
    ratio = grid_step_ratio(result.normals)
    print(f"{kind} {light} {'given' if given else 'estimated'}: {ratio:.3f} (truth {grid_step_ratio(scene.normals):.3f})")
    assert ratio <= BOUND


def test_bumps_have_no_block_grid():
    # The labelling's convex/concave creases between the bumps stay on the coarse pixels' edges (1.134,
    # 1.113, 1.226 in its normals); a relief's normals are its integrated depth's, which smooths them.
    ratios = []
    for light in LIGHTS:
        scene = synthetic.bumps(light, 256)
        ratios.append(grid_step_ratio(shadecut.reconstruct(scene.image, scene.light, scene="relief").normals))
    print("bumps:", [round(r, 3) for r in ratios])
    assert max(ratios) <= BOUND


@pytest.mark.parametrize("name", PHOTOGRAPHS)
def test_photographs_have_no_block_grid(name):
    data = pytest.importorskip("skimage.data", reason="python3-skimage (its CC0 photographs) is not installed")
    pixels = np.asarray(getattr(data, name)(), dtype=np.float64)
    image = srgb_to_linear(pixels / 255.0)
    result = shadecut.reconstruct(image, None, scene="relief")  # every default, as a user would
    ratio = grid_step_ratio(result.normals)
    print(f"{name} {image.shape}: {ratio:.3f}")
    assert ratio <= BOUND


@pytest.mark.parametrize("name", ["sphere", "torus", "mozart"])
def test_objects_have_no_block_grid(name, mozart_path):
    if name == "mozart":
        scene = synthetic.mozart(mozart_path, (1.0, 0.0, 1.0))
    elif name == "torus":
        scene = synthetic.torus((0.5, 0.5, 1.0), 256)
    else:
        scene = synthetic.sphere((1.0, 0.0, 1.0), 256)
    result = shadecut.reconstruct(scene.image, scene.light, scene.mask)
    ratio = grid_step_ratio(result.normals, scene.mask)
    print(f"{name}: {ratio:.3f} (truth {grid_step_ratio(scene.normals, scene.mask):.3f})")
    assert ratio <= BOUND


def test_seams_are_found_wherever_a_rectangle_of_normals_is_turned():
    """seam_pixels finds the rectangles a blocky labelling leaves, at any position, and nothing on a
    smooth surface: a sphere with a 40 x 30 block of its normals turned by 5 degrees at an odd place."""
    from shadecut.evaluation import metrics

    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=128)
    assert metrics.seam_share(sphere.normals, sphere.mask) == 0.0
    blocky = sphere.normals.copy()
    turn = np.radians(5.0)
    rotation = np.array([[np.cos(turn), 0.0, np.sin(turn)], [0.0, 1.0, 0.0], [-np.sin(turn), 0.0, np.cos(turn)]])
    blocky[37:67, 45:85] = blocky[37:67, 45:85] @ rotation.T
    seams = metrics.seam_pixels(blocky, sphere.mask)
    rows, cols = np.nonzero(seams)
    assert seams.sum() >= 2 * (40 + 30) - 8
    assert set(rows) <= {36, 37, 65, 66, *range(37, 67)} and set(cols) <= {44, 45, 83, 84, *range(45, 85)}


def test_the_truth_of_mozart_and_a_smooth_result_have_no_seams():
    """The paper's bust: its true normals have almost none (a coat edge), a blurred result none
    (docs/results.md gives today's result's share)."""
    from scipy import ndimage
    from shadecut.evaluation import metrics

    bust = synthetic.mozart(REPO / "data" / "mozart" / "moz256.depth", light=(1.0, 0.0, 1.0))
    result = shadecut.reconstruct(bust.image, bust.light, bust.mask)
    smooth = np.stack([ndimage.gaussian_filter(result.normals[..., k], 3) for k in range(3)], axis=-1)
    assert metrics.seam_share(bust.normals, bust.mask) < 0.1
    assert metrics.seam_share(smooth, bust.mask) == 0.0


@pytest.mark.parametrize("light, bound", [
    pytest.param((1.0, 0.0, 1.0), 14.5, marks=pytest.mark.xfail(strict=True, reason=(
        "measured 17.45: the viscosity pull's labelling renders closer to the image (0.00606 against 0.00638) "
        "and is further from the truth than the paper's energy alone (14.76)"))),
    pytest.param((-0.5, 0.8, 1.0), 17.5, marks=pytest.mark.xfail(strict=True, reason=(
        "measured 20.08 (18.33 without the viscosity pull)"))),
])
def test_mozart_within_issue_44s_bounds(mozart_path, light, bound):
    bust = synthetic.mozart(mozart_path, light)
    error = bust.mean_error(shadecut.reconstruct(bust.image, bust.light, bust.mask).normals)
    print(f"Mozart {light}: {error:.2f} deg (issue 44 asks <= {bound})")
    assert error <= bound
