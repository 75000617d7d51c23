"""What two photographs can give (issue 45: DiLiGenT's cat within 15 degrees, its reading figure within
25): bounds that hold every pixel the pair cannot decide (lit in fewer than two) at its true normal,
so each favours the route it measures.

Where a pixel is lit in both photographs, the ratio of its two intensities puts its normal on a circle,
n . (I_b S_a - I_a S_b) = 0, whatever its albedo; the albedo picks the point. Two ways to pick it:

- :func:`one_albedo_bound`: one albedo for the whole object (any value: a sweep over the quantiles of
  the pixels' least albedos). The pair's two cones then meet in two normals; the truth chooses between
  them, as no labelling can do better.
- :func:`circle_descent`: the point moved downhill on an energy over the whole object, started from the
  truth's nearest points on the circles: the paper's smoothness (the chords |n_p - n_q| between
  4-neighbours, its V_pq), plus, with ``albedo_weight``, the chords of the log albedo it implies (an
  albedo constant by parts). Where the descent leaves the truth, the energy's minima are elsewhere and
  no labelling that minimizes it lands near the truth.

``scripts/measure_photometric.py --two-photograph-bounds`` prints them (docs/results.md, "Two
photographs: the point on the circle").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .. import ReconstructOptions, angular_error
from ..imaging import luminance

# Numerical smoothing of |x| as sqrt(x^2 + eps), so that the descent has a gradient everywhere: for
# the chords of unit normals (0..2) and for those of the log albedo.
_CHORD_EPS = 1e-4
_LOG_ALBEDO_EPS = 1e-2
_LEAST_FACING = 1e-3  # n . (S_a + S_b) below this is taken as this: the log albedo stays finite


@dataclass
class PairCircles:
    """The circles two photographs leave."""

    mask: np.ndarray         # H x W bool: the object
    axis: np.ndarray         # H x W x 3 unit: where usable, the normal is perpendicular to it
    usable: np.ndarray       # H x W bool: lit in both (each at least the core's shadow fraction of the brighter)
    lights: np.ndarray       # 2 x 3 unit directions
    intensities: np.ndarray  # 2 x H x W luminance


def _unit(vectors: np.ndarray) -> np.ndarray:
    return vectors / np.maximum(np.linalg.norm(vectors, axis=-1, keepdims=True), 1e-12)


def pair_circles(photographs: Sequence[np.ndarray], lights: np.ndarray, mask: np.ndarray) -> PairCircles:
    """The circles of two photographs (H x W or H x W x 3 linear, read through LUMINANCE_WEIGHTS) lit
    from ``lights`` (2 x 3, any lengths), inside ``mask``; usable by the rule reconstruct applies
    (ReconstructOptions.photometric_shadow_fraction)."""
    if len(photographs) != 2 or np.shape(lights) != (2, 3):
        raise ValueError("two photographs and their two lights (2 x 3) are needed")
    grey = np.stack([luminance(photo) for photo in photographs])
    directions = _unit(np.asarray(lights, dtype=np.float64))
    axis = _unit(grey[1][..., None] * directions[0] - grey[0][..., None] * directions[1])
    fraction = ReconstructOptions().photometric_shadow_fraction
    brightest = grey.max(axis=0)
    usable = mask & (brightest > 0) & (grey >= fraction * brightest).all(axis=0)
    return PairCircles(mask, axis, usable, directions, grey)


def nearest_on_circles(normals: np.ndarray, circles: PairCircles) -> np.ndarray:
    """``normals`` (H x W x 3 unit) moved to the nearest point of their circles where usable."""
    on_plane = normals - np.sum(normals * circles.axis, axis=-1, keepdims=True) * circles.axis
    return np.where(circles.usable[..., None], _unit(on_plane), normals)


def one_albedo_bound(circles: PairCircles, truth: np.ndarray, scored: np.ndarray, steps: int = 41) -> tuple[float, float]:
    """The least mean angular error (degrees, over ``scored``) of one albedo for the whole object,
    each usable pixel given the better, by ``truth``, of the pair's two normals at that albedo; the
    other pixels are the truth's. Returns the error and the quantile of the pixels' least albedos
    (where the two cones touch) that gives it, out of ``steps`` from 0 to 1."""
    a, b = circles.lights
    cosine = float(a @ b)
    across = _unit(np.cross(a, b))
    across = across if across[2] >= 0 else -across
    grey_a, grey_b = circles.intensities
    # The part of n in the lights' plane at albedo 1; its length is the least albedo at which the cones meet.
    in_plane = ((grey_a - cosine * grey_b)[..., None] * a + (grey_b - cosine * grey_a)[..., None] * b) / (1.0 - cosine**2)
    least = np.linalg.norm(in_plane, axis=-1)[circles.usable]
    best = (np.inf, 0.0)
    for quantile in np.linspace(0.0, 1.0, steps):
        part = in_plane / np.quantile(least, quantile)
        height = np.sqrt(np.clip(1.0 - np.sum(part * part, axis=-1), 0.0, None))[..., None]
        first, second = _unit(part + height * across), _unit(part - height * across)
        nearer = np.where((np.sum(first * truth, -1) >= np.sum(second * truth, -1))[..., None], first, second)
        error = angular_error(np.where(circles.usable[..., None], nearer, truth).astype(np.float32), truth, scored)
        best = min(best, (error, float(quantile)))
    return best


def _smooth_lengths(differences: np.ndarray, eps: float) -> tuple[np.ndarray, np.ndarray]:
    """sqrt(|d|^2 + eps) of each row d of ``differences`` (N x D), and its derivative by d (N x D)."""
    lengths = np.sqrt(np.sum(differences**2, axis=-1) + eps)
    return lengths, differences / lengths[:, None]


@dataclass
class Descent:
    """Where circle_descent started and ended: mean angular errors (degrees) and energies."""

    error_before: float
    error_after: float
    energy_before: float
    energy_after: float
    iterations: int


class _CircleEnergy:
    """The energy of circle_descent as a function of the angle of each usable pixel on its circle."""

    def __init__(self, circles: PairCircles, held: np.ndarray, albedo_weight: float):
        rows, cols = circles.usable.shape
        self.held = held.reshape(-1, 3).astype(np.float64)
        self.pixels = np.flatnonzero(circles.usable)
        # An orthonormal pair (u, v) spanning each circle's plane: the normal is cos t u + sin t v.
        u = _unit(np.cross(circles.axis, np.array([0.0, 0.0, 1.0])))
        self.u = u.reshape(-1, 3)[self.pixels]
        self.v = np.cross(circles.axis, u).reshape(-1, 3)[self.pixels]
        firsts, seconds = [], []
        for down, right in ((0, 1), (1, 0)):
            both = circles.mask[:rows - down, :cols - right] & circles.mask[down:, right:]
            r, c = np.nonzero(both)
            firsts.append(r * cols + c)
            seconds.append((r + down) * cols + c + right)
        self.first, self.second = np.concatenate(firsts), np.concatenate(seconds)
        on_circles = circles.usable.ravel()
        self.albedo_pairs = on_circles[self.first] & on_circles[self.second]
        self.weight = albedo_weight
        self.light_sum = circles.lights.sum(axis=0)
        self.log_brightness = np.log(np.maximum(circles.intensities.sum(axis=0).ravel(), 1e-12))

    def angles_of(self, normals: np.ndarray) -> np.ndarray:
        flat = normals.reshape(-1, 3)[self.pixels]
        return np.arctan2(np.sum(flat * self.v, -1), np.sum(flat * self.u, -1))

    def normals(self, angles: np.ndarray) -> np.ndarray:
        field = self.held.copy()
        field[self.pixels] = np.cos(angles)[:, None] * self.u + np.sin(angles)[:, None] * self.v
        return field

    def __call__(self, angles: np.ndarray) -> tuple[float, np.ndarray]:
        field = self.normals(angles)
        lengths, slopes = _smooth_lengths(field[self.first] - field[self.second], _CHORD_EPS)
        by_normal = np.zeros_like(field)
        np.add.at(by_normal, self.first, slopes)
        np.add.at(by_normal, self.second, -slopes)
        turning = -np.sin(angles)[:, None] * self.u + np.cos(angles)[:, None] * self.v  # d n / d t
        energy, gradient = float(lengths.sum()), np.sum(by_normal[self.pixels] * turning, axis=-1)
        if self.weight:
            facing = np.maximum(field @ self.light_sum, _LEAST_FACING)
            log_albedo = self.log_brightness - np.log(facing)
            first, second = self.first[self.albedo_pairs], self.second[self.albedo_pairs]
            albedo_lengths, albedo_slopes = _smooth_lengths((log_albedo[first] - log_albedo[second])[:, None],
                                                            _LOG_ALBEDO_EPS)
            by_log_albedo = np.zeros(len(field))
            np.add.at(by_log_albedo, first, self.weight * albedo_slopes[:, 0])
            np.add.at(by_log_albedo, second, -self.weight * albedo_slopes[:, 0])
            energy += self.weight * float(albedo_lengths.sum())
            gradient += by_log_albedo[self.pixels] * -(turning @ self.light_sum) / facing[self.pixels]
        return energy, gradient


def circle_descent(circles: PairCircles, truth: np.ndarray, scored: np.ndarray, albedo_weight: float = 0.0,
                   iterations: int = 2000) -> Descent:
    """From the truth's nearest points on the circles, at most ``iterations`` L-BFGS steps down the
    energy sum of chords |n_p - n_q| + albedo_weight * sum of chords |log rho_p - log rho_q| (4-neighbours
    inside the mask, rho = (I_a + I_b) / n . (S_a + S_b), between usable pixels), the pixels off the
    circles held at ``truth``. Errors are mean angular errors over ``scored``."""
    from scipy.optimize import minimize  # only here: the add-on runs without scipy

    rows, cols = circles.usable.shape
    energy = _CircleEnergy(circles, truth, albedo_weight)
    start = energy.angles_of(nearest_on_circles(truth.astype(np.float64), circles))
    found = minimize(energy, start, jac=True, method="L-BFGS-B", options={"maxiter": iterations})

    def error(angles: np.ndarray) -> float:
        return angular_error(energy.normals(angles).reshape(rows, cols, 3).astype(np.float32), truth, scored)

    return Descent(error(start), error(found.x), energy(start)[0], float(found.fun), int(found.nit))
