"""Runs ui_session.py in a real Blender window under Xvfb (software OpenGL), where modal operators,
timers, Esc and undo behave as for a user; background mode has none of them."""

import subprocess
from pathlib import Path

import bpy

SESSION = Path(__file__).with_name("ui_session.py")


def test_operator_in_the_user_interface():
    result = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24",
         bpy.app.binary_path, "--factory-startup", "--enable-event-simulate", "-P", str(SESSION)],
        capture_output=True, text=True, timeout=300,
    )
    print(result.stdout[-2000:])
    assert result.returncode == 0 and "ui: all checks passed" in result.stdout, result.stdout + result.stderr
