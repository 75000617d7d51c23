"""The dataset format (shadecut.dataset) without Blender: samples and manifests round-trip."""

import csv
import json

import numpy as np
import OpenImageIO as oiio
import pytest

import shadecut
from shadecut import dataset, dataset_files, synthetic

PIXEL_SIZE = 0.01  # scene units per pixel


def sphere_sample(tmp_path, name="sphere_000", **extra):
    scene = synthetic.sphere((1.0, 0.5, 1.0), size=32, albedo=0.8)
    z = (scene.depth - 100.0) * PIXEL_SIZE  # camera-frame z, in front of the camera (negative)
    dataset.write_sample(tmp_path / name, image=scene.image, normals=scene.normals, depth=np.where(scene.mask, z, 0),
                         mask=scene.mask, light=(1.0, 0.5, 1.0), albedo=0.8,
                         meta={"pixel_size": PIXEL_SIZE, "shape": "sphere"}, **extra)
    return scene


def test_sample_round_trip(tmp_path):
    scene = sphere_sample(tmp_path)
    sample = dataset.load_sample(tmp_path / "sphere_000")
    assert sample.id == "sphere_000" and sample.folder == tmp_path / "sphere_000"
    np.testing.assert_array_equal(sample.mask, scene.mask)
    np.testing.assert_allclose(sample.image, scene.image, atol=1e-7)
    np.testing.assert_allclose(sample.normals, scene.normals, atol=1e-7)
    np.testing.assert_allclose(sample.depth[scene.mask], scene.depth[scene.mask] - 100.0, atol=1e-3)
    assert not sample.depth[~scene.mask].any()
    np.testing.assert_allclose(sample.light, np.array([1.0, 0.5, 1.0]) / 1.5)
    assert sample.albedo == 0.8 and sample.shadow_mask is None and sample.albedo_map is None
    assert sample.meta["shape"] == "sphere" and sample.meta["resolution"] == [32, 32]
    assert sorted(p.name for p in (tmp_path / "sphere_000").iterdir()) == sorted(sample.meta["files"])
    # The 16-bit PNG gives back the linear values and the mask through the ordinary loader.
    png = shadecut.load_image(tmp_path / "sphere_000" / "image.png")
    np.testing.assert_allclose(png.image, scene.image, atol=2e-5)
    np.testing.assert_array_equal(png.mask, scene.mask)


def test_a_depth_written_with_the_former_z_channel_still_loads(tmp_path):
    """depth.exr was Z + A (which Blender loads black) before save_depth wrote Y + A: samples rendered
    and cached then keep loading, with the same depth."""
    scene = sphere_sample(tmp_path)
    path = tmp_path / "sphere_000" / "depth.exr"
    pixels, channels = dataset_files.read_image_channels(path)
    assert set(channels) == {"Y", "A"}
    spec = oiio.ImageSpec(32, 32, 2, oiio.FLOAT)
    spec.channelnames, spec.alpha_channel = ("Z", "A"), 1
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec)
    out.write_image(np.dstack([pixels[..., channels.index("Y")], pixels[..., channels.index("A")]]))
    out.close()
    assert dataset.check_sample(tmp_path / "sphere_000") is None
    sample = dataset.load_sample(tmp_path / "sphere_000")
    np.testing.assert_allclose(sample.depth[scene.mask], scene.depth[scene.mask] - 100.0, atol=1e-3)


def test_optional_shadow_mask_and_albedo_map(tmp_path):
    shadow = np.zeros((32, 32), bool)
    shadow[10:14, 10:20] = True
    albedo_map = np.full((32, 32), 0.5, np.float32)
    sphere_sample(tmp_path, shadow_mask=shadow, albedo_map=albedo_map)
    sample = dataset.load_sample(tmp_path / "sphere_000")
    np.testing.assert_array_equal(sample.shadow_mask, shadow)
    np.testing.assert_allclose(sample.albedo_map[sample.mask], 0.5)


def test_rewrite_replaces_and_leaves_no_temporary_folder(tmp_path):
    sphere_sample(tmp_path)
    sphere_sample(tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["sphere_000"]


def test_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(ValueError, match="pixel_size"):
        dataset.write_sample(tmp_path / "bad", image=np.zeros((4, 4)), normals=np.zeros((4, 4, 3)),
                             depth=np.zeros((4, 4)), mask=np.ones((4, 4), bool), light=(0, 0, 1), albedo=1.0, meta={})
    with pytest.raises(ValueError, match="share"):
        dataset.write_sample(tmp_path / "bad", image=np.zeros((4, 4)), normals=np.zeros((4, 5, 3)),
                             depth=np.zeros((4, 4)), mask=np.ones((4, 4), bool), light=(0, 0, 1), albedo=1.0,
                             meta={"pixel_size": 1.0})
    assert not any(tmp_path.iterdir())
    assert not dataset.is_sample(tmp_path / "bad")


def test_manifest_json_and_csv(tmp_path):
    entries = [
        {"id": f"sphere_{i:03d}", "shape": "sphere", "folder": f"sphere_{i:03d}", "light": [0.1 * i, 0.0, 1.0],
         "albedo": 0.8, "size": 64, "seed": 7 + i, "slant": 5.7 * i}
        for i in range(3)
    ]
    dataset.write_manifest(tmp_path, entries, {"seed": 7})
    assert dataset.load_manifest(tmp_path) == entries
    assert dataset.load_dataset_info(tmp_path) == {"seed": 7}
    rows = list(csv.DictReader((tmp_path / "manifest.csv").open()))
    assert [row["id"] for row in rows] == ["sphere_000", "sphere_001", "sphere_002"]
    assert float(rows[2]["light_x"]) == pytest.approx(0.2) and rows[1]["seed"] == "8"
    assert json.loads((tmp_path / "manifest.json").read_text())["format"] == "shadecut-dataset"
    with pytest.raises(ValueError, match="lacks"):
        dataset.write_manifest(tmp_path, [{"id": "x"}])
    with pytest.raises(OSError, match="manifest"):
        dataset.load_manifest(tmp_path / "nowhere")


def test_interrupted_write_leaves_no_sample(tmp_path, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(dataset_files, "save_depth", interrupted)  # after image.exr/.png and normals.exr
    with pytest.raises(KeyboardInterrupt):
        sphere_sample(tmp_path)
    assert not any(tmp_path.iterdir())


def test_leftover_of_a_killed_write_is_neither_a_sample_nor_kept(tmp_path):
    partial = tmp_path / ".sphere_000.partial"
    partial.mkdir()
    (partial / "image.exr").write_text("half")
    assert not dataset.is_sample(partial) and not dataset.is_sample(tmp_path / "sphere_000")
    sphere_sample(tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["sphere_000"]


def _truncate(path, keep=0.5):
    data = path.read_bytes()
    path.write_bytes(data[: int(len(data) * keep)])


def _replace_meta(folder, **changes):
    meta = json.loads((folder / "meta.json").read_text())
    meta.update(changes)
    (folder / "meta.json").write_text(json.dumps(meta))


@pytest.mark.parametrize("damage, message", [
    (lambda f: _truncate(f / "image.exr"), "image.exr is unreadable"),
    (lambda f: _truncate(f / "image.exr", 0.99), "image.exr is unreadable"),
    (lambda f: _truncate(f / "normals.exr"), "normals.exr is unreadable"),
    (lambda f: _truncate(f / "depth.exr"), "depth.exr is unreadable"),
    (lambda f: _truncate(f / "image.png"), "image.png is unreadable"),
    (lambda f: (f / "mask.png").write_bytes(b""), "mask.png is unreadable"),
    (lambda f: (f / "normals.exr").unlink(), "normals.exr is missing"),
    (lambda f: _truncate(f / "meta.json"), "meta.json is unreadable"),
    (lambda f: (f / "meta.json").write_text("[1, 2]"), "meta.json is malformed"),
    (lambda f: _replace_meta(f, files=None), "meta.json is malformed"),
    (lambda f: _replace_meta(f, resolution=[16, 32]), "not 16 x 32"),
    (lambda f: (f / "meta.json").unlink(), "not a sample"),
])
def test_check_sample_finds_damaged_files(tmp_path, damage, message):
    sphere_sample(tmp_path)
    folder = tmp_path / "sphere_000"
    assert dataset.check_sample(folder) is None
    damage(folder)
    problem = dataset.check_sample(folder)
    assert problem is not None and message in problem


def test_check_sample_with_optional_files(tmp_path):
    scene = sphere_sample(tmp_path, shadow_mask=np.zeros((32, 32), bool), albedo_map=np.full((32, 32), 0.5))
    assert scene is not None and dataset.check_sample(tmp_path / "sphere_000") is None
    _truncate(tmp_path / "sphere_000" / "albedo.exr")
    assert "albedo.exr is unreadable" in dataset.check_sample(tmp_path / "sphere_000")


@pytest.mark.parametrize("text", ["[1, 2]", "null", '"text"', "{ not json", json.dumps({"format": "other"}),
                                  json.dumps({"format": dataset.FORMAT, "samples": "abc"}),
                                  json.dumps({"format": dataset.FORMAT, "samples": [1]})])
def test_a_malformed_manifest_is_a_value_error(tmp_path, text):
    (tmp_path / dataset.MANIFEST_JSON).write_text(text)
    with pytest.raises(ValueError):
        dataset.load_manifest(tmp_path)
