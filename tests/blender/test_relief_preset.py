"""Subject = Relief on a brick-wall image, through the add-on's operator as an artist runs it: the
result is a flat slab (height range at most 5% of its width), and Subject = Object is not flatter.

The image is shadecut.synthetic's brick wall (running bond, 4 px deep mortar grooves, +-5% albedo
noise), saved as a 16-bit sRGB PNG and loaded as the add-on's input; every other setting is the
add-on's default (light estimated, for a relief by the relief estimator). The true wall's relief
is 4 px over the image's width (1.6% at 256 px), so a faithful relief keeps well inside the bound;
what the bound catches is the slab bending or tilting as a whole.
"""

import bpy
import numpy as np
import pytest

import shadecut
from shadecut import synthetic

MAX_HEIGHT_FRACTION = 0.05

# (image size, light). 256 is the synthetic wall's own size, 512 a small photograph's.
CASES = [
    pytest.param(256, (0.6, 0.3, 1.0), id="256px-light-right"),
    pytest.param(256, (0.2, -0.7, 1.0), id="256px-light-below"),
    pytest.param(256, (-0.5, 0.4, 1.0), id="256px-light-upper-left"),
    pytest.param(512, (-0.5, 0.4, 1.0), id="512px-light-upper-left"),
    pytest.param(128, (0.6, 0.3, 1.0), id="128px-light-right"),
]


@pytest.fixture
def addon():
    shadecut.register()
    yield bpy.context.scene.shadecut
    shadecut.unregister()


def bricks_image(tmp_path, size, light):
    path = tmp_path / f"bricks_{size}.png"
    shadecut.save_image(path, synthetic.bricks(light, size=size).image)
    return bpy.data.images.load(str(path))


def reconstructed_extent(settings, subject: str) -> tuple[float, float]:
    """Width (x extent) and height range (z extent), in scene units, of the result object of one click."""
    settings.scene = subject
    before = set(bpy.data.objects)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    (result,) = set(bpy.data.objects) - before
    co = np.empty(3 * len(result.data.vertices), np.float32)
    result.data.vertices.foreach_get("co", co)
    matrix = np.array(result.matrix_world)
    world = co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]
    return float(np.ptp(world[:, 0])), float(np.ptp(world[:, 2]))


@pytest.mark.parametrize("size, light", CASES)
def test_relief_gives_a_flat_slab(addon, tmp_path, size, light):
    addon.image = bricks_image(tmp_path, size, light)
    width, height = reconstructed_extent(addon, "relief")
    print(f"Relief, {size} px, light {light}: height range {height:.4f} over width {width:.3f} "
          f"= {height / width:.2%}")
    assert height <= MAX_HEIGHT_FRACTION * width


@pytest.mark.parametrize("size, light", CASES)
def test_object_is_not_flatter_than_relief(addon, tmp_path, size, light):
    addon.image = bricks_image(tmp_path, size, light)
    relief = reconstructed_extent(addon, "relief")
    whole = reconstructed_extent(addon, "object")
    print(f"{size} px, light {light}: height range / width: Relief {relief[1]:.4f} / {relief[0]:.3f} "
          f"= {relief[1] / relief[0]:.2%}, Object {whole[1]:.4f} / {whole[0]:.3f} = {whole[1] / whole[0]:.2%}")
    assert whole[1] / whole[0] >= relief[1] / relief[0]


def test_detail_size_flattens_larger_forms(addon, tmp_path):
    """A smaller Detail size takes more of the relief's forms away: the slab comes out flatter."""
    addon.image = bricks_image(tmp_path, 256, (0.6, 0.3, 1.0))
    assert addon.detail_size == 0.0  # Auto, the library's default
    _, auto = reconstructed_extent(addon, "relief")
    addon.detail_size = 8.0  # the finest the damping resolves is 5 px
    _, fine = reconstructed_extent(addon, "relief")
    assert fine < auto
