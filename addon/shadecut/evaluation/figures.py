"""Figures of one sample: the input, the true normals and every method's normals and error map."""

from __future__ import annotations

import os
import textwrap

import numpy as np

from .. import angular_error_map, erode_mask
from ..atomic_write import replacing
from .metrics import ERODE_PIXELS


def _normal_colours(normals: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The usual normal-map colours (n + 1) / 2, white outside the mask."""
    return np.where(mask[..., None], np.clip((normals + 1) / 2, 0, 1), 1.0)


def save_strip(path: os.PathLike | str, title: str, truth, reconstructions: dict, records: list[dict],
               erode: int = ERODE_PIXELS) -> None:
    """A figure of one sample: the input and the true normals, then a column per method.

    Top row: input, true normals, each method's normals; bottom row, under each method: its
    angular-error map on the eroded mask. The error maps share one colour scale, 0 to 90 degrees,
    with its colour bar at the right end; a failed method's column says so and shows its error.
    """
    # The object-oriented API with its own Agg canvas leaves pyplot's global backend alone.
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    inside = erode_mask(truth.mask, erode)
    columns = 2 + len(records)
    figure = Figure(figsize=(1.9 * columns + 0.6, 4.3))
    FigureCanvasAgg(figure)
    # A narrow last column holds the colour bar, so that no panel shrinks to make room for it.
    axes = figure.subplots(2, columns + 1, gridspec_kw={"width_ratios": [1] * columns + [0.07]})
    for axis in axes.flat:
        axis.set_axis_off()
    axes[0, 0].imshow(truth.image, cmap="gray", vmin=0, vmax=max(float(truth.image.max()), 1e-6))
    axes[0, 0].set_title("input", fontsize=9)
    axes[0, 1].imshow(_normal_colours(truth.normals, truth.mask))
    axes[0, 1].set_title("true normals", fontsize=9)
    light = np.asarray(truth.light, dtype=np.float64) / np.linalg.norm(truth.light)
    axes[1, 0].text(0.0, 0.5, "light ({:.2f}, {:.2f}, {:.2f})\n\nthis row: angular error\non the mask eroded\n"
                    "by {} pixels".format(*light, erode), fontsize=8, va="center", transform=axes[1, 0].transAxes)
    shown = None
    for column, record in enumerate(records, 2):
        method = record["method"]
        if record["status"] != "ok":
            axes[0, column].set_title(f"{method}: failed", fontsize=9)
            axes[0, column].text(0.5, 0.5, textwrap.fill(record["error"] or "", 30), ha="center", va="center",
                                 fontsize=6, transform=axes[0, column].transAxes)
            continue
        axes[0, column].imshow(_normal_colours(reconstructions[method].normals, truth.mask))
        axes[0, column].set_title(method, fontsize=9)
        error_map = angular_error_map(reconstructions[method].normals, truth.normals, inside)
        shown = axes[1, column].imshow(error_map, cmap="magma", vmin=0, vmax=90)
        axes[1, column].set_title(f"mean {record['mean_deg']:.1f}°, median {record['median_deg']:.1f}°", fontsize=8)
    if shown is not None:
        axes[1, -1].set_axis_on()
        figure.colorbar(shown, cax=axes[1, -1], label="degrees")
    figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    with replacing(path) as temporary:  # a full disk leaves no truncated figure under the name
        figure.savefig(temporary, dpi=72)
