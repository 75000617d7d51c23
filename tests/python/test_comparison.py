"""Issue 3's acceptance: the paper's comparison methods and the light estimators, through the Python API."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

ESTIMATION_LIGHTS = [(1.0, 0.0, 1.0), (1.5, 0.866, 1.0), (-0.939, 1.867, 1.0), (0.3, -0.2, 1.0)]


def slant_tilt(light):
    x, y, z = np.asarray(light, float) / np.linalg.norm(light)
    return np.degrees(np.arccos(z)), np.degrees(np.arctan2(y, x))


def error_of(scene, method, **options):
    result = shadecut.reconstruct(scene.image, scene.light, scene.mask, scene.albedo, method=method, **options)
    return scene.mean_error(result.normals), result


def flat_plane_error(scene) -> float:
    flat = np.zeros(scene.normals.shape, np.float32)
    flat[..., 2] = 1.0
    return scene.mean_error(flat)


# Lee & Rosenfeld's sphere model leaves out the attached shadow, so its slant falls short of oblique
# lights (README, "Light and albedo estimation"): these are its measured bounds for the two lights
# where the 10 degrees / 10 % are not reached. Its tilt meets the 5 degrees everywhere.
LEE_ROSENFELD_REACHES = {(1.5, 0.866, 1.0): (15.0, 0.14), (-0.939, 1.867, 1.0): (17.0, 0.17)}


# The estimators that model a sphere; "relief" models a relief (tests/python/test_relief.py).
SPHERE_ESTIMATORS = ("lee_rosenfeld", "zheng_chellappa")


@pytest.mark.parametrize("method", SPHERE_ESTIMATORS)
@pytest.mark.parametrize("light", ESTIMATION_LIGHTS)
def test_light_and_albedo_estimated_on_spheres(light, method):
    sphere = synthetic.sphere(light, albedo=0.8)
    estimate, albedo = shadecut.estimate_light(sphere.image, sphere.mask, method)
    (slant, tilt), (true_slant, true_tilt) = slant_tilt(estimate), slant_tilt(light)
    tilt_error = abs((tilt - true_tilt + 180.0) % 360.0 - 180.0)
    print(f"{method} {light}: slant {slant:.1f} (true {true_slant:.1f}), tilt {tilt:.1f} (true {true_tilt:.1f}), "
          f"albedo {albedo:.3f} (true 0.8)")
    assert estimate.shape == (3,) and np.linalg.norm(estimate) == pytest.approx(1.0)
    assert tilt_error <= 5.0
    slant_bound, albedo_bound = (10.0, 0.10)
    if method == "lee_rosenfeld" and light in LEE_ROSENFELD_REACHES:
        slant_bound, albedo_bound = LEE_ROSENFELD_REACHES[light]
        assert slant < true_slant - 10.0 and albedo < 0.8  # the bias is the known one, not noise
    assert abs(slant - true_slant) <= slant_bound
    assert abs(albedo - 0.8) <= albedo_bound * 0.8


def test_estimate_light_rejects_bad_input():
    with pytest.raises(ValueError, match="dark everywhere"):
        shadecut.estimate_light(np.zeros((8, 8), np.float32))
    with pytest.raises(ValueError, match="unknown light estimator"):
        shadecut.estimate_light(np.ones((8, 8), np.float32), method="pentland")
    with pytest.raises(ValueError, match="mask is"):
        shadecut.estimate_light(np.ones((8, 8), np.float32), np.ones((7, 8), bool))


def test_brooks_horn_and_tsai_shah_on_the_sphere():
    sphere = synthetic.sphere((1.0, 0.0, 1.0))
    errors = {m: error_of(sphere, m)[0] for m in ("graphcut", "brooks_horn", "tsai_shah")}
    print("sphere (1, 0, 1): " + ", ".join(f"{m} {e:.2f} deg" for m, e in errors.items()))
    assert errors["brooks_horn"] < 15.0
    assert errors["graphcut"] <= 0.5 * min(errors["brooks_horn"], errors["tsai_shah"])


@pytest.mark.xfail(strict=True, reason=(
    "Tsai & Shah's per-pixel Newton steps from a flat start build the sphere's depth far too slowly and "
    "diverge when iterated longer: no number of sweeps beats a flat plane there (next test; README, Results)."))
def test_tsai_shah_recovers_the_sphere():
    sphere = synthetic.sphere((1.0, 0.0, 1.0))
    assert error_of(sphere, "tsai_shah")[0] < 15.0


def test_tsai_shah_does_no_better_than_a_flat_plane_on_the_sphere_whatever_the_sweeps():
    """Why the bound above is out of reach: not a matter of the tuned number of sweeps."""
    sphere = synthetic.sphere((1.0, 0.0, 1.0))
    flat_error = flat_plane_error(sphere)
    errors = {sweeps: error_of(sphere, "tsai_shah", iterations=sweeps)[0] for sweeps in (1, 2, 5, 10, 20, 50, 100, 500)}
    print(f"sphere (1, 0, 1), flat plane {flat_error:.2f} deg; tsai_shah after n sweeps: "
          + ", ".join(f"{n}: {e:.2f}" for n, e in errors.items()))
    assert all(error > flat_error for error in errors.values())


def test_upwind_the_viscosity_baseline():
    """What a user might pick instead of the paper's methods: ahead of a flat plane everywhere, far
    ahead of the paper's energy on the bumps and dents (where that energy's minimum is a wrong
    surface), behind graphcut where a silhouette surrounds a shadowed side (the sphere)."""
    scenes = {"sphere": synthetic.sphere((1.0, 0.0, 1.0)), "bumps": synthetic.bumps((1.0, 0.0, 1.0))}
    errors = {name: {"paper's energy": error_of(scene, "graphcut", viscosity_weight=0.0)[0],
                     **{m: error_of(scene, m)[0] for m in ("graphcut", "tsai_shah", "upwind")}}
              for name, scene in scenes.items()}
    for name, scene in scenes.items():
        print(f"{name} (1, 0, 1): flat plane {flat_plane_error(scene):.2f} deg, "
              + ", ".join(f"{m} {e:.2f} deg" for m, e in errors[name].items()))
    assert errors["sphere"]["upwind"] < 15.0  # measured 12.08
    assert errors["sphere"]["upwind"] < 0.5 * min(flat_plane_error(scenes["sphere"]), errors["sphere"]["tsai_shah"])
    assert errors["sphere"]["graphcut"] < errors["sphere"]["upwind"]
    assert errors["bumps"]["upwind"] < 3.0  # measured 1.43
    assert errors["bumps"]["upwind"] < 0.25 * min(flat_plane_error(scenes["bumps"]), errors["bumps"]["paper's energy"])


def test_upwind_settles_where_the_image_reaches_the_albedo():
    scene = synthetic.sphere((0.4, 0.3, 1.0), 96, radius_fraction=0.45)
    assert (scene.image[scene.mask] > 0.99).sum() > 100
    for rounds in (None, 100):  # the method's tuned rounds, and many more
        result = shadecut.reconstruct(scene.image, scene.light, scene.mask, 0.99, method="upwind", iterations=rounds)
        print(f"upwind, albedo 0.99, rounds {rounds or 'default'}: {scene.mean_error(result.normals):.2f} deg")
        assert scene.mean_error(result.normals) < 10.0


def test_mozart_every_method_side_by_side(mozart_path):
    mozart = synthetic.mozart(mozart_path, (1.0, 0.0, 1.0))
    errors = {m: error_of(mozart, m)[0] for m in shadecut.METHODS}
    print("Mozart, light (1, 0, 1), true light and albedo, mean angular error on the mask eroded by 2 px: "
          + ", ".join(f"{m} {e:.2f} deg" for m, e in errors.items()))
    assert set(errors) == {"graphcut", "graphcut_two", "lee_rosenfeld", "brooks_horn", "tsai_shah", "upwind", "pentland"}
    assert errors["graphcut"] < errors["lee_rosenfeld"]
    assert errors["graphcut"] < errors["tsai_shah"]
    assert errors["graphcut"] < errors["upwind"]  # issue 15: graphcut below the modern baseline here
    estimated = {m: mozart.mean_error(shadecut.reconstruct(mozart.image, None, mozart.mask, method=m).normals)
                 for m in shadecut.METHODS}
    print("Mozart, light and albedo estimated (reconstruct's default, zheng_chellappa): "
          + ", ".join(f"{m} {e:.2f} deg" for m, e in estimated.items()))


def test_mozart_with_the_estimated_light(mozart_path):
    mozart = synthetic.mozart(mozart_path, (1.0, 0.0, 1.0))
    true_error, _ = error_of(mozart, "graphcut")
    for light_method in SPHERE_ESTIMATORS:
        result = shadecut.reconstruct(mozart.image, None, mozart.mask, light_method=light_method)
        slant, tilt = slant_tilt(result.light)
        print(f"Mozart, graphcut: true light {true_error:.2f} deg; light estimated by {light_method} "
              f"(slant {slant:.1f}, tilt {tilt:.1f}, albedo {result.albedo:.3f}; true 45.0, 0.0, 1.000): "
              f"{mozart.mean_error(result.normals):.2f} deg")
        assert result.stats.light_estimated


def test_reconstruct_without_a_light_on_the_sphere():
    sphere = synthetic.sphere((1.0, 0.0, 1.0), albedo=0.8)
    given = shadecut.reconstruct(sphere.image, sphere.light, sphere.mask)
    estimated = shadecut.reconstruct(sphere.image, mask=sphere.mask)
    given_error, estimated_error = sphere.mean_error(given.normals), sphere.mean_error(estimated.normals)
    print(f"sphere (1, 0, 1), graphcut: true light {given_error:.2f} deg, estimated light {estimated_error:.2f} deg")
    assert estimated_error <= given_error + 5.0
    assert not given.stats.light_estimated and estimated.stats.light_estimated
    # estimate_light's default estimator is reconstruct's.
    expected, albedo = shadecut.estimate_light(sphere.image, sphere.mask)
    np.testing.assert_allclose(estimated.light, expected, atol=1e-9)
    assert estimated.albedo == pytest.approx(albedo)
    # A given albedo is kept; only the light is estimated.
    assert shadecut.reconstruct(sphere.image, mask=sphere.mask, albedo=0.5).albedo == 0.5


@pytest.mark.parametrize("method", shadecut.METHODS)
def test_every_method_reports_iterations_and_seconds_and_can_be_cancelled(method):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=32)
    stages = []
    result = shadecut.reconstruct(sphere.image, sphere.light, sphere.mask, method=method,
                                  progress=lambda f, s: stages.append((f, s)))
    fractions = [f for f, _ in stages]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    assert result.stats.seconds["total"] > 0.0
    assert (result.stats.iterations > 0) == (method != "lee_rosenfeld")
    with pytest.raises(shadecut.Cancelled):
        shadecut.reconstruct(sphere.image, sphere.light, sphere.mask, method=method, progress=lambda f, s: False)
    with pytest.raises(ValueError, match="dark everywhere"):
        shadecut.reconstruct(np.zeros((16, 16), np.float32), sphere.light, method=method)
    with pytest.raises(ValueError, match="horizon"):
        shadecut.reconstruct(sphere.image, (1.0, 0.0, -1.0), method=method)


@pytest.mark.parametrize("options, message", [
    ({"method": "brooks_horn", "smoothness": 0.0}, "smoothness"),
    ({"method": "brooks_horn", "iterations": 0}, "iterations"),
    ({"method": "brooks_horn", "tolerance": -1.0}, "tolerance"),
    ({"method": "tsai_shah", "iterations": -3}, "iterations"),
    ({"light": None, "light_method": "magic"}, "unknown light estimator"),
])
def test_method_parameters_are_checked(options, message):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=16)
    options = {"light": sphere.light, **options}
    with pytest.raises(ValueError, match=message):
        shadecut.reconstruct(sphere.image, mask=sphere.mask, **options)


def noisy_sphere(size=48):
    """A sphere with noise, which no sweep count solves exactly: the methods never stop on their own."""
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=size)
    noise = np.random.default_rng(3).normal(0.0, 0.02, sphere.image.shape).astype(np.float32)
    return sphere, np.clip(sphere.image + noise, 0.0, None)


@pytest.mark.parametrize("method", ["tsai_shah", "brooks_horn"])
def test_an_iterative_method_answers_a_cancel_within_a_fraction_of_a_second(method):
    """They reported after every hundredth of their sweeps: with 10^9 sweeps a cancel waited minutes.
    Now they report every 0.1 s of work."""
    sphere, image = noisy_sphere()
    start = time.monotonic()
    answers = []

    def progress(fraction, stage):
        answers.append(time.monotonic() - start)
        return answers[-1] < 0.3

    with pytest.raises(shadecut.Cancelled):
        shadecut.reconstruct(image, sphere.light, sphere.mask, method=method, iterations=10**9, tolerance=0.0,
                             progress=progress)
    assert time.monotonic() - start < 1.5
    assert len(answers) >= 3  # reports while it runs, not only at its end


CTRL_C_CHILD = """
import sys
import numpy as np
import shadecut
from shadecut import synthetic
sphere = synthetic.sphere((1.0, 0.0, 1.0), size=48)
image = sphere.image + np.random.default_rng(3).random(sphere.image.shape, dtype=np.float32) * 0.02
print("started", flush=True)
shadecut.reconstruct(image, sphere.light, sphere.mask, method=sys.argv[1], iterations=10**9, tolerance=0.0)
"""


@pytest.mark.parametrize("method", ["tsai_shah", "brooks_horn"])
def test_ctrl_c_stops_a_long_call_without_a_progress_callback(method):
    """Python handles Ctrl+C between bytecodes only; the call now asks for it at its progress reports."""
    child = subprocess.Popen([sys.executable, "-c", CTRL_C_CHILD, method], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONPATH": str(Path(shadecut.__file__).parents[1])})
    try:
        assert child.stdout.readline() == "started\n"
        time.sleep(0.5)
        interrupted = time.monotonic()
        child.send_signal(signal.SIGINT)
        _, stderr = child.communicate(timeout=30)
    finally:
        child.kill()  # a call that ignores Ctrl+C would otherwise sweep on after the test
    assert "KeyboardInterrupt" in stderr, stderr
    assert time.monotonic() - interrupted < 2.0
