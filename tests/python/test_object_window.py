"""An object small in a large frame is reconstructed in a window around its mask (issue 48): the
result is the object's own, put back in the frame, and the call's memory follows the object."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

ADDON = Path(__file__).resolve().parents[2] / "addon"
TOP, LEFT = 301, 517  # off every coarse grid


def in_frame(array: np.ndarray, size: int) -> np.ndarray:
    frame = np.zeros((size, size) + array.shape[2:], array.dtype)
    frame[TOP:TOP + array.shape[0], LEFT:LEFT + array.shape[1]] = array
    return frame


def window(array: np.ndarray, like: np.ndarray) -> np.ndarray:
    return array[TOP:TOP + like.shape[0], LEFT:LEFT + like.shape[1]]


@pytest.mark.parametrize("method", ["graphcut", "brooks_horn", "upwind"])
def test_an_object_in_a_large_frame_is_the_object_reconstructed_alone(method):
    scene = synthetic.torus((0.4, 0.7, 1.0), size=96)
    alone = shadecut.reconstruct(scene.image, scene.light, scene.mask, method=method)
    framed = shadecut.reconstruct(in_frame(scene.image, 900), scene.light, in_frame(scene.mask, 900), method=method)
    np.testing.assert_array_equal(framed.mask, in_frame(scene.mask, 900))
    np.testing.assert_allclose(window(framed.normals, scene.mask), alone.normals, atol=1e-5)
    np.testing.assert_allclose(window(framed.depth, scene.mask), alone.depth, atol=1e-3)
    outside = ~framed.mask
    assert not framed.normals[outside].any() and not framed.depth[outside].any() and not framed.albedo_map[outside].any()
    assert framed.albedo == alone.albedo


def test_a_colour_object_keeps_its_de_lit_colour_in_the_frame():
    scene = synthetic.sphere((0.5, 0.3, 1.0), 64)
    colour = scene.image[..., None] * np.array([0.9, 0.6, 0.3], np.float32)
    alone = shadecut.reconstruct(colour, scene.light, scene.mask)
    framed = shadecut.reconstruct(in_frame(colour, 700), scene.light, in_frame(scene.mask, 700))
    assert framed.albedo_colour.shape == (700, 700, 3)
    np.testing.assert_allclose(window(framed.albedo_colour, scene.mask), alone.albedo_colour, atol=1e-6)
    assert not framed.albedo_colour[~framed.mask].any()


def test_several_photographs_of_an_object_in_a_large_frame():
    scene = synthetic.sphere((0.0, 0.0, 1.0), 64)
    lights = np.array([[1, 0, 1], [0, 1, 1], [-1, 0, 1]], float)
    photos = np.stack([shadecut.render(scene.normals, light, 0.8, scene.mask) for light in lights])
    alone = shadecut.reconstruct(photos, lights, scene.mask)
    framed = shadecut.reconstruct(np.stack([in_frame(p, 600) for p in photos]), lights, in_frame(scene.mask, 600))
    np.testing.assert_allclose(window(framed.normals, scene.mask), alone.normals, atol=1e-5)
    assert framed.residual.shape == (600, 600) and not framed.residual[~framed.mask].any()
    np.testing.assert_allclose(window(framed.residual, scene.mask), alone.residual, atol=1e-6)


def test_a_mask_of_another_shape_is_still_named_as_such():
    scene = synthetic.sphere((0.5, 0.3, 1.0), 64)
    with pytest.raises(ValueError, match="mask"):
        shadecut.reconstruct(in_frame(scene.image, 700), scene.light, in_frame(scene.mask, 600))


def test_the_memory_of_a_small_object_follows_the_object_not_its_frame():
    # Before the window, a 64-pixel sphere in a 3000 x 3000 frame peaked at 4.7 GB (issue 48); the
    # frame's own arrays are 45 MB.
    script = (
        "import resource, numpy as np, shadecut\n"
        "from shadecut import synthetic\n"
        "s = synthetic.sphere((0.4, 0.3, 1.0), 64)\n"
        "image = np.zeros((3000, 3000), np.float32); mask = np.zeros((3000, 3000), bool)\n"
        "image[1234:1298, 2001:2065] = s.image; mask[1234:1298, 2001:2065] = s.mask\n"
        "result = shadecut.reconstruct(image, s.light, mask)\n"
        "assert result.mask.sum() == s.mask.sum()\n"
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024)\n"
    )
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ADDON)},
                         check=True)
    peak_mb = int(run.stdout.split()[-1])
    print(f"64-pixel sphere in a 3000 x 3000 frame: peak {peak_mb} MB")
    assert peak_mb < 400
