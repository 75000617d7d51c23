"""The metrics of a reconstruction against its ground truth: angular and depth errors, light error.

Every metric is taken on the ground-truth mask eroded by :data:`ERODE_PIXELS`, where the central
differences of the image and of the true normals see no background. Angles are in degrees, depth in
pixel units.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .. import angular_error_map, erode_mask, mask_components

ERODE_PIXELS = 2
THRESHOLDS = (11.25, 22.5, 30.0)  # degrees, the customary shares of shape-from-shading papers

# The numeric columns of a record, in the order of results.csv and of the tables.
METRICS = (
    "mean_deg",
    "median_deg",
    "under_11.25_pct",
    "under_22.5_pct",
    "under_30_pct",
    "depth_rmse",
    "depth_rmse_scaled",
    "depth_scale",
    "seconds",
    "light_error_deg",
)


def normal_errors(normals: np.ndarray, truth: np.ndarray, mask: np.ndarray, erode: int = ERODE_PIXELS) -> dict:
    """Mean and median angular error and the share (percent) of pixels under each of THRESHOLDS.

    Taken on ``mask`` eroded by ``erode`` pixels. Raises ValueError when the eroded mask is empty or
    the normals are not finite there (a method that produced NaN has failed, not scored 0).
    """
    inside = erode_mask(mask, erode)
    normals = np.asarray(normals)
    # Checked here (the core checks it too, in its words): a method's NaN is a failure of the method.
    if normals.shape[:2] == inside.shape and not np.isfinite(normals[inside]).all():
        raise ValueError("the reconstructed normals are not finite (or are zero) on the mask")
    errors = angular_error_map(normals, truth, inside)[inside]
    if errors.size == 0:
        raise ValueError(f"the mask eroded by {erode} pixels is empty: nothing to measure")
    if not np.isfinite(errors).all():
        raise ValueError("the reconstructed normals are not finite (or are zero) on the mask")
    metrics = {"mean_deg": float(np.mean(errors, dtype=np.float64)), "median_deg": float(np.median(errors))}
    for threshold in THRESHOLDS:
        metrics[f"under_{threshold:g}_pct"] = float(100.0 * np.count_nonzero(errors < threshold) / errors.size)
    return metrics


def mask_parts(mask: np.ndarray) -> np.ndarray:
    """Labels the 4-connected parts of a mask: each pixel gets the smallest flat index of its part.

    Outside the mask the label is ``mask.size``. The parts are the core's (:func:`shadecut.mask_components`,
    the integrator's own), each named here by its first pixel in raster order.
    """
    mask = np.asarray(mask, dtype=bool)
    labels, _ = mask_components(mask)
    flat = labels.ravel()
    inside = np.flatnonzero(flat >= 0)
    # The core numbers the parts in the raster order of their first pixels: part k starts at the k-th new label.
    _, first = np.unique(flat[inside], return_index=True)
    named = np.full(mask.size, mask.size, dtype=np.int64)
    named[inside] = inside[first][flat[inside]]
    return named.reshape(mask.shape)


def depth_errors(depth: np.ndarray, truth: np.ndarray, mask: np.ndarray, erode: int = ERODE_PIXELS) -> dict:
    """Depth RMSE after the best offset, and after the best scale and offset, on the eroded mask.

    Shape from shading fixes depth only up to a constant per connected part of the mask (4-neighbour
    parts, as the integrator), so each part gets its own best offset; the scale is one for the image.
    Returns ``depth_rmse``, ``depth_rmse_scaled`` and the fitted ``depth_scale`` (truth ~ scale *
    depth + offsets; 1 for a reconstruction of the right amplitude).
    """
    inside = erode_mask(mask, erode)
    if not inside.any():
        raise ValueError(f"the mask eroded by {erode} pixels is empty: nothing to measure")
    _, part = np.unique(mask_components(mask)[0][inside], return_inverse=True)  # parts numbered 0, 1, ...
    pixels = np.bincount(part)

    def centred(values: np.ndarray) -> np.ndarray:
        values = values[inside].astype(np.float64)
        return values - (np.bincount(part, weights=values) / pixels)[part]

    estimate, true = centred(np.asarray(depth)), centred(np.asarray(truth))
    if not np.isfinite(estimate).all():
        raise ValueError("the reconstructed depth is not finite on the mask")
    power = float(np.dot(estimate, estimate))
    scale = float(np.dot(estimate, true)) / power if power > 0 else 0.0
    return {
        "depth_rmse": float(np.sqrt(np.mean((estimate - true) ** 2))),
        "depth_rmse_scaled": float(np.sqrt(np.mean((true - scale * estimate) ** 2))),
        "depth_scale": scale,
    }


def light_error(estimated: Sequence[float], truth: Sequence[float]) -> float:
    """The angle in degrees between two light directions (either length)."""
    a = np.asarray(estimated, dtype=np.float64)
    b = np.asarray(truth, dtype=np.float64)
    # atan2 of |a x b| and a . b stays accurate for small angles, where arccos of the cosine does not.
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b))))


def _unit_normals(normals, mask) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals (H x W x 3, 0 outside) and where they are: in ``mask`` (default every pixel), finite, not zero."""
    normals = np.asarray(normals, dtype=np.float64)
    if normals.ndim != 3 or normals.shape[2] != 3:
        raise ValueError(f"normals must be H x W x 3, got {normals.shape}")
    length = np.linalg.norm(normals, axis=2)
    inside = np.isfinite(length) & (length > 0)
    if mask is not None:
        inside &= np.asarray(mask, dtype=bool)
    return np.where(inside[..., None], normals / np.where(inside, length, 1.0)[..., None], 0.0), inside


def _steps(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angles (radians) between unit normals: atan2 of |a x b| and a . b, accurate for the small angles
    between neighbours, where arccos is not."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))


GRID_PERIODS = (8, 16, 32, 64)  # pixels: the blocks of coarse to fine at 2, 3, 4 and 5 levels below the image


def grid_step_ratio(normals: np.ndarray, mask: np.ndarray | None = None, periods: Sequence[int] = GRID_PERIODS) -> float:
    """How much a normal map steps on a block grid: 1 for none, 2 when its steps there are twice as large.

    A *step* is the angle between the normals of two 4-neighbours, both in ``mask``. The boundary
    between columns c - 1 and c, and between rows r - 1 and r, is *on the grid* when c (r) is a
    positive multiple of any of ``periods`` (pixels, counted from the image's first row and column,
    where coarse to fine's blocks start). Returns the mean step across the boundaries on the grid
    divided by the mean step across all the others, rows and columns pooled. No metric of the truth
    is needed: a surface without blocks scores about 1 whatever its shape, since its steps do not
    care where the grid is.

    ``normals``: H x W x 3 (any length; zero or non-finite normals count as outside). ``mask``: H x W
    bool, default every pixel. Raises ValueError when either kind of boundary has no step to measure
    (an image smaller than the smallest period) or the steps off the grid are all zero (a plane).
    """
    unit, inside = _unit_normals(normals, mask)

    def on_grid(count: int) -> np.ndarray:
        index = np.arange(1, count)  # boundary i lies between i - 1 and i
        return np.any([index % period == 0 for period in periods], axis=0)

    across_columns = _steps(unit[:, :-1], unit[:, 1:])
    across_rows = _steps(unit[:-1], unit[1:])
    both_columns = inside[:, :-1] & inside[:, 1:]
    both_rows = inside[:-1] & inside[1:]
    grid_columns = np.broadcast_to(on_grid(normals.shape[1])[None, :], across_columns.shape)
    grid_rows = np.broadcast_to(on_grid(normals.shape[0])[:, None], across_rows.shape)
    on = np.concatenate([across_columns[both_columns & grid_columns], across_rows[both_rows & grid_rows]])
    off = np.concatenate([across_columns[both_columns & ~grid_columns], across_rows[both_rows & ~grid_rows]])
    if on.size == 0 or off.size == 0:
        raise ValueError(f"no steps to compare: the masked image has no boundaries {'on' if on.size == 0 else 'off'} "
                         f"the grid of periods {tuple(periods)}")
    off_mean = float(np.mean(off))
    if off_mean <= 0.0:
        raise ValueError("the normals do not change off the grid: no step to compare with")
    return float(np.mean(on)) / off_mean


SEAM_STEP_DEG = 1.0  # a seam's step exceeds the steps of the boundaries beside it by this much
SEAM_LENGTH = 24  # pixels: a seam is straight over at least this many pixels along a row or a column
SEAM_SHARE = 0.9  # of which at least this share steps


def seam_pixels(normals: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
    """The pixels on axis-aligned straight seams of a normal map: the rectangles a blocky labelling
    leaves, at any position (grid_step_ratio sees only those on a fixed grid).

    A boundary between rows r and r + 1 (or columns) *steps* at a pixel when the angle between the two
    normals there exceeds, by SEAM_STEP_DEG, the largest step of the two boundaries on either side of
    it: a local maximum across the boundary, which a smooth surface, however curved, does not make. A
    seam is a run of at least SEAM_LENGTH pixels along the boundary of which SEAM_SHARE step. Returns
    H x W bool, true on the pixel above (left of) each stepping pixel of a seam.
    """
    unit, inside = _unit_normals(normals, mask)
    seams = np.zeros(inside.shape, dtype=bool)
    for transposed in (False, True):
        n = unit.transpose(1, 0, 2) if transposed else unit
        m = inside.T if transposed else inside
        both = m[:-1] & m[1:]
        step = np.where(both, np.degrees(_steps(n[:-1], n[1:])), np.nan)
        padded = np.pad(step, ((2, 2), (0, 0)), constant_values=np.nan)
        beside = np.stack([padded[2 + k:padded.shape[0] - 2 + k] for k in (-2, -1, 1, 2)])
        with np.errstate(all="ignore"):
            largest_beside = np.where(np.isnan(beside).all(axis=0), 0.0, np.nanmax(np.nan_to_num(beside, nan=-np.inf), axis=0))
        stepped = both & (np.nan_to_num(step - largest_beside, nan=-1.0) > SEAM_STEP_DEG)
        kernel = np.ones(SEAM_LENGTH)
        counts = np.apply_along_axis(lambda row: np.convolve(row, kernel, mode="same"), 1, stepped.astype(float))
        long_run = counts >= SEAM_SHARE * SEAM_LENGTH
        spread = np.apply_along_axis(lambda row: np.convolve(row, kernel, mode="same"), 1, long_run.astype(float)) > 0
        on_seam = np.zeros(m.shape, dtype=bool)
        on_seam[:-1] = spread & stepped
        seams |= on_seam.T if transposed else on_seam
    return seams


def seam_share(normals: np.ndarray, mask: np.ndarray | None = None) -> float:
    """Percent of the masked pixels on straight seams (seam_pixels): about 0 for a smooth surface."""
    _, inside = _unit_normals(normals, mask)
    if not inside.any():
        raise ValueError("no normal to measure: the mask is empty or every normal is zero")
    return 100.0 * float(seam_pixels(normals, mask).sum()) / float(inside.sum())
