"""eval.py's result files on a full disk (issue 48, finding 3): each file is whole or its previous
version, the up-front check notices the disk, and nothing temporary is left. A full disk is made
real for one process by its file-size limit (RLIMIT_FSIZE): every write past the limit fails with
EFBIG, as a write past the free space fails with ENOSPC."""

import os
import resource
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

# Run in a child process: evaluates a small dataset into OUT (figures in OUT/figures), then, under a
# file-size limit of LIMIT bytes (none when 0), writes the results and one strip again.
CHILD = textwrap.dedent("""
    import resource, signal, sys
    from pathlib import Path
    from shadecut import evaluation, synthetic
    out, limit = Path(sys.argv[1]), int(sys.argv[2])
    dataset = evaluation.write_synthetic_dataset(out.parent / "dataset", {
        "sphere_0": ("sphere", synthetic.sphere((0.5, 0.3, 1.0), size=24)),
        "bowl_0": ("bowl", synthetic.sphere((-0.4, 0.6, 1.0), size=24, bowl=True))})
    figures = out / "figures"
    figures.mkdir(parents=True, exist_ok=True)
    if limit:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # the write fails with EFBIG instead of killing us
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    try:
        if sys.argv[3] == "prepare":
            evaluation.prepare_output(out / "checked")
        else:
            run = evaluation.evaluate_dataset(dataset, ("lee_rosenfeld",), figures_dir=figures, log=lambda line: None)
            evaluation.write_results(out, run, ["figures/sphere_0.png"])
    except (OSError, evaluation.EvaluationError) as error:
        print(f"{type(error).__name__}: {error}")
""")


def child(out, limit, what="results"):
    run = subprocess.run([sys.executable, "-B", "-c", CHILD, str(out), str(limit), what], capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    return run.stdout


def test_results_and_figures_on_a_full_disk_keep_their_previous_versions(tmp_path):
    out = tmp_path / "eval"
    assert child(out, 0) == ""
    files = sorted(path for path in out.rglob("*") if path.is_file())
    assert {"results.json", "results.csv", "report.md", "sphere_0.png"} <= {path.name for path in files}
    before = {path: path.read_bytes() for path in files}
    limit = min(len(data) for path, data in before.items() if path.name in ("results.json", "sphere_0.png")) // 2
    said = child(out, limit)
    assert "OSError" in said and "File too large" in said
    after = sorted(path for path in out.rglob("*") if path.is_file())
    assert after == files  # no temporary file left behind
    assert all(path.read_bytes() == data for path, data in before.items())


def test_the_up_front_check_notices_a_full_disk(tmp_path):
    """It wrote an empty file, which a full disk still accepts."""
    said = child(tmp_path / "eval", 1, "prepare")
    assert said.startswith("EvaluationError: cannot write to the output folder") and "File too large" in said


def test_a_killed_runs_sample_folder_is_removed_and_a_running_ones_kept(tmp_path):
    """Sample folders are written under a name of their writer's process: another run's, still at
    work, is left alone; one whose process is gone is removed before the sample is written."""
    from shadecut import dataset, synthetic
    from shadecut.atomic_write import temporary_name

    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    dead = tmp_path / temporary_name(tmp_path / "s").name.replace(str(os.getpid()), gone.stdout.strip())
    alive = temporary_name(tmp_path / "s")  # this process's: it runs
    for folder in (dead, alive):
        folder.mkdir()
        (folder / "image.exr").write_text("half")
    scene = synthetic.sphere((0.5, 0.3, 1.0), size=16)
    dataset.write_sample(tmp_path / "s", image=scene.image, normals=scene.normals, depth=scene.depth,
                         mask=scene.mask, light=scene.light, albedo=scene.albedo, meta={"pixel_size": 1.0})
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(["s", alive.name])


@pytest.mark.parametrize("limit, code, said", [
    (8192, 2, "eval.py: error: cannot write to the output folder"),  # caught by the check before any work
    (80_000, 1, "eval.py: error: cannot write"),  # the paper's strip (about 90 KB) fails part-way
])
def test_eval_py_on_a_full_disk_names_the_write_and_keeps_the_previous_results(tmp_path, limit, code, said):
    """It ended in matplotlib's traceback, results.json cut to the limit."""
    from shadecut import evaluation, synthetic

    if shutil.which("blender") is None:
        pytest.skip("Blender is not installed")
    dataset = evaluation.write_synthetic_dataset(tmp_path / "dataset", {
        "sphere_0": ("sphere", synthetic.sphere((0.5, 0.3, 1.0), size=24))})
    out = tmp_path / "eval"
    out.mkdir()
    previous = "{" + '"previous": "results", ' * 4000 + '"end": 1}\n'
    (out / "results.json").write_text(previous)

    def full_disk():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))

    eval_py = Path(__file__).resolve().parents[2] / "blender_scripts" / "eval.py"
    run = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "-P", str(eval_py), "--",
                          "--dataset", str(dataset), "--methods", "lee_rosenfeld", "--out", str(out)],
                         capture_output=True, text=True, timeout=600, preexec_fn=full_disk)
    assert run.returncode == code, run.stdout[-2000:] + run.stderr[-2000:]
    assert said in run.stderr and "File too large" in run.stderr
    assert "Traceback" not in run.stdout + run.stderr
    assert (out / "results.json").read_text() == previous
    assert not [path for path in out.rglob(".*") if path.is_file()]  # no temporary file left
