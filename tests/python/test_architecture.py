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
