"""Turning pixel buffers from elsewhere (Blender's images, arrays) into the core's linear input.

No ``bpy`` here: the add-on hands over plain arrays, so all of this is tested outside Blender. The
rules themselves (sRGB decoding, luminance, block averaging) are the core's, shared with
``shadecut.load_image`` and the graph cut's coarse levels.
"""

from __future__ import annotations

import math

import numpy as np

from . import _core

# A working-size pixel lies in the mask when at least this share of its block does.
MASK_COVERAGE = 0.5


def srgb_to_linear(encoded) -> np.ndarray:
    """The sRGB transfer function inverted (IEC 61966-2-1), elementwise."""
    return np.asarray(_core.srgb_to_linear(np.asarray(encoded, dtype=float)), dtype=np.float32)


def intensity_and_mask(rgba: np.ndarray, *, srgb_encoded: bool) -> tuple[np.ndarray, np.ndarray, bool]:
    """Linear intensity and mask from an (H, W, 4) RGBA buffer with row 0 at the top.

    Colour becomes Rec. 709 luminance after decoding, as ``shadecut.load_image`` does. Alpha > 0.5
    is the mask; an image whose alpha is 1 everywhere has no mask (all pixels).

    Returns:
        intensity (H, W) float32 linear, mask (H, W) bool, has_alpha.
    """
    rgba = np.asarray(rgba, dtype=np.float32)
    if rgba.ndim != 3 or rgba.shape[2] != 4:
        raise ValueError(f"expected an (H, W, 4) RGBA buffer, got shape {rgba.shape}")
    intensity, mask = _core.intensity_from_pixels(rgba, srgb_encoded, 3)
    return intensity, mask, bool((rgba[..., 3] < 1.0).any())


def downsample(image: np.ndarray, mask: np.ndarray, max_size: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Shrinks an image by an integer factor until neither side exceeds ``max_size`` pixels.

    Each output pixel averages the masked pixels of its factor x factor block and is in the mask
    when at least half of the block is (0 elsewhere). Trailing rows/columns that do not fill a block
    are dropped.

    Returns:
        image (h, w) float32, mask (h, w) bool, factor (1 = unchanged; 0 for max_size means no limit).
    """
    height, width = mask.shape
    if max_size <= 0 or max(height, width) <= max_size:
        return image, mask, 1
    factor = math.ceil(max(height, width) / max_size)
    if height // factor < 2 or width // factor < 2:
        raise ValueError(f"a working size of {max_size} px leaves fewer than 2 x 2 pixels of the {width} x {height} image")
    small, small_mask = _core.downsample(np.asarray(image, dtype=np.float32), np.asarray(mask, dtype=bool), factor,
                                         MASK_COVERAGE)
    return small, small_mask, factor
