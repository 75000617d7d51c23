"""Several photographs as a user meets them, in a real Blender window (under Xvfb): the panel
draws the Photographs list, one click on Reconstruct (invoked as the UI does) runs the job on its
worker thread into a mesh with the normal map and the albedo wired, one undo step removes it, and
Esc cancels a second run with nothing added. Run by test_photographs_addon.py:

    xvfb-run -a blender --factory-startup --enable-event-simulate -P tests/blender/photographs_ui_session.py

timers.py (next to this script) ends the process with the script's outcome.
"""

import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "addon"))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # timers.py, window_steps.py
import shadecut  # noqa: E402
from shadecut import synthetic  # noqa: E402
from shadecut.blender import panels  # noqa: E402
from timers import run_steps_then_exit  # noqa: E402
from window_steps import (meshes, reconstruct_until, record_progress, undo_then_cancel,  # noqa: E402
                          view3d_override)

# Four lights about 40 degrees from the viewer, from the top, the left, the bottom and the right.
AROUND = np.array([[0.0, 0.64, 0.77], [-0.64, 0.0, 0.77], [0.0, -0.64, 0.77], [0.64, 0.0, 0.77]])
state = {"fractions": [], "hold": False, "drawn": None}


def show_the_panel():
    """The panel's settings with the Photographs list drawn into a real layout (a popup: Blender 3.4
    has no API for the sidebar's tab); a failure of the drawing is recorded, and fails the test."""

    def draw(menu, context):
        try:
            panels.draw_reconstruct_settings(menu.layout, context.scene.shadecut)
            state["drawn"] = True
        except Exception as error:  # noqa: BLE001 - reported by the step that waits for the drawing
            state["drawn"] = error

    with bpy.context.temp_override(**view3d_override()):
        bpy.context.window_manager.popup_menu(draw, title="ShadeCut")


def add_photographs(scene) -> None:
    directory = Path(tempfile.mkdtemp())
    names = [f"sphere_{index}.png" for index in range(len(AROUND))]
    for name, light in zip(names, AROUND):
        shadecut.save_image(directory / name, shadecut.render(scene.normals, light, 0.8, scene.mask), scene.mask)
    assert bpy.ops.shadecut.photographs_add(directory=str(directory),
                                            files=[{"name": name} for name in names]) == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    settings.light_source = "DIRECTION"
    for row, light in zip(settings.photographs, AROUND):
        row.direction = light


def steps():
    """The test as a generator: each yield waits for Blender's next timer tick."""
    shadecut.register()
    record_progress(state)
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=256)
    add_photographs(scene)
    show_the_panel()
    for _ in range(50):
        if state["drawn"] is not None:
            break
        yield
    assert state["drawn"] is True, f"the panel with the Photographs list was not drawn: {state['drawn']}"
    print("ui: the panel drew the Photographs list")
    bpy.context.window_manager.windows[0].event_simulate(type="ESC", value="PRESS")  # closes the popup
    yield
    bpy.ops.ed.undo_push(message="ShadeCut test: before")
    before = meshes()

    yield from reconstruct_until(lambda: meshes() != before, "no result")
    assert meshes() - before == {"sphere_0"}, meshes() - before
    obj = bpy.data.objects["sphere_0"]
    nodes = obj.active_material.node_tree.nodes
    base_colour = nodes["Principled BSDF"].inputs["Base Color"].links[0].from_node.image.name
    assert base_colour == "sphere_0 albedo" and "sphere_0 normals" in bpy.data.images, base_colour
    print(f"ui: four photographs gave '{obj.name}' after {len(state['fractions'])} progress calls")

    yield from undo_then_cancel(state, before)
    print("ui: all checks passed")


run_steps_then_exit(steps(), 0.1)
