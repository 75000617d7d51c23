"""Steps shared by the scripts that drive the add-on in a real Blender window (ui_session.py,
photographs_ui_session.py), and the test-side call that runs such a script under Xvfb."""

from __future__ import annotations

import subprocess
import threading
import time
from pathlib import Path

import bpy

from shadecut.blender import reconstruct_job


def run_in_window(script: Path) -> subprocess.CompletedProcess:
    """Runs ``script`` in a Blender window under Xvfb (software OpenGL), events simulated."""
    return subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24",
         bpy.app.binary_path, "--factory-startup", "--enable-event-simulate", "-P", str(script)],
        capture_output=True, text=True, timeout=300,
    )


def view3d_override() -> dict:
    window = bpy.context.window_manager.windows[0]
    area = next(area for area in window.screen.areas if area.type == "VIEW_3D")
    region = next(region for region in area.regions if region.type == "WINDOW")
    return dict(window=window, area=area, region=region)


def meshes() -> set:
    return {obj.name for obj in bpy.data.objects if obj.type == "MESH"}


def record_progress(state: dict) -> None:
    """Every job's progress fractions go to ``state["fractions"]``; while ``state["hold"]`` the job
    waits at its progress calls for Esc (at most 10 s), as a long reconstruction would."""
    original = reconstruct_job.Job.progress

    def progress(job, fraction, stage):
        state["fractions"].append(fraction)
        deadline = time.monotonic() + 10.0
        while state.get("hold") and not job.cancel and time.monotonic() < deadline:
            time.sleep(0.01)
        return original(job, fraction, stage)

    reconstruct_job.Job.progress = progress


def invoke_reconstruct() -> None:
    """Invokes Reconstruct as the UI does, from the 3D Viewport."""
    with bpy.context.temp_override(**view3d_override()):
        assert bpy.ops.shadecut.reconstruct("INVOKE_DEFAULT") == {"RUNNING_MODAL"}


def reconstruct_until(finished, failure: str):
    """Steps: invokes Reconstruct as the UI does, then waits timer ticks until finished() (at most
    600: 60 s at the scripts' 0.1 s); returns how many ticks that took."""
    invoke_reconstruct()
    return (yield from wait_until(finished, failure))


def start_held(state: dict):
    """Steps: invokes Reconstruct with the job to be held at its progress calls (record_progress) and
    waits until it reaches the first."""
    state["fractions"].clear()
    state["hold"] = True
    invoke_reconstruct()
    yield from wait_until(lambda: state["fractions"], "the job never reported progress")


def reconstruct_held_until(state: dict, finished, failure: str, held_ticks: int = 3):
    """Steps: as reconstruct_until, with the job held at its first progress call for ``held_ticks``
    timer ticks, so that the check that Blender keeps running while the worker works does not depend
    on how fast this machine reconstructs; returns the ticks after the job was let go."""
    yield from start_held(state)
    for _ in range(held_ticks):
        yield
    assert any_running(), "the worker stopped while it was held"
    assert not finished(), "the result came while the worker was held"
    state["hold"] = False
    return (yield from wait_until(finished, failure))


def wait_until(finished, failure: str):
    """Steps: waits timer ticks until finished() (at most 600: 60 s at the scripts' 0.1 s); returns
    how many ticks that took."""
    ticks = 0
    while not finished():
        yield
        ticks += 1
        assert ticks < 600, f"{failure} after 60 s"
    return ticks


def any_running() -> bool:
    return any(thread.name == "shadecut-reconstruct" for thread in threading.enumerate())


def cancel_with_esc(state: dict):
    """Steps (a generator: each yield waits for a timer tick): invokes Reconstruct as the UI does with
    the job held at its first progress call, presses Esc, and waits until the worker has stopped."""
    yield from start_held(state)
    bpy.context.window_manager.windows[0].event_simulate(type="ESC", value="PRESS")
    for _ in range(100):  # the worker stops at its next progress call
        yield
        if not any_running():
            break
    yield  # the operator's next timer event finishes it
    state["hold"] = False


def undo_then_cancel(state: dict, before: set):
    """Steps: one undo step must take the result just built out (``before``: the meshes there were),
    and Esc must then cancel a second run with nothing added."""
    with bpy.context.temp_override(**view3d_override()):
        bpy.ops.ed.undo()
    yield
    assert meshes() == before, f"undo left {meshes() - before}"
    print("ui: one undo step removed the result")
    yield from cancel_with_esc(state)
    assert meshes() == before, f"cancelling left {meshes() - before}"
    assert state["fractions"][-1] < 1.0, "Esc came too late to cancel"
    print(f"ui: Esc cancelled at {state['fractions'][-1]:.2f}, nothing added")
