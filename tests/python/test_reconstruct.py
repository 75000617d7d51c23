"""The acceptance figures of the core, through the Python API, on images made by shadecut.render."""

import threading

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

PAPER_LIGHTS = [(1.0, 0.0, 1.0), (1.5, 0.866, 1.0), (-0.939, 1.867, 1.0)]


def error_of(scene, method, **options):
    """The paper's setting: light and albedo known."""
    result = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo, method=method, **options)
    return scene.mean_error(result.normals), result


@pytest.mark.parametrize("light", PAPER_LIGHTS)
def test_graphcut_recovers_the_sphere(light):
    error, result = error_of(synthetic.sphere(light), "graphcut")
    print(f"sphere {light}: graphcut {error:.2f} deg")
    assert error <= 3.0
    assert result.normals.shape == (128, 128, 3) and result.normals.dtype == np.float32
    assert result.depth.shape == (128, 128) and result.mask.dtype == bool
    np.testing.assert_allclose(np.linalg.norm(result.light), 1.0)


def test_graphcut_recovers_the_bowl_where_the_convex_assumption_fails():
    bowl = synthetic.sphere((1.0, 0.0, 1.0), bowl=True)
    graphcut, _ = error_of(bowl, "graphcut")
    local, _ = error_of(bowl, "lee_rosenfeld")
    print(f"bowl: graphcut {graphcut:.2f} deg, lee_rosenfeld {local:.2f} deg")
    assert graphcut <= 5.0
    assert local > 60.0


def test_graphcut_beats_the_local_method_on_bumps_and_dents():
    """Under this light the paper's energy has its minimum at a wrong surface (the labelling nearest
    the truth costs 1.6 x more: GlobalStep.OnTheTestBumpsTheTruthCostsMoreThanTheLabellingFound); the
    labelling pulled toward the viscosity solution explains the image better and is kept."""
    bumps = synthetic.bumps((1.0, 0.0, 1.0))
    graphcut, result = error_of(bumps, "graphcut")
    paper, _ = error_of(bumps, "graphcut", viscosity_weight=0.0)
    local, _ = error_of(bumps, "lee_rosenfeld")
    print(f"bumps: graphcut {graphcut:.2f} deg (the paper's energy alone {paper:.2f}), lee_rosenfeld {local:.2f} deg")
    assert result.stats.pulled_kept and result.stats.pulled_residual < result.stats.paper_residual
    assert graphcut <= 0.75 * local


@pytest.mark.parametrize("light", PAPER_LIGHTS[1:])
def test_graphcut_beats_the_local_method_on_the_same_bumps_under_the_other_lights(light):
    """The bound of the test above holds on the same surface when the light's tilt does not run along
    its rows of alternating bumps and dents."""
    bumps = synthetic.bumps(light)
    graphcut, _ = error_of(bumps, "graphcut")
    local, _ = error_of(bumps, "lee_rosenfeld")
    print(f"bumps {light}: graphcut {graphcut:.2f} deg, lee_rosenfeld {local:.2f} deg")
    assert graphcut <= 0.75 * local


def test_mozart_graphcut_against_lee_rosenfeld(mozart_path):
    mozart = synthetic.mozart(mozart_path, (1.0, 0.0, 1.0))
    errors = {m: error_of(mozart, m)[0] for m in ("graphcut", "graphcut_two", "lee_rosenfeld")}
    print("Mozart, light (1, 0, 1), mean angular error on the mask eroded by 2 px: "
          + ", ".join(f"{m} {e:.2f} deg" for m, e in errors.items()))
    assert errors["graphcut"] <= 0.7 * errors["lee_rosenfeld"]


def test_energy_never_rises_and_is_recorded_per_cycle(mozart_path):
    mozart = synthetic.mozart(mozart_path)
    for method in ("graphcut", "graphcut_two"):
        stats = shadecut.reconstruct(mozart.image, mozart.light, mozart.mask, method=method).stats
        energy = stats.energy_per_cycle
        assert len(energy) == stats.cycles + 1
        assert all(b <= a + 1e-9 for a, b in zip(energy, energy[1:]))
        assert set(stats.seconds) >= {"local", "energy", "graphcut", "integration", "total"}


def test_a_tolerance_stops_earlier_at_the_same_accuracy(mozart_path):
    mozart = synthetic.mozart(mozart_path)
    # One level, so that the cycles counted are all of the run's.
    exact_error, exact = error_of(mozart, "graphcut", coarse_to_fine_band=-1)
    loose_error, loose = error_of(mozart, "graphcut", tolerance=1e-2, coarse_to_fine_band=-1)
    assert loose.stats.cycles < exact.stats.cycles
    assert loose.stats.energy_per_cycle[-1] <= exact.stats.energy_per_cycle[0]
    assert abs(loose_error - exact_error) < 0.5
    with pytest.raises(ValueError, match="tolerance"):
        error_of(mozart, "graphcut", tolerance=-1.0)


@pytest.mark.parametrize("scene", ["sphere", "bumps"])
def test_coarse_to_fine_reaches_the_exact_minimum_s_accuracy(scene):
    """Of the paper's energy: neither the outline's term nor the viscosity pull (a second energy)."""
    truth = getattr(synthetic, scene)((1.0, 0.0, 1.0), size=256)
    paper = {"contour_weight": 0.0, "viscosity_weight": 0.0}
    exact_error, exact = error_of(truth, "graphcut", coarse_to_fine_band=-1, **paper)
    everywhere_error, everywhere = error_of(truth, "graphcut", coarse_to_fine_radius=-1, **paper)
    fast_error, fast = error_of(truth, "graphcut", **paper)
    energy = {name: run.stats.energy_per_cycle[-1] for name, run in
              (("exact", exact), ("band everywhere", everywhere), ("default", fast))}
    print(f"{scene} 256 px: exact alpha-expansion {exact_error:.2f} deg; band everywhere {everywhere_error:.2f} deg; "
          f"default (band near the coarse jumps) {fast_error:.2f} deg; energies {energy}")
    assert exact.stats.levels == 1 and fast.stats.levels == 3  # 256 -> 128 -> 64 px
    # Coarse to fine must not lose the exact minimum's accuracy. It may beat it: the pixels that keep
    # their coarse label take the coarse level's tilts interpolated, finer than a label step (issue
    # 29), which puts the default at 0.96 deg on the sphere against the exact run's 1.34.
    assert fast_error <= exact_error + 0.25
    assert abs(everywhere_error - exact_error) <= 0.25
    # Local minima of the banded moves: with the band everywhere measured 1.8% (sphere) and 0.9%
    # (bumps) above the exact one; with the band only at the coarse jumps 4.3% and 1.0%, the smooth
    # parts keeping the coarse labels' one-step quantisation, which the snapping to the local
    # candidates removes from the normals.
    assert energy["band everywhere"] <= 1.03 * energy["exact"]
    assert energy["default"] <= 1.05 * energy["exact"]


def test_the_residual_of_one_photograph_is_how_far_the_result_renders_from_it():
    """|image - albedo_map max(0, n . S)| of the result's normals, 0 outside the mask."""
    scene = synthetic.sphere((1.0, 0.0, 1.0))
    result = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo)
    rendered = result.albedo_map * np.clip(result.normals @ result.light, 0.0, None)
    np.testing.assert_allclose(result.residual, np.abs(scene.image - rendered) * scene.mask, atol=1e-6)
    assert result.residual.dtype == np.float32 and not result.residual[~scene.mask].any()


def test_the_residual_shows_a_stain_a_relief_cannot_explain():
    """A square of paint at half the albedo on a brick wall: no relief renders that dark a patch, so
    it stands out in the residual for every relief method that reads it."""
    wall = synthetic.bricks((0.5, 0.3, 1.0), size=256, albedo_noise=0.0)
    image, stain = wall.image.copy(), (slice(100, 140), slice(100, 140))
    image[stain] *= 0.5
    elsewhere = np.ones(image.shape, dtype=bool)
    elsewhere[stain] = False
    for method in ("graphcut", "pentland"):
        residual = shadecut.reconstruct(image, wall.light, scene="relief", method=method).residual
        print(f"{method}: median residual {np.median(residual[stain]):.3f} on the stain, "
              f"{np.median(residual[elsewhere]):.3f} elsewhere")
        assert np.median(residual[stain]) > 4.0 * np.median(residual[elsewhere])


def test_albedo_is_estimated_from_the_brightest_pixels():
    sphere = synthetic.sphere((1.0, 0.0, 1.0), albedo=0.7)
    result = shadecut.reconstruct(sphere.image, sphere.light, sphere.mask)
    assert result.albedo == pytest.approx(0.7, rel=1e-3)
    assert sphere.mean_error(result.normals) <= 3.0


def test_progress_reports_stages_and_false_cancels():
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=48)
    seen = []
    shadecut.reconstruct(sphere.image, sphere.light, sphere.mask, progress=lambda f, s: seen.append((f, s)))
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    assert {s for _, s in seen} == {"upwind", "local", "energy", "graphcut", "integration"}
    with pytest.raises(shadecut.Cancelled):
        shadecut.reconstruct(sphere.image, sphere.light, sphere.mask, progress=lambda f, s: s != "graphcut")


def test_the_paint_passes_report_one_progress_from_0_to_1():
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=48)
    seen = []
    shadecut.reconstruct(sphere.image, sphere.light, sphere.mask, albedo_method="retinex", retinex_passes=3,
                         progress=lambda f, s: seen.append((f, s)))
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0
    assert [s for _, s in seen].count("albedo") >= 3  # each pass reads the paint


def test_a_progress_callback_that_raises_propagates_its_exception():
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=32)

    def broken(fraction, stage):
        raise KeyError("from the callback")

    with pytest.raises(KeyError):
        shadecut.reconstruct(sphere.image, sphere.light, sphere.mask, progress=broken)


def test_the_native_call_releases_the_gil(mozart_path):
    mozart = synthetic.mozart(mozart_path)
    ticks = 0
    done = threading.Event()

    def work():
        shadecut.reconstruct(mozart.image, mozart.light, mozart.mask)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    while not done.wait(0.001):
        ticks += 1  # runs only while the reconstruction does not hold the GIL
    worker.join()
    assert ticks > 10
