"""Subject = Relief with Seamless on, through the operator as an artist runs it: the surface tiles
(its left edge meets its right, its top its bottom) where the same click without Seamless does not."""

import bpy
import numpy as np

from test_relief_preset import bricks_image


def result_heights(settings) -> np.ndarray:
    """The new object's vertex heights as a grid, row 0 at the top (one vertex per pixel)."""
    before = set(bpy.data.objects)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    (result,) = set(bpy.data.objects) - before
    co = np.empty(3 * len(result.data.vertices), np.float32)
    result.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    columns, rows = np.unique(co[:, 0]), np.unique(co[:, 1])
    grid = np.full((len(rows), len(columns)), np.nan, np.float32)
    grid[len(rows) - 1 - np.searchsorted(rows, co[:, 1]), np.searchsorted(columns, co[:, 0])] = co[:, 2]
    assert not np.isnan(grid).any()
    return grid


def seam_and_inner_steps(z: np.ndarray) -> tuple[float, float]:
    seam = max(np.abs(z[:, 0] - z[:, -1]).max(), np.abs(z[0] - z[-1]).max())
    inner = max(np.abs(np.diff(z, axis=1)).max(), np.abs(np.diff(z, axis=0)).max())
    return float(seam), float(inner)


def test_seamless_relief_tiles(addon, tmp_path):
    settings = bpy.context.scene.shadecut
    settings.image = bricks_image(tmp_path, 128, (0.6, 0.3, 1.0))
    settings.scene = "relief"
    settings.seamless = True
    seam, inner = seam_and_inner_steps(result_heights(settings))
    print(f"seamless: seam step {seam:.5f}, largest inner step {inner:.5f}")
    assert seam <= inner
    settings.seamless = False
    seam, inner = seam_and_inner_steps(result_heights(settings))
    print(f"not seamless: seam step {seam:.5f}, largest inner step {inner:.5f}")
    assert seam > inner
