"""method="pentland" and shadecut.evaluation.linear_relief (issue 46): the linear reading of a relief, on
a relief of known depth and on the scanned materials, where it is measured against the issue's bounds."""

import re
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut.evaluation.linear_relief import INPUTS, SMOOTHNESSES, evaluate_linear_relief
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


@pytest.mark.parametrize("light", [(0.5, 0.3, 1.0), (-0.2, -0.6, 1.0)])
def test_a_shallow_relief_is_read_from_its_shading(light):
    mask = np.ones((96, 96), bool)
    truth = shadecut.normals_from_depth(shallow_relief().astype(np.float32), mask)
    image = (0.7 * np.clip(truth @ (np.array(light) / np.linalg.norm(light)), 0.0, None)).astype(np.float32)
    flat = shadecut.angular_error(flat_normals(truth.shape), truth)

    def read(**options):
        return shadecut.reconstruct(image, light, mask, 0.7, method="pentland", smoothness=0.001, **options)

    result = read()
    error = shadecut.angular_error(result.normals, truth)
    # Measured 0.41 / 0.48 deg against flat's 2.37, the first-order solve 1.03 / 0.82.
    assert error < 0.25 * flat and error < 0.6 * shadecut.angular_error(read(iterations=1).normals, truth)
    assert result.stats.iterations == shadecut.method_defaults("pentland").iterations
    assert set(result.stats.seconds) >= {"pentland", "integration", "total"}
    # As a relief, its forms are kept: the same normals but for the carrier's flattening.
    relief = read(scene="relief")
    assert np.isnan(relief.stats.detail_size)
    assert shadecut.angular_error(relief.normals, truth) < 0.25 * flat


@pytest.mark.parametrize("options, word", [({"smoothness": 0.0}, "smoothness"), ({"iterations": 0}, "iteration")])
def test_bad_options_are_refused(options, word):
    with pytest.raises(ValueError, match=word):
        shadecut.reconstruct(np.full((8, 8), 0.5, np.float32), (0.3, 0.2, 1.0), None, 1.0, method="pentland", **options)


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
