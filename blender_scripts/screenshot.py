"""The README's picture of the add-on: Blender's window with the ShadeCut panel and a reconstruction.

    xvfb-run -a -s "-screen 0 1600x900x24" blender --factory-startup --enable-event-simulate \
        -P blender_scripts/screenshot.py -- docs/addon_screenshot.png

Mozart (data/mozart) is rendered by shadecut.render with light (1, 0, 1), opened as an image and
reconstructed by the operator with the panel's defaults (the light estimated), as a user would.
"""

import math
import sys
import tempfile
from pathlib import Path

import bpy
from mathutils import Euler

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "addon"))
sys.path.insert(0, str(REPO / "tests" / "blender"))  # timers.py, the UI-scripting helper of the tests
import shadecut  # noqa: E402
from shadecut import synthetic  # noqa: E402
from timers import run_steps_then_exit  # noqa: E402

LIGHT = (1.0, 0.0, 1.0)
OUTPUT = Path(sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else "docs/addon_screenshot.png").resolve()


def build_scene():
    shadecut.register()
    for obj in list(bpy.data.objects):
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)
    scene = synthetic.mozart(REPO / "data" / "mozart" / "moz256.depth", LIGHT)
    path = Path(tempfile.mkdtemp()) / "mozart.png"
    shadecut.save_image(path, scene.image, scene.mask)
    image = bpy.data.images.load(str(path))

    settings = bpy.context.scene.shadecut
    settings.image, settings.width = image, 4.0  # the rest as the add-on starts: the light is estimated
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    return image


def arrange_window(image):
    window = bpy.context.window_manager.windows[0]
    window.event_simulate(type="ESC", value="PRESS")  # closes the splash screen
    screen = window.screen
    view3d = next(area for area in screen.areas if area.type == "VIEW_3D")
    properties = next(area for area in screen.areas if area.type == "PROPERTIES")
    properties.type = "IMAGE_EDITOR"
    properties.spaces.active.image = image

    space = view3d.spaces.active
    space.show_region_ui = True
    space.shading.type = "SOLID"
    space.overlay.show_floor = False
    view = space.region_3d
    view.view_rotation = Euler((math.radians(35), 0, math.radians(15))).to_quaternion()
    view.view_location = (0.0, -0.2, 0.3)
    view.view_distance = 6.5
    view.view_perspective = "PERSP"

    # Blender 3.4 has no API for the sidebar's active tab, so click it as a user would: with the
    # factory theme and scale the tabs read Item, Tool, View, ShadeCut from the top, and ShadeCut's
    # centre sits 13 px from the region's right edge and 174 px below its top.
    sidebar = next(region for region in view3d.regions if region.type == "UI")
    x, y = sidebar.x + sidebar.width - 13, sidebar.y + sidebar.height - 174
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    window.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    window.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x - 600, y=y)  # no hover highlight


def steps():
    image = build_scene()
    yield
    arrange_window(image)
    for _ in range(5):  # a few redraws under software OpenGL
        yield
    OUTPUT.parent.mkdir(parents=True, exist_ok=True)
    with bpy.context.temp_override(window=bpy.context.window_manager.windows[0]):
        bpy.ops.screen.screenshot(filepath=str(OUTPUT))
    print(f"screenshot: {OUTPUT}")


run_steps_then_exit(steps(), 0.5)
