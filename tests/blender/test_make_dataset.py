"""blender_scripts/make_dataset.py's generator (dataset_generator.py) run in-process: folders, manifest,
seeds, re-runs, shards, bad input."""

import importlib.util
import json
import math
import os
import signal
import subprocess

import numpy as np
import pytest

import bpy
from shadecut import dataset


@pytest.fixture(scope="module")
def generator(repo):
    """dataset_generator.py, the module make_dataset.py runs."""
    path = repo / "blender_scripts" / "dataset_generator.py"
    spec = importlib.util.spec_from_file_location("dataset_generator", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


FLOAT_ROUNDING = 1e-6  # two renders of one scene differ by this much at most: sums in another order


def run(generator, out, *extra):
    return generator.main(["--out", str(out), "--shapes", "sphere,suzanne", "--lights", "2", "--size", "64",
                              "--seed", "3", "--noise", "0.005", *extra])


def test_two_shapes_two_lights(generator, tmp_path, capsys):
    assert run(generator, tmp_path / "a") == 0
    output = capsys.readouterr().out
    assert "[4/4] suzanne_001" in output and "to go" in output
    entries = dataset.load_manifest(tmp_path / "a")
    assert [e["id"] for e in entries] == ["sphere_000", "sphere_001", "suzanne_000", "suzanne_001"]
    assert sorted(p.name for p in (tmp_path / "a").iterdir()) == sorted(
        [e["folder"] for e in entries] + ["manifest.json", "manifest.csv"])
    assert len((tmp_path / "a" / "manifest.csv").read_text().splitlines()) == 5
    for entry in entries:
        assert 10 <= entry["slant_deg"] <= 60 and entry["size"] == 64 and entry["albedo"] == 0.8
        sample = dataset.load_sample(tmp_path / "a" / entry["folder"])
        assert sample.image.shape == (64, 64) and sample.mask.any()
        np.testing.assert_allclose(sample.light, entry["light"])
        assert sample.meta["shape"] == entry["shape"] and sample.meta["seed"] == entry["seed"]
        assert sample.meta["noise_sigma"] == 0.005
    assert dataset.load_dataset_info(tmp_path / "a")["seed"] == 3

    # The same seed gives the same dataset; another seed other lights.
    assert run(generator, tmp_path / "b") == 0
    assert dataset.load_manifest(tmp_path / "b") == entries
    for entry in entries:
        first = dataset.load_sample(tmp_path / "a" / entry["folder"])
        second = dataset.load_sample(tmp_path / "b" / entry["folder"])
        # Equal up to float rounding: Blender's threads may sum a subdivided surface in another order
        # (seen: 6e-8 on suzanne in 3.4.1); another seed moves the image by ~the noise, 5e-3.
        for rendered in ("image", "normals"):
            np.testing.assert_allclose(getattr(first, rendered), getattr(second, rendered), rtol=0,
                                       atol=FLOAT_ROUNDING)
        np.testing.assert_array_equal(first.mask, second.mask)
    assert run(generator, tmp_path / "c", "--seed", "4") == 0
    assert [e["light"] for e in dataset.load_manifest(tmp_path / "c")] != [e["light"] for e in entries]
    # More lights extend the dataset: the first ones stay, so their samples are skipped.
    capsys.readouterr()
    assert generator.main(["--out", str(tmp_path / "b"), "--shapes", "sphere", "--lights", "3", "--size", "64",
                              "--seed", "3", "--noise", "0.005"]) == 0
    assert "2 already done, 1 to render" in capsys.readouterr().out

    # A re-run skips everything: no sample is written again.
    stamps = {p.name: p.stat().st_mtime_ns for p in (tmp_path / "a").glob("*/image.exr")}
    capsys.readouterr()
    assert run(generator, tmp_path / "a") == 0
    assert "4 already done, 0 to render" in capsys.readouterr().out
    assert {p.name: p.stat().st_mtime_ns for p in (tmp_path / "a").glob("*/image.exr")} == stamps
    # Other settings into the same folder are refused rather than mixed in.
    assert run(generator, tmp_path / "a", "--albedo", "0.5") == 2
    assert "other settings" in capsys.readouterr().err


def test_a_light_one_bit_apart_is_the_same_setting_and_a_light_moved_is_not(generator, tmp_path, capsys):
    assert run(generator, tmp_path) == 0
    meta_path = tmp_path / "suzanne_001" / "meta.json"
    meta = json.loads(meta_path.read_text())
    planned = meta["dataset_entry"]["light"]
    meta["dataset_entry"]["light"] = [float(np.nextafter(planned[0], 1.0)), *planned[1:]]
    meta_path.write_text(json.dumps(meta))
    capsys.readouterr()
    assert run(generator, tmp_path) == 0
    assert "4 already done, 0 to render" in capsys.readouterr().out
    meta["dataset_entry"]["light"] = [planned[0] + 1e-3, *planned[1:]]
    meta_path.write_text(json.dumps(meta))
    assert run(generator, tmp_path) == 2
    assert "suzanne_001 was made with other settings (light)" in capsys.readouterr().err


def test_shards_split_the_samples_and_a_missing_sample_is_redone(generator, tmp_path, capsys):
    assert run(generator, tmp_path, "--shard", "1/2") == 0
    assert sorted(e["id"] for e in dataset.load_manifest(tmp_path)) == ["sphere_001", "suzanne_001"]
    assert run(generator, tmp_path, "--shard", "0/2") == 0
    assert len(dataset.load_manifest(tmp_path)) == 4
    # A sample folder without meta.json (never made by write_sample, e.g. copied half) is not done.
    (tmp_path / "sphere_000" / "meta.json").unlink()
    capsys.readouterr()
    assert run(generator, tmp_path) == 0
    assert "3 already done, 1 to render" in capsys.readouterr().out
    assert dataset.is_sample(tmp_path / "sphere_000")


def test_interrupted_run_keeps_finished_samples_and_resumes(generator, tmp_path, monkeypatch, capsys):
    render_sample = generator.render_sample
    calls = []

    def interrupted_on_the_third(*args):
        calls.append(args[0]["id"])
        if len(calls) == 3:
            raise KeyboardInterrupt
        render_sample(*args)

    monkeypatch.setattr(generator, "render_sample", interrupted_on_the_third)
    assert run(generator, tmp_path) == 130
    assert [e["id"] for e in dataset.load_manifest(tmp_path)] == ["sphere_000", "sphere_001"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["manifest.csv", "manifest.json", "sphere_000", "sphere_001"]
    monkeypatch.setattr(generator, "render_sample", render_sample)
    capsys.readouterr()
    assert run(generator, tmp_path) == 0
    assert "2 already done, 2 to render" in capsys.readouterr().out


def test_every_catalogue_shape_and_fixed_lights(generator, tmp_path):
    assert generator.main(["--out", str(tmp_path), "--size", "32", "--light", "1,0,1", "--light", "0,-1,2",
                              "--shadows", "--bits", "8"]) == 0
    entries = dataset.load_manifest(tmp_path)
    assert sorted({e["shape"] for e in entries}) == sorted(generator.CATALOGUE)
    assert len(entries) == 2 * len(generator.CATALOGUE)
    assert entries[0]["light"] == pytest.approx([2**-0.5, 0, 2**-0.5])
    for entry in entries:
        sample = dataset.load_sample(tmp_path / entry["folder"])
        assert sample.mask.mean() > 0.1, entry["id"]
        assert sample.shadow_mask is not None and sample.meta["quantization_bits"] == 8
        # Visible surfaces face the viewer.
        assert np.mean(sample.normals[sample.mask][:, 2] > 0) > 0.95, entry["id"]


def _mesh_arrays(mesh):
    positions = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", positions)
    corners = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", corners)
    return positions, corners


def test_every_shape_is_built_the_same_every_time(generator):
    """Vertices and face corners in one order: Cycles splits a quad at its first corner, so a shape
    whose corners moved would render a few pixels differently under the same seed."""
    for shape in generator.CATALOGUE:
        first, second = (generator.BUILDERS[shape](3) for _ in range(2))
        try:
            for a, b in zip(first, second, strict=True):
                for array_a, array_b in zip(_mesh_arrays(a.data), _mesh_arrays(b.data)):
                    np.testing.assert_array_equal(array_a, array_b, err_msg=shape)
        finally:
            for ob in first + second:
                mesh = ob.data
                bpy.data.objects.remove(ob)
                bpy.data.meshes.remove(mesh)


def test_mesh_files(generator, tmp_path):
    ply = tmp_path / "tetra.ply"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n0 0 1\n0 -1 0\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n")
    assert generator.main(["--out", str(tmp_path / "out"), "--mesh", str(ply), "--lights", "1",
                              "--size", "32"]) == 0
    (entry,) = dataset.load_manifest(tmp_path / "out")
    assert entry["shape"] == "tetra" and entry["mesh_file"] == str(ply)
    assert dataset.load_sample(tmp_path / "out" / "tetra_000").mask.sum() > 50


@pytest.mark.parametrize("arguments, message", [
    (["--mesh", "{tmp}/missing.obj"], "cannot read mesh"),
    (["--mesh", "{tmp}/garbage.ply"], "cannot read mesh"),
    (["--mesh", "{tmp}/model.fbx"], "format must be"),
    (["--shapes", "cube"], "unknown shape"),
    (["--light", "1,0,-1"], "horizon"),
    (["--light", "1,0"], "X,Y,Z"),
    (["--slant-max", "90"], "horizon"),
    (["--shard", "3/3"], "--shard"),
    (["--size", "4"], "--size"),
    (["--bits", "12"], "invalid choice"),
    (["--seed", "-1"], "--seed must be >= 0"),
    (["--noise", "nan"], "--noise must be a finite number >= 0"),
    (["--noise", "inf"], "--noise must be a finite number >= 0"),
    (["--noise", "-0.1"], "--noise must be a finite number >= 0"),
    (["--albedo", "nan"], "--albedo must be in (0, 1]"),
    (["--albedo", "0"], "--albedo must be in (0, 1]"),
    (["--size", "0"], "--size"),
    (["--size", "nan"], "invalid int value"),
    (["--lights", "0"], "--lights must be 1 to"),
    (["--lights", "-3", "--light", "1,0,1"], "--lights must be 1 to"),
    (["--lights", "1000000000"], "--lights must be 1 to"),
    (["--samples", "0"], "--samples must be 1 to"),
    (["--slant-min", "nan"], "the slants must satisfy"),
    (["--slant-min=-inf"], "the slants must satisfy"),
    (["--light", "nan,0,1"], "NaN or infinite"),
    (["--shard=-1/2"], "--shard"),
])
def test_bad_input_exits_with_a_message(generator, tmp_path, capsys, arguments, message):
    (tmp_path / "garbage.ply").write_text("this is not a ply file\n")
    arguments = [a.format(tmp=tmp_path) for a in arguments]
    assert generator.main(["--out", str(tmp_path / "out"), "--size", "32", *arguments]) == 2
    error = capsys.readouterr().err
    assert message in error and "Traceback" not in error
    assert not dataset.is_sample(tmp_path / "out" / "sphere_000")


def test_unwritable_output_folder(generator, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert generator.main(["--out", str(blocker / "dataset"), "--shapes", "sphere", "--size", "32"]) == 2
    assert "cannot write to the output folder" in capsys.readouterr().err
    if os.geteuid() != 0:  # root writes into read-only folders anyway
        readonly = tmp_path / "readonly"
        readonly.mkdir(mode=0o500)
        assert generator.main(["--out", str(readonly), "--shapes", "sphere", "--size", "32"]) == 2


def test_lights_are_uniform_over_the_slant_band(generator):
    lights = np.array(generator.draw_lights(generator.shape_rng(0, "x"), 4000, 10, 60))
    slants = np.degrees(np.arccos(lights[:, 2]))
    assert slants.min() >= 10 and slants.max() <= 60
    # Uniform over the solid angle: cos(slant) uniform between cos 60 and cos 10.
    assert np.mean(lights[:, 2]) == pytest.approx((math.cos(math.radians(10)) + 0.5) / 2, abs=0.01)
    np.testing.assert_allclose(np.linalg.norm(lights, axis=1), 1)


def test_a_sample_damaged_after_it_was_written_is_rendered_again(generator, tmp_path, capsys):
    assert run(generator, tmp_path) == 0
    image = tmp_path / "sphere_001" / "image.exr"
    image.write_bytes(image.read_bytes()[: image.stat().st_size // 2])  # e.g. a copy cut short, a full disk
    (tmp_path / "suzanne_000" / "meta.json").write_text('{"format": ')  # meta.json itself cut short
    capsys.readouterr()
    assert run(generator, tmp_path) == 0
    captured = capsys.readouterr()
    assert "2 already done, 2 to render" in captured.out
    assert "sphere_001 is incomplete or damaged" in captured.err and "image.exr" in captured.err
    assert "suzanne_000 is incomplete or damaged" in captured.err
    assert "[1/2] sphere_001" in captured.out and "[2/2] suzanne_000" in captured.out
    for entry in dataset.load_manifest(tmp_path):
        assert dataset.check_sample(tmp_path / entry["folder"]) is None, entry["id"]
        assert dataset.load_sample(tmp_path / entry["folder"]).image.shape == (64, 64)
    # A damaged sample of another shard is not listed in the manifest that shard writes.
    image.write_bytes(b"")
    assert run(generator, tmp_path, "--shard", "0/2") == 0
    assert "sphere_001" not in [e["id"] for e in dataset.load_manifest(tmp_path)]


def test_ctrl_c_stops_the_whole_run(repo, tmp_path):
    """SIGINT, as Ctrl+C sends it, after the first sample: the run stops (not just the render under way)."""
    command = [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
               "-P", str(repo / "blender_scripts" / "make_dataset.py"), "--", "--out", str(tmp_path),
               "--shapes", "sphere,torus,suzanne", "--lights", "4", "--size", "64"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = []
        for line in process.stdout:
            lines.append(line)
            if line.startswith("[1/12]"):
                process.send_signal(signal.SIGINT)
        code = process.wait(timeout=120)
        error = process.stderr.read()
    finally:
        if process.poll() is None:
            process.kill()
    output = "".join(lines) + error
    assert code == 130, output
    assert "interrupted (Ctrl+C): the run is stopped" in error and "Traceback" not in output
    assert not any(line.startswith("[12/12]") for line in lines), output
    on_disk = sorted(p.name for p in tmp_path.iterdir() if p.is_dir())
    assert 1 <= len(on_disk) < 12 and not [name for name in on_disk if name.startswith(".")], on_disk
    assert sorted(e["id"] for e in dataset.load_manifest(tmp_path)) == on_disk  # consistent with the disk
    assert all(dataset.check_sample(tmp_path / name) is None for name in on_disk)


def test_stop_on_interrupt_turns_sigint_into_keyboard_interrupt_then_restores(generator):
    before = signal.getsignal(signal.SIGINT)
    with pytest.raises(KeyboardInterrupt):
        with generator.STOP.installed():
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):  # the handler runs between bytecodes
                sum(range(100))
    assert signal.getsignal(signal.SIGINT) == before

    # Inside a sample (STOP.deferring) the sample is finished first, then the run stops.
    finished = []
    with pytest.raises(KeyboardInterrupt):
        with generator.STOP.installed(), generator.STOP.deferring():
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):
                sum(range(100))
            finished.append(True)
    assert finished == [True] and signal.getsignal(signal.SIGINT) == before
