"""Runs ui_session.py in a real Blender window under Xvfb (software OpenGL), where modal operators,
timers, Esc and undo behave as for a user; background mode has none of them."""

from pathlib import Path

from window_steps import run_in_window

SESSION = Path(__file__).with_name("ui_session.py")


def test_operator_in_the_user_interface():
    result = run_in_window(SESSION)
    print(result.stdout[-2000:])
    assert result.returncode == 0 and "ui: all checks passed" in result.stdout, result.stdout + result.stderr
