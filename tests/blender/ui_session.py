"""The operator as a user meets it: invoked from the UI of a real Blender window (under Xvfb).

    xvfb-run -a blender --factory-startup --enable-event-simulate -P tests/blender/ui_session.py

Checks that the reconstruction runs on a worker thread while Blender keeps handling events, that
one undo step removes the result, that Esc cancels cleanly, and that one undo step takes the maps out
of the active object's material again. Blender's exit code is the result:
timers.py (next to this script) ends the process with the script's outcome.
"""

import sys
import tempfile
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "addon"))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # timers.py, window_steps.py
import shadecut  # noqa: E402
from shadecut import synthetic  # noqa: E402
from timers import run_steps_then_exit  # noqa: E402
from window_steps import (meshes, reconstruct_held_until, reconstruct_until, record_progress,  # noqa: E402
                          undo_then_cancel, view3d_override)

LIGHT = (1.0, 0.0, 1.0)
state = {"fractions": []}


def steps():
    """The test as a generator: each yield waits for Blender's next timer tick."""
    shadecut.register()
    record_progress(state)
    scene = synthetic.sphere(light=LIGHT, size=256)
    path = Path(tempfile.mkdtemp()) / "sphere.png"
    shadecut.save_image(path, scene.image, scene.mask)
    settings = bpy.context.scene.shadecut
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    # No image in the settings: the operator takes the one shown in an Image Editor.
    editor = next(area for area in bpy.context.window.screen.areas if area.type == "PROPERTIES")
    editor.type = "IMAGE_EDITOR"
    editor.spaces.active.image = bpy.data.images.load(str(path))
    bpy.ops.ed.undo_push(message="ShadeCut test: before")
    before = meshes()

    # Held at its first progress call, the job must leave Blender running its timers (and so its UI).
    ticks = yield from reconstruct_held_until(state, lambda: meshes() != before, "no result")
    new = meshes() - before
    assert new == {"sphere"}, new
    print(f"ui: Blender ran its timers while the worker was held; result {ticks} ticks after it was let go; "
          f"{len(state['fractions'])} progress calls, last {state['fractions'][-1]:.2f}")
    assert state["fractions"][-1] == 1.0

    yield from undo_then_cancel(state, before)

    # Apply to: Active object changes the user's own material; one undo step gives it back.
    bpy.context.view_layer.objects.active = bpy.data.objects["Cube"]
    settings = bpy.context.scene.shadecut  # the earlier undo rebuilt the scene's data
    settings.target, settings.normal_map, settings.height_map = "ACTIVE_MATERIAL", True, True
    bpy.ops.ed.undo_push(message="ShadeCut test: before applying")
    own_nodes, own_images = nodes(), images()
    yield from reconstruct_until(lambda: nodes() != own_nodes, "the maps did not reach the active object's material")
    print(f"ui: maps applied to the cube's material: {len(nodes()) - len(own_nodes)} nodes added")
    with bpy.context.temp_override(**view3d_override()):
        bpy.ops.ed.undo()
    yield
    assert nodes() == own_nodes, f"undo left the material with {sorted(set(nodes()) - set(own_nodes))}"
    assert images() == own_images, f"undo left {images() - own_images}"
    print("ui: one undo step gave the cube its own material back")
    print("ui: all checks passed")


def nodes() -> list:
    """The node names of the cube's material (looked up anew: undo rebuilds the data)."""
    return sorted(node.name for node in bpy.data.objects["Cube"].active_material.node_tree.nodes)


def images() -> set:
    return {image.name for image in bpy.data.images}


run_steps_then_exit(steps(), 0.1)
