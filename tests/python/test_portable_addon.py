"""The add-on's zip runs outside this Debian machine: its compiled module needs the C runtime only.

What is checked is the zip the build made (build/shadecut-addon-<version>-<platform>-cp<XY>.zip),
as an artist would install it: the ELF dependencies of its _core, and a reconstruction by that _core
in a process whose dynamic loader is given nothing but the C runtime and what Python and numpy
themselves map.
"""

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import compatibility, synthetic

elftools = pytest.importorskip("elftools", reason="python3-pyelftools reads the ELF dependencies")
from elftools.elf.dynamic import DynamicSection  # noqa: E402
from elftools.elf.elffile import ELFFile  # noqa: E402
from elftools.elf.gnuversions import GNUVerNeedSection  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
C_RUNTIME = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "ld-linux-x86-64.so.2"}
LIGHT = (0.5, 0.2, 1.0)

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the zip built here is Linux's")


@pytest.fixture(scope="module")
def addon_zip() -> Path:
    path = REPO / "build" / compatibility.addon_zip_name(shadecut.__version__)
    assert path.is_file(), f"no {path.name}: build first (cmake --build build)"
    return path


@pytest.fixture(scope="module")
def unpacked(addon_zip, tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("addon")
    with zipfile.ZipFile(addon_zip) as archive:
        archive.extractall(folder)
    return folder


def shipped_core(unpacked: Path) -> Path:
    cores = list((unpacked / "shadecut").glob("_core.*.so"))
    assert len(cores) == 1, cores
    return cores[0]


def soname(path: Path) -> str:
    """The name a shared object is asked for by (its DT_SONAME), else its file name."""
    with open(path, "rb") as file:
        for section in ELFFile(file).iter_sections():
            if isinstance(section, DynamicSection):
                for tag in section.iter_tags():
                    if tag.entry.d_tag == "DT_SONAME":
                        return tag.soname
    return path.name


def dynamic_needs(path: Path) -> tuple[set, set]:
    """(DT_NEEDED sonames, glibc symbol versions asked for) of an ELF shared object."""
    with open(path, "rb") as file:
        elf = ELFFile(file)
        needed = {tag.needed for section in elf.iter_sections() if isinstance(section, DynamicSection)
                  for tag in section.iter_tags() if tag.entry.d_tag == "DT_NEEDED"}
        versions = {aux.name for section in elf.iter_sections() if isinstance(section, GNUVerNeedSection)
                    for _, auxiliaries in section.iter_versions() for aux in auxiliaries}
    return needed, versions


def test_the_zip_ships_core_alone_and_names_its_platform(addon_zip, unpacked):
    names = zipfile.ZipFile(addon_zip).namelist()
    assert not [name for name in names if "_imageio" in name or "/evaluation/" in name], names
    manifest = (unpacked / "shadecut" / "blender_manifest.toml").read_text()
    assert 'platforms = ["linux-x64"]' in manifest
    assert compatibility.core_problem(unpacked / "shadecut") is None  # this Python loads it


def test_the_shipped_module_needs_only_the_c_runtime(unpacked):
    needed, versions = dynamic_needs(shipped_core(unpacked))
    assert needed <= C_RUNTIME, f"beyond the C runtime: {sorted(needed - C_RUNTIME)}"
    glibc = [tuple(int(part) for part in name[len("GLIBC_"):].split(".")) for name in versions
             if name.startswith("GLIBC_")]
    assert max(glibc) <= compatibility.OLDEST_GLIBC, f"asks for glibc {max(glibc)}"
    assert not [name for name in versions if name.startswith(("GLIBCXX", "CXXABI", "GCC_", "GOMP", "OMP"))], versions


def mapped_libraries(script: str, command: list, env: dict) -> tuple[str, dict]:
    """Runs ``script`` by ``command``; returns its output and {file name: path} of the shared
    objects mapped into the process when it ended."""
    listing = ("\nprint('MAPPED', *sorted({line.split()[-1] for line in open('/proc/self/maps') "
               "if '.so' in line.split()[-1]}))")
    result = subprocess.run([*command, "-c", script + listing], env=env, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    mapped = next(line for line in result.stdout.splitlines() if line.startswith("MAPPED")).split()[1:]
    return result.stdout, {Path(path).name: Path(path) for path in mapped}


def test_the_shipped_module_reconstructs_with_only_the_c_runtime_in_reach(unpacked, tmp_path):
    python = Path(os.path.realpath(sys.executable))
    env = {key: value for key, value in os.environ.items() if not key.startswith(("PYTHON", "LD_"))}
    # What Python and numpy map by themselves, then the loader restricted to that and the C runtime.
    _, baseline = mapped_libraries("import numpy", [str(python)], env)
    assert not [name for name in baseline if name.startswith(("libstdc++", "libgomp"))], \
        f"numpy itself maps the C++ runtime here, so this test could not tell: {sorted(baseline)}"
    loader = next(path for name, path in baseline.items() if name.startswith("ld-linux"))
    libraries = tmp_path / "libraries"
    libraries.mkdir()
    reachable = {soname(path): path for name, path in baseline.items() if ".cpython-" not in name}
    for name in C_RUNTIME - set(reachable):
        for folder in (Path("/lib/x86_64-linux-gnu"), Path("/usr/lib/x86_64-linux-gnu")):
            if (folder / name).exists():
                reachable[name] = folder / name
                break
    for name, path in reachable.items():
        (libraries / name).symlink_to(path)

    script = f"""
import numpy as np
import shadecut
from shadecut import synthetic
assert shadecut.__file__.startswith({str(unpacked)!r}), shadecut.__file__
scene = synthetic.sphere({LIGHT!r}, size=96)
result = shadecut.reconstruct(scene.image, mask=scene.mask, light=scene.light, albedo=scene.albedo)
np.save({str(tmp_path / 'normals.npy')!r}, result.normals)
"""
    env["PYTHONPATH"] = str(unpacked)
    _, mapped = mapped_libraries(script, [str(loader), "--inhibit-cache", "--library-path", str(libraries), str(python)], env)
    ours = {name for name, path in mapped.items() if str(path).startswith(str(unpacked))}
    assert ours == {shipped_core(unpacked).name}
    others = {path for name, path in mapped.items() if name not in ours and ".cpython-" not in name}
    beyond = {path for path in others if path.resolve() not in {p.resolve() for p in reachable.values()}}
    assert not beyond, f"mapped beyond Python's own and the C runtime: {sorted(map(str, beyond))}"

    # The same normals as the developer build's module, and the sphere's true shape.
    scene = synthetic.sphere(LIGHT, size=96)
    expected = shadecut.reconstruct(scene.image, mask=scene.mask, light=scene.light, albedo=scene.albedo)
    shipped = np.load(tmp_path / "normals.npy")
    np.testing.assert_array_equal(shipped, expected.normals)
    assert scene.mean_error(shipped) < 1.0  # 0.28 degrees when written; about 1 on the evaluation's sphere


@pytest.mark.parametrize("file_name, described", [
    ("_core.cpython-311-x86_64-linux-gnu.so", "Python 3.11 on Linux x86_64"),
    ("_core.cp312-win_amd64.pyd", "Python 3.12 on Windows amd64"),
    ("_core.cpython-311-darwin.so", "Python 3.11 on macOS"),
])
def test_a_compiled_modules_name_says_whom_it_is_for(file_name, described):
    assert compatibility.describe_build(file_name) == described


def test_the_core_problem_is_named_without_loading_the_module(tmp_path):
    assert "is missing: build it first" in compatibility.core_problem(tmp_path)
    (tmp_path / "_core.cp312-win_amd64.pyd").write_bytes(b"not loaded")
    problem = compatibility.core_problem(tmp_path, suffixes=[".cpython-311-x86_64-linux-gnu.so"],
                                         running="Python 3.11 on Linux x86_64")
    assert problem.startswith("This ShadeCut was built for Python 3.12 on Windows amd64, but this Blender runs "
                              "Python 3.11 on Linux x86_64: install the ShadeCut zip built for it")
    assert compatibility.core_problem(tmp_path, suffixes=[".cp312-win_amd64.pyd"]) is None
