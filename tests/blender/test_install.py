"""The add-on zip installs and enables in a fresh Blender user folder, as a user would do it."""

import os
import subprocess
import sys
from pathlib import Path

import bpy
import pytest

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
print("installed add-on:", shadecut.__file__)
"""


@pytest.fixture(scope="module")
def addon_zip() -> Path:
    zips = sorted((REPO / "build").glob("shadecut-addon-*.zip"))
    assert zips, "no add-on zip: build first (cmake --build build makes build/shadecut-addon-<version>.zip)"
    return zips[-1]


def run_blender(args, user: Path):
    env = dict(os.environ, BLENDER_USER_CONFIG=str(user / "config"), BLENDER_USER_SCRIPTS=str(user / "scripts"))
    env.pop("PYTHONPATH", None)  # the add-on must come from the install, not from the repository
    result = subprocess.run([bpy.app.binary_path, "-b", "--python-exit-code", "1", *args],
                            cwd=user, env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def test_zip_installs_and_stays_enabled(addon_zip, tmp_path):
    run_blender(["--factory-startup", "--python-expr", INSTALL, "--", str(addon_zip)], tmp_path)
    installed = tmp_path / "scripts" / "addons" / "shadecut"
    assert (installed / "__init__.py").is_file() and list(installed.glob("_core*.so"))
    output = run_blender(["--python-expr", CHECK, "--", str(installed)], tmp_path)
    assert "installed add-on:" in output
