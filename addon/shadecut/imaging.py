"""Turning pixel buffers from elsewhere (Blender's images, arrays) into the core's linear input,
and results into the texture maps a material reads.

No ``bpy`` here: the add-on hands over plain arrays, so all of this is tested outside Blender. The
input rules (sRGB decoding, luminance, block averaging) are the core's, shared with
``shadecut.load_image`` and the graph cut's coarse levels; the two map encodings at the end
(:func:`normal_colors`, :func:`unit_height`) are written here only.
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


def luminance(image) -> np.ndarray:
    """(H, W) float64 linear intensity of a linear (H, W) grey or (H, W, 3) RGB image: the Rec. 709
    luminance the core reads colour through (``shadecut.LUMINANCE_WEIGHTS``); grey is returned as it is."""
    image = np.asarray(image, dtype=np.float64)
    return image @ np.array(_core.LUMINANCE_WEIGHTS) if image.ndim == 3 else image


def decode_rgba(rgba: np.ndarray, *, srgb_encoded: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear intensity (H, W), mask (H, W) and linear RGB (H, W, 3) from an (H, W, 4) RGBA buffer
    with row 0 at the top: the rule ``shadecut.load_image`` follows (Rec. 709 luminance after
    decoding; alpha > 0.5 is the mask)."""
    rgba = np.asarray(rgba, dtype=np.float32)
    if rgba.ndim != 3 or rgba.shape[2] != 4:
        raise ValueError(f"expected an (H, W, 4) RGBA buffer, got shape {rgba.shape}")
    return _core.intensity_from_pixels(rgba, srgb_encoded, 3)


def intensity_and_mask(rgba: np.ndarray, *, srgb_encoded: bool) -> tuple[np.ndarray, np.ndarray, bool]:
    """Linear intensity and mask from an (H, W, 4) RGBA buffer with row 0 at the top (:func:`decode_rgba`).
    An image whose alpha is 1 everywhere has no mask (all pixels).

    Returns:
        intensity (H, W) float32 linear, mask (H, W) bool, has_alpha.
    """
    intensity, mask, _ = decode_rgba(rgba, srgb_encoded=srgb_encoded)
    return intensity, mask, bool((np.asarray(rgba)[..., 3] < 1.0).any())


def shrink_factor(height: int, width: int, max_size: int) -> int:
    """The smallest whole factor that brings neither side above ``max_size`` pixels (1 when the image
    fits, or for max_size 0: no limit); ValueError when fewer than 2 x 2 pixels would remain."""
    if max_size <= 0 or max(height, width) <= max_size:
        return 1
    factor = math.ceil(max(height, width) / max_size)
    if height // factor < 2 or width // factor < 2:
        raise ValueError(f"a working size of {max_size} px leaves fewer than 2 x 2 pixels of the {width} x {height} image")
    return factor


def shrink(image: np.ndarray, mask: np.ndarray, factor: int) -> tuple[np.ndarray, np.ndarray]:
    """Each output pixel averages the masked pixels of its factor x factor block and is in the mask
    when at least half of the block is (0 elsewhere). Trailing rows/columns that do not fill a block
    are dropped, so an image shrunk in bands of whole blocks gives the same result."""
    if factor == 1:
        return image, mask
    return _core.downsample(np.asarray(image, dtype=np.float32), np.asarray(mask, dtype=bool), factor, MASK_COVERAGE)


def downsample(image: np.ndarray, mask: np.ndarray, max_size: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Shrinks an image by an integer factor until neither side exceeds ``max_size`` pixels
    (:func:`shrink_factor`, :func:`shrink`).

    Returns:
        image (h, w) float32, mask (h, w) bool, factor (1 = unchanged; 0 for max_size means no limit).
    """
    factor = shrink_factor(*mask.shape, max_size)
    return (*shrink(image, mask, factor), factor)


# The colour of an untilted normal (0, 0, 1): where a normal map has no normal.
FLAT_NORMAL_COLOR = (0.5, 0.5, 1.0)


def normal_colors(normals: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
    """Camera-frame unit normals (H, W, 3) as a normal map's colours (H, W, 3) float32: 0.5 * n + 0.5.

    Red = x (right), green = y (up), blue = z (toward the viewer), the convention of Blender's Normal
    Map node (and OpenGL's): on a flat surface whose UVs lay the image out unrotated, the camera
    frame is the tangent space. Pixels outside ``mask``, or without a normal (zero), are
    :data:`FLAT_NORMAL_COLOR`, so that texture filtering at the mask's edge does not blend in a
    zero normal.
    """
    normals = np.asarray(normals, dtype=np.float32)
    valid = np.linalg.norm(normals, axis=2) > 0
    if mask is not None:
        valid &= np.asarray(mask, dtype=bool)
    colors = 0.5 * normals + 0.5
    colors[~valid] = FLAT_NORMAL_COLOR
    return colors.astype(np.float32)


def residual_share(residual: np.ndarray, albedo_map: np.ndarray) -> np.ndarray:
    """``Reconstruction.residual`` (H, W) over the albedo there, clipped to 0..1 (0 where the albedo
    is 0): what the add-on's Residual map image shows."""
    residual = np.asarray(residual, dtype=np.float32)
    share = np.divide(residual, albedo_map, out=np.zeros_like(residual), where=np.asarray(albedo_map) > 0)
    return np.clip(share, 0.0, 1.0)


def unit_height(depth: np.ndarray, mask: np.ndarray) -> tuple[np.ndarray, float, float]:
    """A depth map (H, W) as a height image in 0..1 with the rule to undo it.

    ``depth = (height - zero) * span`` on the mask, where ``span`` = the depth's range (the span of
    the mask's depths and 0) and ``zero`` = the image value of depth 0, which pixels outside the mask
    hold. A displacement of ``(height - zero) * span * s`` (Blender's Displacement node with
    Midlevel ``zero`` and Scale ``span * s``) therefore equals ``depth * s``.

    Returns:
        height (H, W) float32 in 0..1, zero, span (1 when the depth is 0 everywhere).
    """
    mask = np.asarray(mask, dtype=bool)
    depth = np.where(mask, np.asarray(depth, dtype=np.float64), 0.0)
    low, high = min(float(depth.min()), 0.0), max(float(depth.max()), 0.0)
    span = high - low if high > low else 1.0
    height = (depth - low) / span
    return np.clip(height, 0.0, 1.0).astype(np.float32), -low / span, span
