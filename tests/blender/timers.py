"""Scripting a real Blender window: a script's steps run between redraws, then Blender exits.

Code in a Blender window must return to the event loop for anything to be drawn, for modal
operators to run and for simulated events to arrive, so a script that drives the UI is written as
a generator and advanced by a timer. Timers run outside ``--python-exit-code``'s reach, so the
process exits here with the script's outcome.

Used by tests/blender/ui_session.py and blender_scripts/screenshot.py, which put this folder on
``sys.path``.
"""

from __future__ import annotations

import os
import sys
import traceback
from typing import Callable, Iterator

import bpy


def run_steps_then_exit(steps: Iterator[None], interval: float, on_tick: Callable[[], None] = lambda: None) -> None:
    """Advances ``steps`` every ``interval`` seconds; exits 0 when it ends, 1 when it raises."""

    def tick():
        on_tick()
        try:
            next(steps)
            return interval
        except StopIteration:
            code = 0
        except Exception:  # any failure of the script is its result: print it and exit 1
            traceback.print_exc()
            code = 1
        sys.stdout.flush()
        os._exit(code)

    bpy.app.timers.register(tick, first_interval=1.0)
