"""The Python API of ShadeCut: thin, documented wrappers over the compiled ``_core`` module.

Arrays: an image is (H, W) float32 linear intensity, row 0 at the top; normals are (H, W, 3) float32
in the camera frame (x right, y up, z toward the viewer); depth is (H, W) float32 in pixel units,
larger = closer; masks are (H, W) bool. Bad input raises ValueError with a message that says what.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

try:
    from . import _core
except ImportError as error:  # the extension is produced by the CMake build
    raise ImportError(
        "shadecut's compiled module _core is missing: build it first (see README.md, "
        "'cmake -S . -B build && cmake --build build'), which places it in addon/shadecut/"
    ) from error

Cancelled = _core.Cancelled
Cancelled.__doc__ = "Raised when a progress callback returns False."

ProgressCallback = Callable[[float, str], Optional[bool]]

METHODS: tuple = tuple(_core.METHODS)
"""Every reconstruction method's name, for ``reconstruct(..., method=...)``."""

LIGHT_METHODS: tuple = tuple(_core.LIGHT_METHODS)
"""Every light estimator's name, for :func:`estimate_light` and ``reconstruct(..., light_method=...)``."""


@dataclass
class Reconstruction:
    """The result of :func:`reconstruct`."""

    normals: np.ndarray  # (H, W, 3) float32, camera frame; 0 outside the mask
    depth: np.ndarray  # (H, W) float32, pixel units, larger = closer; each mask component's minimum is 0
    mask: np.ndarray  # (H, W) bool
    albedo: float  # the albedo used: given, estimated with the light, or the brightest pixels
    light: np.ndarray  # (3,) unit vector toward the light used (given or estimated), camera frame
    # seconds per stage, iterations, energy per cycle, moves, light_estimated (and light_method), ...
    stats: dict = field(default_factory=dict)


@dataclass
class LoadedImage:
    """An image file read by :func:`load_image`."""

    image: np.ndarray  # (H, W) float32 linear intensity
    mask: np.ndarray  # (H, W) bool: alpha > 0.5, or all True without alpha
    has_alpha: bool
    color_space: str  # how the stored values were read: "linear" or "srgb"


def _mask(mask) -> Optional[np.ndarray]:
    return None if mask is None else np.ascontiguousarray(mask, dtype=bool)


def _vector3(light: Sequence[float]) -> list[float]:
    vector = np.asarray(light, dtype=float).reshape(-1)
    if vector.shape != (3,):
        raise ValueError(f"shadecut: the light must have 3 components (x, y, z); got shape {np.shape(light)}")
    return vector.tolist()


def reconstruct(
    image,
    light: Optional[Sequence[float]] = None,
    mask=None,
    albedo: Optional[float] = None,
    method: str = "graphcut",
    *,
    labels: int = 36,
    data_weight: float = 0.2,
    undefined_weight: Optional[float] = None,
    integrator: str = "poisson",
    maxflow: str = "grid",
    max_cycles: int = 20,
    coarse_to_fine_band: int = 1,
    tolerance: Optional[float] = None,
    iterations: Optional[int] = None,
    smoothness: Optional[float] = None,
    light_method: str = "zheng_chellappa",
    min_curvature: Optional[float] = None,
    refine: bool = True,
    max_slope: float = 10.0,
    fill_shadows: bool = True,
    occluding_contour: bool = True,
    threads: int = 0,
    progress: Optional[ProgressCallback] = None,
) -> Reconstruction:
    """Reconstructs normals and depth from one Lambertian image.

    Args:
        image: (H, W) linear intensity, at least 2 x 2, finite, >= 0.
        light: direction toward the distant light in the camera frame, S_z > 0; normalized here.
            None = estimated from the image by ``light_method`` (see :func:`estimate_light`), and then
            also the albedo unless given; ``stats["light_estimated"]`` says so.
        mask: (H, W) bool pixels to reconstruct; None = every pixel.
        albedo: > 0; None = estimated with the light, or with a given light the brightest value of the
            3 x 3 median-filtered image in the mask.
        method: one of :data:`METHODS`: "graphcut" (eq. 15), "graphcut_two" (eq. 10),
            "lee_rosenfeld" (local, convex), "brooks_horn" (variational), "tsai_shah" (linear, depth).
        labels: K discrete tilts, >= 4.
        data_weight: lambda of eq. (15) (graphcut only) for an object of 128 pixels (the square root
            of the mask's area); for an object of L pixels the per-pixel weight is data_weight * 128 / L,
            which keeps the balance with the pairwise term the same at every resolution.
        undefined_weight: pull toward tilt pi where the local tilt is undefined, scaled like
            data_weight; None = the method's tuned default (README, "Choosing the parameters").
        integrator: "poisson" (least squares on the mask) or "frankot_chellappa".
        maxflow: "grid" (ShadeCut's grid solver), "opencv" or "boost".
        max_cycles: upper bound on alpha-expansion cycles.
        coarse_to_fine_band: graphcut, graphcut_two: when >= 0 and the object is at least 96 pixels
            across, solve at half resolution first (recursively) and keep at each pixel only the
            labels within this many steps of its coarse label; < 0 = every label at full resolution
            (the exact alpha-expansion). ``stats["levels"]`` counts the resolutions solved.
        tolerance: graphcut, graphcut_two: also stop when a cycle lowers the energy by no more than
            this share of it, 0 = only when a cycle lowers it no more (the paper's criterion);
            brooks_horn: stop when a sweep moves the normals by no more than this (mean |dn|).
            None = the method's default (README, "Choosing the parameters").
        iterations: brooks_horn, tsai_shah: the number of sweeps (an upper bound for brooks_horn);
            None = the method's tuned default.
        smoothness: brooks_horn: weight lambda of the smoothness term for an object 128 pixels across
            (scaled by the object's area in pixels, so the same value means the same at every
            resolution); None = the tuned default.
        light_method: the estimator used when ``light`` is None, one of :data:`LIGHT_METHODS`.
        min_curvature: the local tilt is undefined where the surface reads as flat: where
            |grad I| L / (albedo sin s), the curvature of the locally spherical patch in units of the
            object (L = sqrt of the mask's area, s the slant), is below this; None = the method's
            tuned default. The same at every resolution of the same surface.
        refine: keep the local step's exact tilt where the label agrees with a candidate.
        max_slope: integrator gradient clamp (depth units per pixel).
        fill_shadows: interpolate normals where the image is black (attached shadow).
        occluding_contour: take the mask's edge as the object's silhouette when filling shadows, and as
            brooks_horn's boundary condition.
        threads: OpenMP threads, 0 = all cores.
        progress: called as progress(fraction, stage); returning False raises :class:`Cancelled`.
    """
    result = _core.reconstruct(
        np.asarray(image), None if light is None else _vector3(light), _mask(mask), albedo, method, labels, data_weight,
        undefined_weight, integrator, maxflow, max_cycles, coarse_to_fine_band, tolerance, iterations, smoothness, light_method, min_curvature,
        refine, max_slope, fill_shadows, occluding_contour, threads,
        progress,
    )
    return Reconstruction(
        normals=result["normals"],
        depth=result["depth"],
        mask=result["mask"],
        albedo=result["albedo"],
        light=np.asarray(result["light"]),
        stats=result["stats"],
    )


def render(depth_or_normals, light: Sequence[float], albedo: float = 1.0, mask=None) -> np.ndarray:
    """Lambertian image albedo * max(0, S . N) of a height field (H, W) or a normal map (H, W, 3).

    Pixels outside ``mask`` are 0. A height field's normals come from :func:`normals_from_depth`.
    """
    surface = np.asarray(depth_or_normals)
    normals = normals_from_depth(surface, mask) if surface.ndim == 2 else surface
    return _core.render_normals(normals, _vector3(light), float(albedo), _mask(mask))


def normals_from_depth(depth, mask=None) -> np.ndarray:
    """Camera-frame unit normals normalize(-dz/dx, -dz/dy, 1) of a height field, (H, W, 3)."""
    return _core.normals_from_depth(np.asarray(depth), _mask(mask))


def integrate(normals, mask=None, method: str = "poisson", max_slope: float = 10.0) -> np.ndarray:
    """Depth (H, W) from camera-frame normals (H, W, 3); each mask component's minimum is 0."""
    return _core.integrate(np.asarray(normals), _mask(mask), method, max_slope)


def angular_error_map(n1, n2, mask=None) -> np.ndarray:
    """Per-pixel angle between two normal maps in degrees, NaN outside the mask."""
    return _core.angular_error_map(np.asarray(n1), np.asarray(n2), _mask(mask))


def angular_error(n1, n2, mask=None) -> float:
    """Mean angle between two normal maps over the mask, in degrees."""
    errors = angular_error_map(n1, n2, mask)
    selected = errors[np.isfinite(errors)] if mask is None else errors[_mask(mask)]
    if selected.size == 0:
        raise ValueError("shadecut: the mask for the angular error selects no pixel")
    return float(np.mean(selected))


def erode_mask(mask, pixels: int) -> np.ndarray:
    """The mask shrunk by ``pixels`` steps of 4-neighbour erosion (the image border erodes too)."""
    return _core.erode_mask(_mask(mask), int(pixels))


def estimate_light(image, mask=None, method: str = "lee_rosenfeld") -> tuple[np.ndarray, float]:
    """Estimates (light, albedo) of a Lambertian image: light a (3,) unit vector toward the light.

    ``method``: "lee_rosenfeld" (Lee & Rosenfeld 1985: tilt from the mean direction of the intensity
    gradients, slant from the mean and mean squared intensity of a sphere without attached shadow) or
    "zheng_chellappa" (tilt from the mean gradient, slant from the moments of a sphere with its
    attached shadow). Both assume normals spread like a sphere's over the mask, which should cover
    the object only. Their measured biases are in the README ("Comparison methods and light estimation").
    """
    light, albedo = _core.estimate_light(np.asarray(image), _mask(mask), method)
    return np.asarray(light), float(albedo)


def estimate_albedo(image, mask=None) -> float:
    """The albedo reconstruct() uses when none is given."""
    return _core.estimate_albedo(np.asarray(image), _mask(mask))


def load_image(path: str | os.PathLike, color_space: str = "auto") -> LoadedImage:
    """Reads an image file as linear intensity through OpenImageIO.

    8/16-bit PNG, TIFF, JPEG and float EXR among others. ``color_space="auto"``: float files are
    linear, integer files sRGB unless they say they are linear. Colour becomes Rec. 709 luminance;
    alpha becomes the mask. Raises OSError for a missing or unreadable file.
    """
    image, mask, has_alpha, color_space_used = _core.load_image(os.fspath(path), color_space)
    return LoadedImage(image=image, mask=mask, has_alpha=has_alpha, color_space=color_space_used)


def save_image(path: str | os.PathLike, image, mask=None) -> None:
    """Writes linear intensity: float for .exr/.tif, 16-bit sRGB PNG otherwise (alpha = mask)."""
    _core.save_image(os.fspath(path), np.asarray(image), _mask(mask))


def save_depth(path: str | os.PathLike, depth, mask=None) -> None:
    """Writes depth: float .exr/.tif (data) or 16-bit PNG scaled to the masked range (a picture)."""
    _core.save_depth(os.fspath(path), np.asarray(depth), _mask(mask))


def save_normals(path: str | os.PathLike, normals, mask=None) -> None:
    """Writes normals: float .exr/.tif, or an 8-bit PNG normal map (n + 1) / 2."""
    _core.save_normals(os.fspath(path), np.asarray(normals), _mask(mask))


def save_mesh(path: str | os.PathLike, depth, mask=None) -> None:
    """Writes the height field as a .ply or .obj triangle mesh, vertices at (column, -row, depth)."""
    _core.save_mesh(os.fspath(path), np.asarray(depth), _mask(mask))
