"""scripts/test.sh and scripts/build.sh tell what they do (issue 48, finding 23): test.sh ends with one
summary line, every stage passed or which one failed, with the time taken; build.sh says it builds
and how long it took. Run on a copy of the scripts whose commands are stand-ins."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
STAND_IN = "#!/bin/sh\necho \"$(basename \"$0\") $*\"\nexit ${FAIL:-0}\n"


def copy_with_stand_ins(tmp_path, failing=""):
    """A folder shaped like the repository: test.sh itself, every script and tool it calls a stand-in
    (``failing`` the one that fails), and one passing Python test."""
    root = tmp_path / "repo"
    (root / "scripts").mkdir(parents=True)
    shutil.copy(REPO / "scripts" / "test.sh", root / "scripts" / "test.sh")
    tools = tmp_path / "bin"
    tools.mkdir()
    for name in ("install_dependencies.sh", "build.sh", "blender_versions.sh", "sanitize.sh"):
        (root / "scripts" / name).write_text(STAND_IN.replace("${FAIL:-0}", "1" if name == failing else "0"))
    for name in ("ctest", "blender", "nproc"):
        (tools / name).write_text(STAND_IN.replace("${FAIL:-0}", "1" if name == failing else "0"))
        (tools / name).chmod(0o755)
    (root / "tests" / "python").mkdir(parents=True)
    (root / "tests" / "python" / "test_nothing.py").write_text("def test_nothing():\n    pass\n")
    env = {**os.environ, "PATH": f"{tools}:{os.environ['PATH']}"}
    return subprocess.run(["bash", str(root / "scripts" / "test.sh")], capture_output=True, text=True, env=env,
                          timeout=120)


def test_a_passing_run_ends_with_a_summary_and_its_time(tmp_path):
    run = copy_with_stand_ins(tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    last = run.stdout.strip().splitlines()[-1]
    assert last.startswith("== test.sh: every stage passed in ") and last.endswith(" s"), last
    assert "== C++ tests (GoogleTest via ctest) (at 0 min" in run.stdout


@pytest.mark.parametrize("failing, stage", [("ctest", "C++ tests (GoogleTest via ctest)"),
                                            ("sanitize.sh", "C++ tests and the CLI under AddressSanitizer and UBSan")])
def test_a_failing_run_names_the_stage_that_failed(tmp_path, failing, stage):
    run = copy_with_stand_ins(tmp_path, failing)
    assert run.returncode == 1
    assert run.stdout.strip().splitlines()[-1].startswith(f'== test.sh: FAILED in the stage "{stage}" (exit code 1) '
                                                          "after 0 min")


def test_build_sh_says_what_it_builds_and_how_long_it_took():
    text = (REPO / "scripts" / "build.sh").read_text()
    assert 'echo "== build.sh: building ShadeCut' in text and 'echo "== build.sh: built in' in text
    demo = (REPO / "scripts" / "demo.sh").read_text()
    assert "build.sh >/dev/null" not in demo and "Built target" in demo
