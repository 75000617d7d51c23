"""Turning pixel buffers from elsewhere (Blender's images, arrays) into the core's linear input.

No ``bpy`` here: the add-on hands over plain arrays, so all of this is tested outside Blender.
"""

from __future__ import annotations

import math

import numpy as np

REC709_LUMINANCE = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def srgb_to_linear(encoded: np.ndarray) -> np.ndarray:
    """The sRGB transfer function inverted (IEC 61966-2-1), elementwise, float32."""
    encoded = np.asarray(encoded, dtype=np.float32)
    return np.where(
        encoded <= 0.04045, encoded / 12.92, np.power((np.maximum(encoded, 0.04045) + 0.055) / 1.055, 2.4)
    ).astype(np.float32)


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
    rgb = srgb_to_linear(rgba[..., :3]) if srgb_encoded else rgba[..., :3]
    intensity = np.ascontiguousarray(rgb @ REC709_LUMINANCE, dtype=np.float32)
    alpha = rgba[..., 3]
    has_alpha = bool((alpha < 1.0).any())
    return intensity, alpha > 0.5, has_alpha


def downsample(image: np.ndarray, mask: np.ndarray, max_size: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Shrinks an image by an integer factor until neither side exceeds ``max_size`` pixels.

    Each output pixel averages the masked pixels of its factor x factor block and is in the mask
    when at least half of the block is. Trailing rows/columns that do not fill a block are dropped.

    Returns:
        image (h, w) float32, mask (h, w) bool, factor (1 = unchanged; 0 for max_size means no limit).
    """
    height, width = mask.shape
    if max_size <= 0 or max(height, width) <= max_size:
        return image, mask, 1
    factor = math.ceil(max(height, width) / max_size)
    h, w = height // factor, width // factor
    if h < 2 or w < 2:
        raise ValueError(f"a working size of {max_size} px leaves fewer than 2 x 2 pixels of the {width} x {height} image")
    blocks = (h, factor, w, factor)
    weights = mask[: h * factor, : w * factor].astype(np.float32).reshape(blocks)
    values = image[: h * factor, : w * factor].reshape(blocks) * weights
    count = weights.sum(axis=(1, 3))
    small = np.where(count > 0, values.sum(axis=(1, 3)) / np.maximum(count, 1), 0).astype(np.float32)
    return small, count >= factor * factor / 2, factor
