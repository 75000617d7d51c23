"""The add-on zip installs, enables and reconstructs in a fresh Blender user folder, as a user would do
it; a zip built for another Python says so instead of failing with a traceback."""

import os
import subprocess
import sys
from pathlib import Path

import bpy
import pytest

import shadecut
from shadecut import compatibility, synthetic

REPO = Path(__file__).resolve().parents[2]

INSTALL = """
import bpy, sys
bpy.ops.preferences.addon_install(filepath=sys.argv[-1])
bpy.ops.preferences.addon_enable(module="shadecut")
bpy.ops.wm.save_userpref()
"""

CHECK = """
import bpy, shadecut, sys
assert "shadecut" in bpy.context.preferences.addons, "not enabled after a restart"
assert shadecut.__file__.startswith(sys.argv[-1]), shadecut.__file__
assert bpy.ops.shadecut.reconstruct.poll() is not None
assert bpy.context.preferences.addons["shadecut"].preferences.default_method == "graphcut"
assert not bpy.ops.shadecut.render_lambertian.poll(), "the zip has no OpenImageIO module to render with"
print("installed add-on:", shadecut.__file__)
"""


RECONSTRUCT = """
import bpy, sys
bpy.context.scene.shadecut.image = bpy.data.images.load(sys.argv[-1])
before = set(bpy.data.objects)
assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
(result,) = set(bpy.data.objects) - before
print("reconstructed:", result.name, len(result.data.vertices), "vertices")
"""

ANOTHER_PYTHON = """
import bpy
assert "shadecut" in bpy.context.preferences.addons
assert hasattr(bpy.types, "SHADECUT_PT_unavailable") and not hasattr(bpy.types, "SHADECUT_OT_reconstruct")
try:
    bpy.ops.shadecut.unavailable()
except RuntimeError as error:  # an ERROR report, as a Python caller receives it
    print("REPORTED:", error)
"""


@pytest.fixture(scope="module")
def addon_zip() -> Path:
    path = REPO / "build" / compatibility.addon_zip_name(shadecut.__version__)
    assert path.is_file(), f"no {path.name}: build first (cmake --build build)"
    return path


def run_blender(args, user: Path):
    env = dict(os.environ, BLENDER_USER_CONFIG=str(user / "config"), BLENDER_USER_SCRIPTS=str(user / "scripts"))
    env.pop("PYTHONPATH", None)  # the add-on must come from the install, not from the repository
    result = subprocess.run([bpy.app.binary_path, "-b", "--python-exit-code", "1", *args],
                            cwd=user, env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout + result.stderr


def test_the_zips_module_loads_on_the_oldest_glibc_we_name(addon_zip, tmp_path):
    """Built in any Debian (trixie's and sid's glibc 2.41 and 2.43 too), _core asks for no glibc
    symbol version newer than compatibility.OLDEST_GLIBC: every Blender this zip is for loads it."""
    import re
    import zipfile

    with zipfile.ZipFile(addon_zip) as archive:
        (core,) = [name for name in archive.namelist() if re.search(r"/_core\.[^/]*\.so$", name)]
        archive.extract(core, tmp_path)
    symbols = subprocess.run(["objdump", "-T", str(tmp_path / core)], capture_output=True, text=True, check=True).stdout
    versions = {tuple(int(part) for part in found.split(".")) for found in re.findall(r"\bGLIBC_([0-9.]+)\)", symbols)}
    assert versions and max(versions) <= compatibility.OLDEST_GLIBC, sorted(versions)[-3:]


def install(addon_zip: Path, user: Path) -> Path:
    run_blender(["--factory-startup", "--python-expr", INSTALL, "--", str(addon_zip)], user)
    installed = user / "scripts" / "addons" / "shadecut"
    assert (installed / "__init__.py").is_file() and list(installed.glob("_core*.so"))
    assert not list(installed.glob("_imageio*")), "the zip ships the OpenImageIO module"
    return installed


def test_zip_installs_stays_enabled_and_reconstructs(addon_zip, tmp_path):
    installed = install(addon_zip, tmp_path)
    output = run_blender(["--python-expr", CHECK, "--", str(installed)], tmp_path)
    assert "installed add-on:" in output
    scene = synthetic.sphere(light=(1.0, 0.0, 1.0), size=64)
    image = tmp_path / "sphere.png"
    shadecut.save_image(image, scene.image, scene.mask)
    output = run_blender(["--python-expr", RECONSTRUCT, "--", str(image)], tmp_path)
    assert "reconstructed: sphere" in output


def test_a_zip_built_for_another_python_reports_why_instead_of_a_traceback(addon_zip, tmp_path):
    installed = install(addon_zip, tmp_path)
    (core,) = installed.glob("_core.*")
    core.rename(installed / "_core.cpython-399-x86_64-linux-gnu.so")
    output = run_blender(["--python-expr", ANOTHER_PYTHON], tmp_path)
    running = f"Python {sys.version_info.major}.{sys.version_info.minor} on Linux"
    assert f"REPORTED: Error: This ShadeCut was built for Python 3.99 on Linux x86_64, but this Blender runs {running}" in output
    assert "Traceback" not in output
