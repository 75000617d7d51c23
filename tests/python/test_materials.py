"""shadecut.materials: the scanned material sets read in the camera frame, their split, and the
photographs and lights rendered from them."""

import shutil
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import materials

MATERIALS = Path(__file__).resolve().parents[3] / "shared" / "data" / "materials"


def write_codes(path: Path, codes: np.ndarray) -> None:
    """An 8-bit PNG holding exactly ``codes`` (a grey 128 everywhere: a height map saved as a normal map)."""
    import OpenImageIO as oiio

    buffer = oiio.ImageBuf(oiio.ImageSpec(codes.shape[1], codes.shape[0], 3, oiio.UINT8))
    buffer.set_pixels(oiio.ROI(), codes)
    assert buffer.write(str(path))


needs_materials = pytest.mark.skipif(not MATERIALS.is_dir(), reason=f"the scanned materials are not in {MATERIALS}")


def test_the_halves_split_the_set_without_overlap():
    assert not set(materials.TRAINING) & set(materials.TEST)
    assert len(materials.TRAINING) == len(materials.TEST) == 5


@needs_materials
def test_every_material_of_the_set_is_in_one_half():
    present = {p.name for p in MATERIALS.iterdir() if p.is_dir()}
    assert present == set(materials.TRAINING) | set(materials.TEST)


def test_lights_around_the_viewer_at_one_slant_the_first_from_the_top():
    lights = materials.lights_around(4, 40.0)
    np.testing.assert_allclose(np.linalg.norm(lights, axis=1), 1.0)
    np.testing.assert_allclose(np.degrees(np.arccos(lights[:, 2])), 40.0)
    np.testing.assert_allclose(lights[:, :2] / np.sin(np.radians(40.0)), [[0, 1], [-1, 0], [0, -1], [1, 0]], atol=1e-12)


@needs_materials
def test_a_material_reads_in_the_camera_frame():
    material = materials.load_material(MATERIALS / "Bricks061")
    assert material.albedo.shape == material.normals.shape == (*material.height.shape, 3)
    np.testing.assert_allclose(np.linalg.norm(material.normals, axis=-1), 1.0, atol=1e-5)
    # Higher is closer: the normals tilt against the height's slope (x right, y up = toward row 0).
    rows, cols = np.gradient(material.height.astype(np.float64))
    assert np.corrcoef(material.normals[..., 0].ravel(), -cols.ravel())[0, 1] > 0.5
    assert np.corrcoef(material.normals[..., 1].ravel(), rows.ravel())[0, 1] > 0.5
    assert 0.0 < material.albedo.min() and material.albedo.max() <= 1.0


@needs_materials
def test_lambertian_photographs_are_albedo_times_the_clipped_cosine():
    material = materials.load_material(MATERIALS / "Leather037")
    light = np.array([0.3, -0.2, 1.0])
    (photograph,) = materials.lambertian_photographs(material, [light])
    grey = shadecut.render(material.normals, light, 1.0)
    np.testing.assert_allclose(photograph, material.albedo * grey[..., None], rtol=1e-5, atol=1e-6)


@needs_materials
def test_a_relief_lit_from_one_side_photographs_as_its_inversion_lit_from_the_other():
    """Issue 46's light bound needs a prior on which way a relief stands: without cast shadows the
    photograph of a relief under L is, pixel for pixel, that of the relief turned inside out under
    (-L_x, -L_y, L_z), the light from the opposite side. Under the evaluation's four lights the two
    answers lie 2 x 40 = 80 degrees apart, so whatever one photograph's estimator answers, it is at
    least 40 degrees off for one of the two surfaces."""
    material = materials.load_material(MATERIALS / "Bricks061")
    inverted = materials.Material(material.name, material.albedo, material.normals * np.float32([-1, -1, 1]),
                                  1.0 - material.height)
    lights = materials.lights_around(4, 40.0)
    opposite = lights * [-1.0, -1.0, 1.0]
    np.testing.assert_allclose(opposite, lights[[2, 3, 0, 1]], atol=1e-12)  # the same four lights
    for photograph, of_inverse in zip(materials.lambertian_photographs(material, lights),
                                      materials.lambertian_photographs(inverted, opposite)):
        np.testing.assert_array_equal(photograph, of_inverse)
    np.testing.assert_allclose(np.degrees(np.arccos(np.sum(lights * opposite, axis=1))), 80.0)


@needs_materials
def test_cast_shadows_darken_the_rock_where_the_integrated_surface_hides_the_light():
    material = materials.load_material(MATERIALS / "Rock029")
    light = materials.lights_around(1, 60.0)[0]
    (plain,) = materials.lambertian_photographs(material, [light])
    (shadowed,) = materials.lambertian_photographs(material, [light], cast_shadows=True)
    darkened = (shadowed.sum(-1) == 0) & (plain.sum(-1) > 0)
    assert 0.01 < darkened.mean() < 0.5
    np.testing.assert_array_equal(shadowed[~darkened], plain[~darkened])
    # Lit from the top, a pixel in cast shadow lies below the surface toward the top (a smaller row).
    depth = shadecut.integrate(material.normals)
    rows, cols = np.nonzero(darkened)
    assert np.mean(depth[np.maximum(rows - 3, 0), cols] > depth[rows, cols]) > 0.8


@needs_materials
@pytest.mark.parametrize(
    "damage, message",
    [
        (lambda folder: (folder / "normal_gl.png").unlink(), "has no normal_gl.png"),
        (lambda folder: shadecut.save_image(folder / "color.png", np.ones((8, 8), np.float32)), "color.png is 8 x 8"),
        (lambda folder: write_codes(folder / "normal_gl.png", np.full((512, 512, 3), 128, np.uint8)), "no normal"),
    ],
)
def test_a_damaged_material_folder_is_refused_naming_the_file(tmp_path, damage, message):
    folder = tmp_path / "Bricks061"
    shutil.copytree(MATERIALS / "Bricks061", folder)
    damage(folder)
    with pytest.raises(ValueError, match=message):
        materials.load_material(folder)
