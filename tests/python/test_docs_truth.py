"""What the docs say about the tools, checked against the tools (issue 48, finding 24): every flag of
the command-line tool's --help is in docs/cli.md, every output file it writes is named in the README's
example, and every file holding a strict expected failure is named in building_and_testing.md."""

import re
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
CLI = REPO / "build" / "native" / "shadecut"
DOCS = REPO / "docs"


def help_flags() -> set[str]:
    if not CLI.is_file():
        pytest.skip(f"the command-line tool is not built ({CLI})")
    text = subprocess.run([str(CLI), "--help"], capture_output=True, text=True, timeout=60).stdout
    return set(re.findall(r"^\s+(--[a-z][a-z-]*)", text, re.M))


def option_flags() -> set[str]:
    """The flags cli.md's rule gives the library's options: --name (and --no-name for a switch), with
    the table's other names."""
    import shadecut

    flags = set()
    for field in shadecut.option_fields():
        flag = "--" + field["name"].replace("_", "-")
        flags |= {flag, *field["flags"]} | ({"--no-" + flag[2:]} if field["kind"] == "flag" else set())
    return flags


def test_every_flag_of_the_help_is_in_cli_md_by_name_or_by_its_rule():
    """cli.md lacked --max-pixels: a flag of the command line's own must be named there."""
    flags = help_flags()
    assert "--max-pixels" in flags
    documented = (DOCS / "cli.md").read_text()
    assert "named after it, `_` written `-`" in documented
    assert [flag for flag in sorted(flags - option_flags()) if f"`{flag}" not in documented] == []


def test_the_readme_names_every_kind_of_file_the_cli_writes():
    table = (DOCS / "cli.md").read_text().split("## Output", 1)[1].split("## Options", 1)[0]
    kinds = {name.split(".")[0] for name in re.findall(r"`([a-z]+\.(?:exr|png|ply))`", table)}
    assert kinds == {"depth", "normals", "mesh", "albedo", "residual"}
    line = next(line for line in (REPO / "README.md").read_text().splitlines()
                if line.startswith("build/native/shadecut photo.png --light 1,0,1 --out result/"))
    assert all(kind in line.split("#", 1)[1] for kind in kinds), line


def test_building_and_testing_names_every_file_with_a_strict_expected_failure():
    page = (DOCS / "building_and_testing.md").read_text()
    tests = [path for folder in ("python", "blender") for path in (REPO / "tests" / folder).glob("test_*.py")]
    holders = sorted(path.name for path in tests if "mark.xfail(" "strict=True" in path.read_text())
    assert holders and [name for name in holders if f"`{name}`" not in page] == []
