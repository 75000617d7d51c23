"""shadecut.evaluation.linear_relief (issue 46): Pentland's linear reading of a relief, on a relief of
known depth and on the scanned materials, where it is measured against the issue's bounds."""

import re
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut.evaluation.linear_relief import (INPUTS, SMOOTHNESSES, evaluate_linear_relief,
                                               linear_shape_from_shading, photograph_shading)
from shadecut.evaluation.materials import flat_normals
from test_materials import MATERIALS, needs_materials

REPO = Path(__file__).resolve().parents[2]


def shallow_relief(size: int = 96, seed: int = 1) -> np.ndarray:
    """Twelve Gaussian bumps and dents up to 2 pixels high (slopes up to 13 degrees), pixel units."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[:size, :size].astype(float)
    depth = np.zeros((size, size))
    for _ in range(12):
        r, c = rng.uniform(10, size - 10, 2)
        depth += rng.uniform(-2, 2) * np.exp(-((rows - r) ** 2 + (cols - c) ** 2) / (2 * 6.0**2))
    return depth


def normals_of(depth: np.ndarray) -> np.ndarray:
    return shadecut.normals_from_depth(depth.astype(np.float32), np.ones(depth.shape, bool))


@pytest.mark.parametrize("light", [(0.5, 0.3, 1.0), (-0.2, -0.6, 1.0)])
def test_a_shallow_relief_is_read_from_its_shading(light):
    truth = normals_of(shallow_relief())
    shading = np.clip(truth @ (np.array(light) / np.linalg.norm(light)), 0.0, None)
    flat = shadecut.angular_error(flat_normals(truth.shape), truth)
    first_order = shadecut.angular_error(normals_of(linear_shape_from_shading(shading, light, 0.001, iterations=0)), truth)
    read = linear_shape_from_shading(shading, light, 0.001)
    error = shadecut.angular_error(normals_of(read), truth)
    # Measured 0.41 / 0.48 deg against flat's 2.37, the first-order solution 1.03 / 0.82: the square
    # root taken from the last solution is what brings the rest.
    assert error < 0.25 * flat and error < 0.6 * first_order
    assert shadecut.angular_error(normals_of(-read), truth) > flat  # convex read as convex
    assert abs(read.mean()) < 1e-9


def test_the_photograph_is_scaled_so_that_its_median_reads_flat():
    light = np.array([0.0, 0.6, 0.8])
    photograph = np.random.default_rng(0).uniform(0.1, 0.5, (8, 10, 3))
    shading = photograph_shading(photograph, light * 3)
    assert np.median(shading) == pytest.approx(0.8)


@pytest.mark.parametrize("shading, light, smoothness, iterations", [
    (np.full((4, 4), np.nan), (0, 0, 1), 0.1, 3),
    (np.ones(16), (0, 0, 1), 0.1, 3),
    (np.ones((4, 4)), (0.3, 0, -1), 0.1, 3),
    (np.ones((4, 4)), (0, 0, 1), 0.0, 3),
    (np.ones((4, 4)), (0, 0, 1), 0.1, -1),
])
def test_bad_input_is_refused(shading, light, smoothness, iterations):
    with pytest.raises(ValueError, match="shadecut: "):
        linear_shape_from_shading(shading, light, smoothness, iterations)


@pytest.fixture(scope="module")
def measured():
    return evaluate_linear_relief(MATERIALS)


@needs_materials
def test_given_the_true_shading_the_linear_reading_meets_issue_46s_bounds_with_the_light_given(measured):
    """The oracle that places issue 46's gap: with the paint told from the relief perfectly, the linear
    reading is within 0.85 x flat and below flat on at least 5 of every 6 renders (the graph cut's
    reading of the same shading, results.md: 11.78 deg, 18 of 20)."""
    part = measured["inputs"]["true shading"]
    assert part["mean_deg"] <= 0.85 * measured["flat"]
    assert part["below_flat"] >= 5 / 6 * measured["renders"]


@needs_materials
def test_on_the_photograph_the_linear_reading_is_below_flat_on_every_render(measured):
    part = measured["inputs"]["photograph"]
    assert part["below_flat"] == measured["renders"]
    assert part["mean_deg"] > 0.85 * measured["flat"]  # issue 46's bound: the paint still stands between


@needs_materials
def test_the_results_table_is_this_measurement(measured):
    """docs/results.md's table is the output of scripts/measure_linear_relief.py: the same figures."""
    text = (REPO / "docs" / "results.md").read_text()
    for name in INPUTS:
        part = measured["inputs"][name]
        row = re.search(rf"^\| {name} \| ([\d.]+) \| ([\d.]+) \| (\d+) of (\d+) \|", text, re.MULTILINE)
        assert row, f"no row for {name} in results.md"
        assert float(row[1]) == part["smoothness"] and float(row[2]) == pytest.approx(part["mean_deg"], abs=0.006)
        assert (int(row[3]), int(row[4])) == (part["below_flat"], measured["renders"])
    assert set(SMOOTHNESSES) >= {measured["inputs"][name]["smoothness"] for name in INPUTS}
