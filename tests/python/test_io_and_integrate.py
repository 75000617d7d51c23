"""Image files, depth integration and the renderer through the Python API."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest

import shadecut
from shadecut import synthetic


def srgb_to_linear(v):
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def write_with_oiio(path, pixels, dtype):
    pixels = pixels.reshape(pixels.shape[0], pixels.shape[1], -1)  # OIIO's Python wants (H, W, C)
    height, width, channels = pixels.shape
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(width, height, channels, dtype))
    assert out.write_image(np.ascontiguousarray(pixels))
    out.close()


def test_8bit_srgb_png_is_linearized(tmp_path):
    codes = np.arange(256).reshape(16, 16)
    write_with_oiio(tmp_path / "ramp.png", (codes / 255.0).astype(np.float32), oiio.UINT8)
    loaded = shadecut.load_image(tmp_path / "ramp.png")
    assert loaded.color_space == "srgb" and not loaded.has_alpha and loaded.mask.all()
    np.testing.assert_allclose(loaded.image, srgb_to_linear(codes / 255.0), atol=1e-6)


def test_16bit_png_round_trip_keeps_linear_values(tmp_path):
    image = np.random.default_rng(1).random((20, 30), dtype=np.float32)
    mask = image > 0.3
    shadecut.save_image(tmp_path / "image.png", image, mask)
    loaded = shadecut.load_image(tmp_path / "image.png")
    np.testing.assert_allclose(loaded.image, image, atol=2e-5)
    np.testing.assert_array_equal(loaded.mask, mask)


def test_float_exr_with_alpha_gives_luminance_and_mask(tmp_path):
    rgba = np.zeros((8, 10, 4), np.float32)
    rgba[..., 0], rgba[..., 1], rgba[..., 2] = 0.2, 0.5, 0.9
    rgba[:, :5, 3] = 1.0
    write_with_oiio(tmp_path / "colour.exr", rgba, oiio.FLOAT)
    loaded = shadecut.load_image(tmp_path / "colour.exr")
    assert loaded.color_space == "linear" and loaded.has_alpha
    np.testing.assert_allclose(loaded.image, 0.2126 * 0.2 + 0.7152 * 0.5 + 0.0722 * 0.9, rtol=1e-6)
    assert loaded.mask[:, :5].all() and not loaded.mask[:, 5:].any()


def test_poisson_integrates_exact_normals_on_a_non_rectangular_mask():
    bumps = synthetic.bumps((1.0, 0.0, 1.0), size=96)
    rows, cols = np.mgrid[0:96, 0:96]
    mask = ((rows - 48) ** 2 + (cols - 40) ** 2 < 40**2) & ~((rows > 60) & (cols > 50))  # a notched disk
    depth = shadecut.integrate(bumps.normals, mask, "poisson")
    residual = (depth - bumps.depth)[mask]
    rmse = np.sqrt(np.mean((residual - residual.mean()) ** 2))
    depth_range = np.ptp(bumps.depth[mask])
    print(f"Poisson depth RMSE {rmse:.4f} px = {100 * rmse / depth_range:.3f}% of the range")
    assert rmse <= 0.01 * depth_range
    assert depth[mask].min() == pytest.approx(0.0, abs=1e-4) and not depth[~mask].any()


def test_render_is_the_lambertian_model():
    sphere = synthetic.sphere((1.0, 0.5, 1.0), size=32, albedo=0.8)
    light = np.array([1.0, 0.5, 1.0]) / np.linalg.norm([1.0, 0.5, 1.0])
    expected = 0.8 * np.maximum(0, sphere.normals @ light)
    np.testing.assert_allclose(sphere.image, np.where(sphere.mask, expected, 0), atol=1e-6)


def test_depth_of_a_height_field_renders_through_its_normals():
    rows, cols = np.mgrid[0:24, 0:24].astype(np.float32)
    plane = 0.5 * cols + 0.25 * rows  # dz/dx = 0.5, dz/dy = -0.25 (y is up)
    normals = shadecut.normals_from_depth(plane)
    np.testing.assert_allclose(normals[5, 5], np.array([-0.5, 0.25, 1.0]) / np.linalg.norm([-0.5, 0.25, 1.0]), atol=1e-6)
    np.testing.assert_allclose(shadecut.render(plane, (0, 0, 1)), normals[..., 2], atol=1e-6)


def test_save_depth_normals_and_mesh_write_readable_files(tmp_path):
    sphere = synthetic.sphere((1.0, 0.0, 1.0), size=16)
    shadecut.save_depth(tmp_path / "depth.exr", sphere.depth, sphere.mask)
    shadecut.save_normals(tmp_path / "normals.png", sphere.normals, sphere.mask)
    shadecut.save_mesh(tmp_path / "mesh.obj", sphere.depth, sphere.mask)
    exr = oiio.ImageInput.open(str(tmp_path / "depth.exr"))
    z_channel = list(exr.spec().channelnames).index("Y")  # grey, as Blender reads it; EXR sorts channels
    np.testing.assert_allclose(exr.read_image(oiio.FLOAT)[..., z_channel], sphere.depth, atol=1e-5)
    vertices = sum(line.startswith("v ") for line in open(tmp_path / "mesh.obj"))
    assert vertices == sphere.mask.sum()


# Each writer's call on a 128 x 128 noise image (tens of kilobytes in every format), in a child process.
WRITES = {
    "image.exr": "shadecut.save_image(path, noise)",
    "image.png": "shadecut.save_image(path, noise)",
    "colour.png": "shadecut.save_image(path, np.dstack([noise] * 3))",
    "depth.exr": "shadecut.save_depth(path, noise)",
    "depth.png": "shadecut.save_depth(path, noise)",
    "normals.exr": "shadecut.save_normals(path, shadecut.normals_from_depth(noise * 4))",
    "normals.png": "shadecut.save_normals(path, shadecut.normals_from_depth(noise * 4))",
    "mesh.ply": "shadecut.save_mesh(path, noise)",
    "mesh.obj": "shadecut.save_mesh(path, noise)",
}
WRITE_IN_CHILD = """
import sys
import numpy as np
import shadecut
path, seed = sys.argv[1], int(sys.argv[2])
noise = np.random.default_rng(seed).random((128, 128), dtype=np.float32)
try:
    {call}
except OSError as error:
    print(error)
    sys.exit(3)
"""


@pytest.mark.parametrize("name", WRITES)
def test_a_write_that_fails_part_way_leaves_the_old_file_whole(tmp_path, name, file_size_limit):
    """A full disk part-way through a save replaced a good file by a fragment: the new file is now
    written beside it and renamed onto it only when complete. The disk fills at 4 KB here."""
    path = tmp_path / name
    code = WRITE_IN_CHILD.format(call=WRITES[name])
    env = {"PYTHONPATH": str(Path(shadecut.__file__).parents[1])}
    subprocess.run([sys.executable, "-c", code, str(path), "1"], check=True, env=env, timeout=60)
    old = path.read_bytes()
    assert len(old) > 4096
    failed = subprocess.run([sys.executable, "-c", code, str(path), "2"], capture_output=True, text=True, env=env,
                            timeout=60, preexec_fn=file_size_limit(4096))
    assert failed.returncode == 3, failed.stdout + failed.stderr
    assert name in failed.stdout
    assert path.read_bytes() == old
    assert [entry.name for entry in tmp_path.iterdir()] == [name]  # no temporary file left
