"""Reliefs with exact ground truth as real photographs show them: paint, cast shadows, a background.

Each function returns a :class:`ReliefScene`: a height field filling the frame (pixel units, larger =
closer), its normals by central differences, its per-pixel albedo, and the image rendered under a
distant light with the shadows the relief casts on itself (a pixel whose ray toward the light meets
the height field is dark). They train and test the relief pipeline (scripts/tune_parameters.py
--detail-size; tests/python/test_relief_photos.py); the seed picks one of a family, and training and
tests use seeds apart (:data:`TRAINING_SEEDS`, :data:`TEST_SEEDS`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .api import render
from .synthetic import Scene, gradient_normals

TRAINING_SEEDS = tuple(range(0, 4))
TEST_SEEDS = tuple(range(100, 103))


@dataclass
class ReliefScene(Scene):
    albedo_map: np.ndarray | None = None  # (H, W) float32, the paint
    shadow: np.ndarray | None = None  # (H, W) bool, the cast shadows


def cast_shadows(depth: np.ndarray, light: Sequence[float], step: float = 0.5) -> np.ndarray:
    """Pixels of the height field ``depth`` (H, W; x = column, y = up) whose ray toward the distant
    ``light`` passes below the field somewhere: (H, W) bool. Marched in ``step`` pixel steps, the
    field sampled bilinearly; outside the frame the field continues as its nearest edge."""
    from scipy.ndimage import map_coordinates  # only here: the add-on runs without scipy

    s = np.asarray(light, np.float64) / np.linalg.norm(light)
    across = float(np.hypot(s[0], s[1]))
    if across < 1e-6:
        return np.zeros(depth.shape, bool)
    rise = s[2] / across  # height gained per pixel travelled toward the light
    rows, cols = np.mgrid[0 : depth.shape[0], 0 : depth.shape[1]].astype(np.float64)
    shadow = np.zeros(depth.shape, bool)
    reach = min(np.ptp(depth) / max(rise, 1e-6) + 1.0, float(max(depth.shape)))
    for t in np.arange(step, reach + step, step):
        ahead = map_coordinates(depth, [rows - t * s[1] / across, cols + t * s[0] / across], order=1, mode="nearest")
        shadow |= ahead > depth + t * rise + 1e-3
    return shadow


def _relief(depth: np.ndarray, albedo: np.ndarray, light: Sequence[float]) -> ReliefScene:
    dz_drow, dz_dcol = np.gradient(depth)
    normals = gradient_normals(dz_dcol, -dz_drow).astype(np.float32)  # y is up: dz/dy = -dz/drow
    mask = np.ones(depth.shape, bool)
    shadow = cast_shadows(depth, light)
    image = render(normals, light, 1.0, mask) * albedo * ~shadow
    return ReliefScene(image.astype(np.float32), normals, (depth - depth.min()).astype(np.float32), mask,
                       tuple(light), float(np.median(albedo)), albedo.astype(np.float32), shadow)


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3 - 2 * x)


def mortar_bricks(light: Sequence[float], size: int = 256, seed: int = 0) -> ReliefScene:
    """Running-bond bricks of random size (24-40 x 10-16 px) standing 3-6 px proud of recessed,
    bright mortar (albedo 0.8-0.9 against bricks of 0.3-0.55 each): paint that a shading reading
    would take for raised ridges."""
    rng = np.random.default_rng(seed)
    width, course = rng.uniform(24, 40), rng.uniform(10, 16)
    mortar, height, bevel = rng.uniform(2.0, 3.5), rng.uniform(3.0, 6.0), rng.uniform(1.5, 3.0)
    rows, cols = np.mgrid[0:size, 0:size].astype(np.float64)
    row_of = np.floor(rows / course)
    shift = np.where(row_of % 2 == 1, width / 2, 0.0)
    column_of = np.floor((cols + shift) / width)
    along = np.abs(((cols + shift) % width) - width / 2)
    across = np.abs((rows % course) - course / 2)
    distance = np.minimum(width / 2 - along, course / 2 - across) - mortar / 2
    depth = height * _smoothstep(distance / bevel)
    brick_albedo = rng.uniform(0.3, 0.55, (int(size / course) + 2, int(size / width) + 3))
    bricks = brick_albedo[row_of.astype(int), column_of.astype(int) % brick_albedo.shape[1]]
    albedo = np.where(distance > 0, bricks, rng.uniform(0.8, 0.9))
    return _relief(depth, albedo, light)


def pebbles(light: Sequence[float], size: int = 256, seed: int = 0) -> ReliefScene:
    """Rounded pebbles (ellipsoidal caps, 8-24 px across half-axes, as high as 0.5-0.8 of their width)
    packed on a darker ground: under an oblique light they cast shadows into the gaps."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:size, 0:size].astype(np.float64)
    depth = np.zeros((size, size))
    albedo = np.full((size, size), rng.uniform(0.25, 0.35))
    for _ in range(int(size * size / 500)):
        r0, c0 = rng.uniform(0, size, 2)
        a, b = rng.uniform(8, 24), rng.uniform(8, 24)
        angle = rng.uniform(0, np.pi)
        u = ((cols - c0) * np.cos(angle) + (rows - r0) * np.sin(angle)) / a
        v = (-(cols - c0) * np.sin(angle) + (rows - r0) * np.cos(angle)) / b
        cap = rng.uniform(0.5, 0.8) * min(a, b) * np.sqrt(np.clip(1 - u * u - v * v, 0, None))
        higher = cap > depth
        depth = np.where(higher, cap, depth)
        albedo = np.where(higher, rng.uniform(0.45, 0.9), albedo)
    return _relief(depth, albedo, light)


def coin(light: Sequence[float], size: int = 256, seed: int = 0) -> ReliefScene:
    """A coin on a white ground: a disc of radius 0.3-0.4 of the frame whose raised rim (2-3 px) rings
    an embossed field of random bumps and dents (up to 2 px), its metal darker (albedo 0.45-0.6) than
    the ground (0.9)."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:size, 0:size].astype(np.float64)
    radius = rng.uniform(0.3, 0.4) * size
    centre = size / 2 + rng.uniform(-0.05, 0.05, 2) * size
    distance = np.hypot(rows - centre[0], cols - centre[1])
    inside = _smoothstep((radius - distance) / 1.5)
    rim = rng.uniform(2.0, 3.0) * np.exp(-((distance - radius + 4) ** 2) / 8.0)
    field = np.zeros((size, size))
    for _ in range(12):
        r0, c0 = centre + rng.uniform(-0.6, 0.6, 2) * radius
        sigma = rng.uniform(0.05, 0.15) * radius
        field += rng.uniform(-1, 2) * np.exp(-((rows - r0) ** 2 + (cols - c0) ** 2) / (2 * sigma**2))
    field = 2.0 * field / max(np.abs(field).max(), 1e-9)
    depth = inside * (1.0 + rim + np.clip(field, -1, 2) * (distance < radius - 8))
    albedo = 0.9 + (rng.uniform(0.45, 0.6) - 0.9) * inside
    return _relief(depth, albedo, light)


def bark(light: Sequence[float], size: int = 256, seed: int = 0) -> ReliefScene:
    """Bark: ridges running up the frame (noise smoothed 2-4 px across, 15-30 px along), 5-10 px from
    furrow to crest, the furrows darker (albedo 0.25 to 0.55 with the height)."""
    from scipy.ndimage import gaussian_filter  # only here: the add-on runs without scipy

    rng = np.random.default_rng(seed)
    noise = gaussian_filter(rng.standard_normal((size, size)), (rng.uniform(15, 30), rng.uniform(2, 4)), mode="wrap")
    ridges = np.tanh(1.5 * noise / noise.std())  # flat-ish crests, steep furrow walls
    depth = rng.uniform(5, 10) * (ridges - ridges.min()) / np.ptp(ridges)
    albedo = 0.25 + 0.3 * depth / depth.max()
    return _relief(depth, albedo, light)


RELIEFS = {"mortar_bricks": mortar_bricks, "pebbles": pebbles, "coin": coin, "bark": bark}
