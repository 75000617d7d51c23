"""The house rules docs/architecture.md states: it names every source file, every .cpp of the core
sits in a stage folder, and no source file is longer than the project allows."""

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
ARCHITECTURE = (REPO / "docs" / "architecture.md").read_text()
MAX_LINES = 550
SOURCE_ENDINGS = (".cpp", ".hpp", ".py", ".sh")
SOURCE_FOLDERS = ("native", "addon", "blender_scripts", "scripts", "tests")


def source_files() -> list[Path]:
    files = [path for folder in SOURCE_FOLDERS for path in (REPO / folder).rglob("*")
             if path.suffix in SOURCE_ENDINGS and "__pycache__" not in path.parts]
    return sorted(files)


def test_there_are_sources_to_check():
    assert len(source_files()) > 100


def spellings(path: Path, shared: bool) -> list[str]:
    """How the page may name a file: `name`, or a header and its source together as `stem.hpp`/`.cpp`;
    a name several files share (__init__.py, conftest.py, test_defaults.py) with its folder."""
    name = f"{path.parent.name}/{path.name}" if shared else path.name
    found = [f"{name}`", f"{name} "]
    if path.suffix == ".cpp":
        found.append(f"{name[:-4]}.hpp`/`.cpp`")
    return found


@pytest.mark.parametrize("path", source_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_the_architecture_names_every_source_file(path):
    shared = sum(1 for other in source_files() if other.name == path.name) > 1
    assert any(spelling in ARCHITECTURE for spelling in spellings(path, shared)), path.relative_to(REPO)


def test_no_core_source_outside_a_stage_folder():
    assert not list((REPO / "native" / "src").glob("*.cpp"))
    assert not list((REPO / "native" / "src").glob("*.hpp"))
    assert not list((REPO / "native" / "include" / "shadecut").glob("*.hpp"))


@pytest.mark.parametrize("path", source_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_no_source_file_is_too_long(path):
    assert len(path.read_text(errors="replace").splitlines()) <= MAX_LINES, path.relative_to(REPO)


def stage_rows() -> dict:
    """The stage table's rows: {stage folder: (public headers, sources and internal headers)}."""
    rows = {}
    for line in ARCHITECTURE.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) == 6 and cells[0].startswith("`") and cells[0].endswith("/`"):
            names = lambda cell: [name for name in __import__("re").findall(r"`([\w/]+\.[ch]pp)`", cell)]
            rows[cells[0].strip("`/")] = (names(cells[2]), names(cells[3]))
    return rows


def test_each_stage_row_names_files_of_that_stage():
    """A header the map puts in a stage is that stage's public header; a source is in that stage's folder."""
    rows = stage_rows()
    assert {"local", "graphcut", "baselines", "estimate", "integrate", "refine", "photometric", "pipeline", "support",
            "io"} <= set(rows)
    for stage, (headers, sources) in rows.items():
        for header in headers:
            assert (REPO / "native" / "include" / "shadecut" / stage / header).is_file(), f"{stage}: {header}"
        for source in sources:
            found = list((REPO / "native" / "src" / stage).rglob(Path(source).name))
            assert found, f"{stage}: {source}"
    public = {path.relative_to(REPO / "native" / "include" / "shadecut").as_posix()
              for path in (REPO / "native" / "include" / "shadecut").rglob("*.hpp")}
    assert public == {f"{stage}/{header}" for stage, (headers, _) in rows.items() for header in headers}


def test_the_data_paths_files_exist():
    """Every core file the data path names (`stage/file.cpp`) is there."""
    import re

    section = ARCHITECTURE[ARCHITECTURE.index("## The data's path"):ARCHITECTURE.index("## The Python package")]
    named = re.findall(r"`((?:local|graphcut|baselines|estimate|integrate|refine|photometric|pipeline|support)/[\w/]+)`",
                       section)
    assert len(named) > 10
    for name in named:
        stem = REPO / "native" / "src" / name
        assert any(Path(f"{stem}{ending}").is_file() for ending in ("", ".cpp", ".hpp")) or \
            (REPO / "native" / "include" / "shadecut" / f"{name}.hpp").is_file(), name
