"""What a relief's height field should look like, measured: its shape against the truth, how much of
it is carrier (forms larger than the detail) and how deep it runs.

Heights are (H, W) arrays in pixel units over the full frame. Issue 29's figures use these
definitions; docs/method.md ("Reliefs") quotes them.
"""

from __future__ import annotations

import numpy as np

LARGE_FORM_FRACTION = 1 / 8  # forms larger than 1/8 of the image are carrier, not texture


def low_frequency_share(height: np.ndarray, large_form_fraction: float = LARGE_FORM_FRACTION) -> float:
    """The share of the height's variance in forms larger than ``large_form_fraction`` of the image's
    larger side: the power of the cosine transform (mirrored edges: a ramp is not cut into a saw) at
    wavelengths above that size over the power of every non-constant term. 0 for a flat field."""
    from scipy.fft import dctn  # only here: the add-on runs without scipy

    h = np.asarray(height, np.float64)
    power = dctn(h - h.mean(), norm="ortho") ** 2
    rows, cols = h.shape
    # DCT term k of n has wavelength 2 n / k pixels.
    frequency = np.hypot(*np.meshgrid(np.arange(rows) / (2 * rows), np.arange(cols) / (2 * cols), indexing="ij"))
    large = frequency < 1.0 / (large_form_fraction * max(rows, cols))
    large[0, 0] = False
    total = power.sum() - power[0, 0]
    return float(power[large].sum() / total) if total > 0 else 0.0


EDGE_STRIP_PIXELS = 8  # the strip along each frame edge that edge_lean reads


def edge_lean(normals: np.ndarray, form_size: float, width: int = EDGE_STRIP_PIXELS) -> list[float]:
    """How far the strip ``width`` pixels wide along each frame edge (left, right, top, bottom) leans
    across that edge, in standard errors: the mean of the normals' component across the edge (x for
    the left and right, y for the top and bottom) over the strip's spread of it divided by the square
    root of the forms along the strip (its length over ``form_size`` pixels, at least one).

    A relief of many small forms faces the viewer on average, in any strip, up to chance: a value
    beyond 3 is a band of tilted normals along the edge that nothing in the image explains.
    ``normals``: H x W x 3 over the full frame."""
    leans = []
    for strip, axis in ((np.s_[:, :width], 0), (np.s_[:, -width:], 0), (np.s_[:width, :], 1), (np.s_[-width:, :], 1)):
        across = np.asarray(normals[strip][..., axis], np.float64)
        forms = max(max(across.shape) / form_size, 1.0)
        error = across.std() / np.sqrt(forms)
        leans.append(float(abs(across.mean()) / error) if error > 0 else 0.0)
    return leans


def depth_range_fraction(height: np.ndarray) -> float:
    """The height's range (max - min) over the image's width."""
    return float(np.ptp(height) / height.shape[1])


def height_correlation(height: np.ndarray, truth: np.ndarray) -> float:
    """Pearson correlation of two height fields over the frame (offset and scale do not count)."""
    a, b = np.ravel(height).astype(np.float64), np.ravel(truth).astype(np.float64)
    a, b = a - a.mean(), b - b.mean()
    denominator = np.sqrt((a * a).sum() * (b * b).sum())
    return float((a * b).sum() / denominator) if denominator > 0 else 0.0


def relief_figures(height: np.ndarray, truth: np.ndarray | None = None) -> dict:
    """The figures above for one result: low_frequency_share and depth_range_fraction, and with a
    truth its correlation, range ratio and low-frequency share."""
    figures = {"low_frequency_share": low_frequency_share(height), "depth_range_fraction": depth_range_fraction(height)}
    if truth is not None:
        figures.update(correlation=height_correlation(height, truth), range_ratio=float(np.ptp(height) / np.ptp(truth)),
                       truth_low_frequency_share=low_frequency_share(truth))
    return figures
