"""The README's picture of the add-on: Blender's window with the ShadeCut panel and a reconstruction.

    xvfb-run -a -s "-screen 0 1600x900x24" blender --factory-startup --enable-event-simulate \
        -P blender_scripts/screenshot.py -- docs/addon_screenshot.png

Mozart (data/mozart) is rendered by shadecut.render with light (1, 0, 1), opened as an image and
reconstructed by the operator with the panel's defaults (the light estimated), as a user would.
"""

import ctypes
import ctypes.util
import math
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np
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


class XImage(ctypes.Structure):
    """The head of Xlib's XImage, up to the fields read here."""
    _fields_ = [("width", ctypes.c_int), ("height", ctypes.c_int), ("xoffset", ctypes.c_int),
                ("format", ctypes.c_int), ("data", ctypes.POINTER(ctypes.c_ubyte)), ("byte_order", ctypes.c_int),
                ("bitmap_unit", ctypes.c_int), ("bitmap_bit_order", ctypes.c_int), ("bitmap_pad", ctypes.c_int),
                ("depth", ctypes.c_int), ("bytes_per_line", ctypes.c_int), ("bits_per_pixel", ctypes.c_int),
                ("red_mask", ctypes.c_ulong), ("green_mask", ctypes.c_ulong), ("blue_mask", ctypes.c_ulong)]


def capture_window(window) -> np.ndarray:
    """The pixels (rows top first, RGB bytes) of Blender's window as the X server shows it. Blender's
    own screenshot reads back its OpenGL frame, which is black under Xvfb's software OpenGL; the X
    server's copy of the screen (XGetImage of the root window, cut to the window) is what a user sees."""
    x11 = ctypes.CDLL(ctypes.util.find_library("X11") or "libX11.so.6")
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
    x11.XDefaultRootWindow.restype = ctypes.c_ulong
    x11.XGetImage.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_int, ctypes.c_uint,
                              ctypes.c_uint, ctypes.c_ulong, ctypes.c_int]
    x11.XGetImage.restype = ctypes.POINTER(XImage)
    x11.XDestroyImage.argtypes = [ctypes.POINTER(XImage)]
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    display = x11.XOpenDisplay(None)
    if not display:
        raise SystemExit("screenshot: no X display (run it under xvfb-run, as the docstring says)")
    try:
        all_planes, z_pixmap = 0xFFFFFFFF, 2
        # xvfb-run starts no window manager: Blender's window sits at the screen's top-left corner.
        image = x11.XGetImage(display, x11.XDefaultRootWindow(display), 0, 0, window.width, window.height,
                              all_planes, z_pixmap)
        if not image or image.contents.bits_per_pixel != 32:
            raise SystemExit("screenshot: the X server gave no 32-bit image of the screen")
        head = image.contents
        rows = np.ctypeslib.as_array(head.data, shape=(head.height, head.bytes_per_line)).copy()
        x11.XDestroyImage(image)
    finally:
        x11.XCloseDisplay(display)
    pixels = rows[:, :head.width * 4].reshape(head.height, head.width, 4)
    return pixels[..., [2, 1, 0]]  # Xvfb's 24-bit visual keeps pixels as B, G, R, unused


def save_png(rgb: np.ndarray, path: Path) -> None:
    height, width, _ = rgb.shape
    rgba = np.dstack([rgb / 255.0, np.ones((height, width))])[::-1]  # Blender's row 0 is the bottom
    image = bpy.data.images.new("ShadeCut screenshot", width, height, alpha=False)
    image.pixels.foreach_set(rgba.astype(np.float32).ravel())
    image.filepath_raw, image.file_format = str(path), "PNG"
    image.save()


def steps():
    image = build_scene()
    yield
    arrange_window(image)
    for _ in range(5):  # a few redraws under software OpenGL
        yield
    OUTPUT.parent.mkdir(parents=True, exist_ok=True)
    save_png(capture_window(bpy.context.window_manager.windows[0]), OUTPUT)
    print(f"screenshot: {OUTPUT}")


run_steps_then_exit(steps(), 0.5)
