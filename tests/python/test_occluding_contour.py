"""contour_weight: the outline of an object seen whole anchors the convex/concave choice.

Measured on a torus and a vase of shadecut.synthetic under lights the tuning does not use (the
dataset's torus and vase are Blender meshes: the default evaluation measures those). The vase is
symmetric about both image axes and the torus about its centre, so a light's mirror images (and, for
the torus, its rotations) are the same problem: none of these is the training surfaces' up to those.
"""

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

SHAPES = {
    "torus (0.6, -0.4, 1)": synthetic.torus((0.6, -0.4, 1.0), 128),
    "torus (-0.7, 0.2, 1)": synthetic.torus((-0.7, 0.2, 1.0), 160),
    "vase (-0.6, 0.3, 1)": synthetic.vase((-0.6, 0.3, 1.0), 128),
    "vase (0.7, 0.1, 1)": synthetic.vase((0.7, 0.1, 1.0), 160),
}


def outward_share(scene, normals) -> float:
    """The share of the outline's pixels (3 px deep) whose normal turns out of the silhouette, as
    the true one does there."""
    ring = scene.mask & ~shadecut.erode_mask(scene.mask, 3)
    true_across, across = scene.normals[..., :2], normals[..., :2]
    turned = ring & (np.linalg.norm(true_across, axis=2) > 0.5)
    return float(np.mean(np.sum(true_across[turned] * across[turned], axis=1) > 0))


@pytest.mark.parametrize("name", SHAPES)
def test_the_outline_turns_outward_and_the_shape_comes_closer(name):
    scene = SHAPES[name]
    # The contour term alone: the viscosity pull (another candidate labelling) off in both.
    without = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo, contour_weight=0.0,
                                   viscosity_weight=0.0)
    with_contour = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo, viscosity_weight=0.0)
    defaults = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo)
    print(f"{name}: {scene.mean_error(without.normals):.2f} -> {scene.mean_error(with_contour.normals):.2f} deg "
          f"with contour_weight {shadecut.ReconstructOptions().contour_weight:g}; outline outward "
          f"{outward_share(scene, without.normals):.2f} -> {outward_share(scene, with_contour.normals):.2f}; "
          f"every default (the viscosity pull too) {scene.mean_error(defaults.normals):.2f} deg")
    assert outward_share(scene, with_contour.normals) >= 0.9  # measured 0.95-1.00 (0.71-0.88 without)
    assert scene.mean_error(with_contour.normals) < scene.mean_error(without.normals) - 1.0


def test_a_bowl_s_rim_and_a_relief_are_left_alone():
    bowl = synthetic.sphere((0.3, -0.6, 1.0), bowl=True)
    results = [shadecut.reconstruct(bowl.image, bowl.light, bowl.mask, bowl.albedo, contour_weight=w) for w in (0.0, 3.0)]
    np.testing.assert_array_equal(results[0].normals, results[1].normals)
    wall = synthetic.bricks((0.6, 0.3, 1.0), size=64)
    reliefs = [shadecut.reconstruct(wall.image, wall.light, scene="relief", contour_weight=w) for w in (0.0, 3.0)]
    np.testing.assert_array_equal(reliefs[0].normals, reliefs[1].normals)
    with pytest.raises(ValueError, match="contour_weight"):
        shadecut.reconstruct(bowl.image, bowl.light, bowl.mask, contour_weight=-1.0)
