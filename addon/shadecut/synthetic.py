"""Synthetic surfaces with exact ground truth, rendered by :func:`shadecut.render`.

Each function returns a :class:`Scene`: the Lambertian image, the exact camera-frame normals, the
depth (pixel units, larger = closer) and the mask, under the given light. They serve the tests, the
parameter tuning and the demo.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from .api import angular_error, erode_mask, normals_from_depth, render


@dataclass
class Scene:
    image: np.ndarray  # (H, W) float32, linear
    normals: np.ndarray  # (H, W, 3) float32, camera frame, 0 outside the mask
    depth: np.ndarray  # (H, W) float32, pixel units
    mask: np.ndarray  # (H, W) bool
    light: tuple  # direction toward the light, camera frame
    albedo: float = 1.0

    def mean_error(self, normals: np.ndarray, erode: int = 2) -> float:
        """Mean angular error (degrees) of ``normals`` on the mask eroded by ``erode`` pixels."""
        return angular_error(normals, self.normals, erode_mask(self.mask, erode))


def _pixel_grid(size: int) -> tuple[np.ndarray, np.ndarray]:
    """Camera-frame x (right) and y (up) of every pixel, origin at the image centre."""
    rows, cols = np.mgrid[0:size, 0:size].astype(np.float64)
    centre = (size - 1) / 2
    return cols - centre, centre - rows


def _scene(normals, depth, mask, light, albedo) -> Scene:
    normals = np.where(mask[..., None], normals, 0).astype(np.float32)
    image = render(normals, light, albedo, mask)
    return Scene(image, normals, np.where(mask, depth, 0).astype(np.float32), mask, tuple(light), albedo)


def lit_by_lamps(scene: Scene, lights, distance: float, albedo=1.0) -> list:
    """Lambertian photographs of ``scene`` under lamps near it, one per row of ``lights``: each lamp
    ``distance`` frame widths from the frame's centre at the surface's mean depth, along its light,
    its light falling off with the squared distance (the option ``light_distance``; docs/method.md,
    "Near lamps"). ``albedo``: a number or (H, W); a list of (H, W) float32."""
    rows, cols = scene.mask.shape
    r, c = np.mgrid[0:rows, 0:cols].astype(float)
    points = np.stack([c, -r, scene.depth - scene.depth[scene.mask].mean()], axis=-1)
    centre = np.array([(cols - 1) / 2, -(rows - 1) / 2, 0.0])
    reach = distance * cols
    photographs = []
    for light in np.asarray(lights, float):
        toward = centre + reach * light / np.linalg.norm(light) - points
        length = np.linalg.norm(toward, axis=-1)
        cosine = np.clip((scene.normals * toward).sum(-1) / length, 0.0, None)
        photographs.append((albedo * cosine * (reach / length) ** 2 * scene.mask).astype(np.float32))
    return photographs


def gradient_normals(dz_dx: np.ndarray, dz_dy: np.ndarray) -> np.ndarray:
    """Unit camera-frame normals normalize(-dz/dx, -dz/dy, 1) of a height field's slopes (x right,
    y up), (H, W, 3) float64."""
    normals = np.dstack([-dz_dx, -dz_dy, np.ones_like(dz_dx)])
    return normals / np.linalg.norm(normals, axis=2, keepdims=True)


def _height_field(depth, dz_dx, dz_dy, mask, light, albedo) -> Scene:
    return _scene(gradient_normals(dz_dx, dz_dy), depth - depth[mask].min(), mask, light, albedo)


def sphere(light: Sequence[float], size: int = 128, radius_fraction: float = 0.45, bowl: bool = False,
           albedo: float = 1.0) -> Scene:
    """A sphere of radius radius_fraction * size centred in the image; ``bowl``: its concave inside."""
    x, y = _pixel_grid(size)
    radius = radius_fraction * size
    height2 = radius**2 - x**2 - y**2
    mask = height2 > 0
    height = np.sqrt(np.maximum(height2, 0))
    sign = -1.0 if bowl else 1.0
    normals = np.dstack([sign * x, sign * y, height]) / radius
    return _scene(normals, radius - height if bowl else height, mask, light, albedo)


def torus(light: Sequence[float], size: int = 128, major: float = 0.3, minor: float = 0.14,
          albedo: float = 1.0) -> Scene:
    """A torus lying flat, seen from above: a tube of radius ``minor`` around a circle of radius
    ``major`` (units of the image size). Its outline is two circles, both occluding contours; its inner
    half is saddle-shaped."""
    x, y = _pixel_grid(size)
    radial = np.hypot(x, y)
    across = radial - major * size  # from the tube's centre line, outward
    height2 = (minor * size) ** 2 - across**2
    mask = height2 > 0
    height = np.sqrt(np.maximum(height2, 0))
    outward = across / np.maximum(radial, 1e-9)
    normals = np.dstack([outward * x, outward * y, height]) / (minor * size)
    return _scene(normals, height, mask, light, albedo)


def vase(light: Sequence[float], size: int = 128, albedo: float = 1.0) -> Scene:
    """A surface of revolution about the image's vertical axis, seen from the side: radius
    f(y) = size (0.22 + 0.09 cos(2.4 pi y / size)) (a belly and a neck) over |y| < 0.4 size; cut flat at
    both ends."""
    x, y = _pixel_grid(size)
    k = 2.4 * np.pi / size
    radius = size * (0.22 + 0.09 * np.cos(k * y))
    radius_slope = -size * 0.09 * k * np.sin(k * y)  # df/dy
    height2 = radius**2 - x**2
    mask = (height2 > 0) & (np.abs(y) < 0.4 * size)
    height = np.sqrt(np.maximum(height2, 0))
    # x^2 + z^2 = f(y)^2: the gradient (x, -f f', z) is the normal.
    normals = np.dstack([x, -radius * radius_slope, height])
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    return _scene(normals, height, mask, light, albedo)


def _read_features(path: Path) -> tuple[tuple[float, float, float, float], ...]:
    """The rows of a bump table (centre_x, centre_y, sigma, amplitude, a header line first)."""
    rows = path.read_text().split()[1:]
    return tuple(tuple(float(value) for value in row.split(",")) for row in rows)


# (centre x, centre y, sigma, amplitude) in units of the image size: three bumps and three dents on
# a 3 x 2 layout, apart enough that each keeps its own shape. Held in a file that the C++ tests
# (tests/cpp/test_support.cpp) read too, so that both build the same bump field.
BUMPS = _read_features(Path(__file__).with_name("synthetic_bumps.csv"))


def bumps(light: Sequence[float], size: int = 128, features=BUMPS, albedo: float = 1.0) -> Scene:
    """Gaussian bumps and dents on a plane, z = sum a exp(-|p - c|^2 / (2 s^2)), over the whole image.

    ``features``: (centre x, centre y, sigma, amplitude) tuples in units of the image size.
    """
    x, y = _pixel_grid(size)
    depth, dz_dx, dz_dy = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
    for cx, cy, sigma, amplitude in features:
        cx, cy, sigma, amplitude = cx * size, cy * size, sigma * size, amplitude * size
        g = amplitude * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * sigma**2))
        depth += g
        dz_dx -= g * (x - cx) / sigma**2
        dz_dy -= g * (y - cy) / sigma**2
    return _height_field(depth, dz_dx, dz_dy, np.ones(x.shape, bool), light, albedo)


def egg_crate(light: Sequence[float], size: int = 128, periods: float = 2.0, amplitude: float = 0.06,
              albedo: float = 1.0) -> Scene:
    """z = a size sin(2 pi f x / size) sin(2 pi f y / size): alternating bumps and dents, no flat part."""
    x, y = _pixel_grid(size)
    k = 2 * np.pi * periods / size
    a = amplitude * size
    depth = a * np.sin(k * x) * np.sin(k * y)
    return _height_field(depth, a * k * np.cos(k * x) * np.sin(k * y), a * k * np.sin(k * x) * np.cos(k * y),
                         np.ones(x.shape, bool), light, albedo)


def read_depth_text(path: str | os.PathLike, size: int = 256) -> np.ndarray:
    """A size x size depth map stored as one decimal number per line, row-major, row 0 at the top."""
    try:
        depth = np.loadtxt(path, dtype=np.float64)
    except (UnicodeDecodeError, ValueError) as error:  # a picture or another binary file given by mistake
        raise ValueError(f"shadecut: {path} is not a text file of numbers (one depth per line): {error}") from None
    if depth.size != size * size:
        raise ValueError(f"shadecut: {path} holds {depth.size} values, not {size} x {size}")
    return depth.reshape(size, size)


def mozart(path: str | os.PathLike, light: Sequence[float] = (1.0, 0.0, 1.0), albedo: float = 1.0) -> Scene:
    """The Mozart depth map (data/mozart/moz256.depth): mask depth > 0, normals by central differences."""
    depth = read_depth_text(path).astype(np.float32)
    mask = depth > 0
    return _scene(normals_from_depth(depth, mask), depth, mask, light, albedo)


def bricks(light: Sequence[float], size: int = 256, brick: tuple = (32, 12), mortar: float = 1.5, height: float = 4.0,
           bevel: float = 2.0, albedo: float = 0.7, albedo_noise: float = 0.05, seed: int = 0) -> Scene:
    """A brick wall filling the frame: running-bond bricks ``brick`` = (width, height) pixels standing
    ``height`` pixels above mortar grooves ``mortar`` pixels wide, their edges rounded over ``bevel``
    pixels; the albedo varies by +-``albedo_noise`` (uniform, per pixel) around ``albedo``. The image
    is rendered with that varying albedo; ``Scene.albedo`` is the mean."""
    rows, cols = np.mgrid[0:size, 0:size].astype(np.float64)
    width, course = brick
    shift = np.where((rows // course) % 2 == 1, width / 2, 0.0)
    # Distance to the nearest mortar line, horizontal or vertical, within the pixel's own brick.
    along = np.abs(((cols + shift) % width) - width / 2)
    across = np.abs((rows % course) - course / 2)
    distance = np.minimum(width / 2 - along, course / 2 - across) - mortar / 2
    ramp = np.clip(distance / bevel, 0.0, 1.0)
    depth = height * ramp * ramp * (3 - 2 * ramp)  # smoothstep: edges rounded, tops flat
    dz_drow, dz_dcol = np.gradient(depth)
    normals = gradient_normals(dz_dcol, -dz_drow)  # y is up: dz/dy = -dz/drow
    mask = np.ones((size, size), bool)
    variation = 1.0 + np.random.default_rng(seed).uniform(-albedo_noise, albedo_noise, (size, size))
    image = render(normals.astype(np.float32), light, 1.0, mask) * (albedo * variation).astype(np.float32)
    return Scene(image.astype(np.float32), normals.astype(np.float32), depth.astype(np.float32), mask, tuple(light),
                 albedo)


PAINTS = ("patches", "stripes", "text")
_SUPERSAMPLE = 4  # paint drawn at 4x and averaged: anti-aliased edges, as a camera sees them


def _paint_colours(rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` linear RGB paints of random hue, saturation 0.1-0.8 and value 0.35-1."""
    import colorsys

    return np.array([colorsys.hsv_to_rgb(rng.random(), rng.uniform(0.1, 0.8), rng.uniform(0.35, 1.0))
                     for _ in range(count)])


def _downsampled(big: np.ndarray, size: int) -> np.ndarray:
    return big[: size * _SUPERSAMPLE, : size * _SUPERSAMPLE].reshape(size, _SUPERSAMPLE, size, _SUPERSAMPLE, 3).mean(axis=(1, 3))


def paint(kind: str, size: int, seed: int) -> np.ndarray:
    """A (size, size, 3) linear RGB albedo in (0, 1]: ``"patches"`` (Voronoi cells of 8 paints),
    ``"stripes"`` (bands of 3 paints at a random angle and width) or ``"text"`` (dark words on a light
    ground, drawn by matplotlib), anti-aliased. The same seed gives the same paint."""
    rng = np.random.default_rng(seed)
    n = size * _SUPERSAMPLE
    y, x = (np.mgrid[0:n, 0:n] + 0.5) / n
    if kind == "patches":
        seeds, colours = rng.random((8, 2)), _paint_colours(rng, 8)
        nearest = ((x[..., None] - seeds[:, 0]) ** 2 + (y[..., None] - seeds[:, 1]) ** 2).argmin(axis=2)
        return _downsampled(colours[nearest], size)
    if kind == "stripes":
        angle, width, colours = rng.uniform(0, np.pi), rng.uniform(0.06, 0.15), _paint_colours(rng, 3)
        band = np.floor((x * np.cos(angle) + y * np.sin(angle)) / width).astype(int) % 3
        return _downsampled(colours[band], size)
    if kind == "text":
        return _text_paint(size, rng)
    raise ValueError(f"shadecut: unknown paint {kind!r}; expected one of {PAINTS}")


def _text_paint(size: int, rng: np.random.Generator) -> np.ndarray:
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # only here: the add-on runs without it
    from matplotlib.figure import Figure

    n = size * _SUPERSAMPLE
    figure = Figure(figsize=(1, 1), dpi=n)
    FigureCanvasAgg(figure)
    axes = figure.add_axes([0, 0, 1, 1])
    axes.axis("off")
    ground, ink = _paint_colours(rng, 2)
    figure.patch.set_facecolor(np.clip(ground + 0.3, 0, 1))
    words = ("SHADE", "CUT", "PAINT", "GRAPH", "LIGHT", "ALBEDO", "ZEBRA", "PRINT")
    for row in range(4):
        axes.text(rng.uniform(0.0, 0.2), 0.15 + 0.22 * row, " ".join(rng.choice(words, 2)), color=ink * 0.5,
                  fontsize=size * 0.09, fontweight="bold", transform=axes.transAxes)
    figure.canvas.draw()
    encoded = np.asarray(figure.canvas.buffer_rgba())[..., :3].astype(np.float64) / 255.0
    return _downsampled(encoded**2.2, size)  # the canvas is sRGB-like: back to linear


def painted(scene: Scene, kind: str, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``scene`` (rendered with albedo 1) painted with :func:`paint`: (the colour image (H, W, 3), the
    true albedo (H, W, 3)), both float32; the shading is the scene's, the light white."""
    albedo = paint(kind, scene.image.shape[0], seed)
    colour = albedo * (scene.image / scene.albedo)[..., None]
    return colour.astype(np.float32), albedo.astype(np.float32)
