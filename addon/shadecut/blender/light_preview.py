"""The light preview beside the Light setting: a small Lambertian sphere (``shadecut.synthetic.sphere``)
lit from the chosen direction, so that "x right, y up, z toward you", or a Sun's aim, can be checked
at a glance. Drawn from the panel: recomputed (64 x 64 numpy, well under a millisecond) only when the
direction changes, which also follows a Sun turned in the viewport."""

from __future__ import annotations

from typing import Optional

import bpy
import bpy.utils.previews
import numpy as np

from .. import api, synthetic
from .frames import FrameError, light_in_camera_frame

SIZE = 64  # pixels of the preview's side
_state: dict = {}  # "collection": the previews collection, "light": the direction now shown


def register() -> None:
    _state["collection"] = bpy.utils.previews.new()
    _state["light"] = None


def unregister() -> None:
    collection = _state.pop("collection", None)
    if collection is not None:
        bpy.utils.previews.remove(collection)
    _state.pop("light", None)


def sphere_pixels(light, size: int = SIZE) -> np.ndarray:
    """(size, size, 4) float32 RGBA, row 0 at the bottom (as Blender stores images): a white Lambertian
    sphere lit from the unit direction ``light`` (camera frame), grey, transparent around it."""
    scene = synthetic.sphere(light=light, size=size)
    shade = np.clip(scene.image, 0.0, 1.0) ** (1 / 2.2)  # shown as is: roughly the display's encoding
    rgba = np.dstack([shade, shade, shade, scene.mask.astype(np.float32)])
    return np.ascontiguousarray(rgba[::-1], dtype=np.float32)


def panel_light(context, settings) -> Optional[tuple[float, float, float]]:
    """The unit direction toward the light the panel's settings give, camera frame, or None (Estimate,
    or a Sun, camera or direction that cannot be used: the operator reports those)."""
    try:
        if settings.light_source == "DIRECTION":
            light = settings.light_direction
        elif settings.light_source == "OBJECT":
            sun = settings.light_object
            if sun is None:
                suns = [ob for ob in context.scene.objects if ob.type == "LIGHT" and ob.data.type == "SUN"]
                sun = suns[0] if len(suns) == 1 else None
            if sun is None or sun.type != "LIGHT" or sun.data.type != "SUN":
                return None
            camera = (settings.camera or context.scene.camera) if settings.frame == "CAMERA" else None
            if settings.frame == "CAMERA" and camera is None:
                return None
            light = light_in_camera_frame(sun, camera)
        elif settings.light_source == "SIDE" and settings.light_side in api.LIGHT_SIDES:
            light = api.light_from_side(settings.light_side)
        else:
            return None
        return tuple(float(v) for v in api.light_direction(np.array(light, dtype=float)))
    except (FrameError, ValueError):
        return None


def preview_icon(light) -> int:
    """The icon id of the preview showing ``light``, recomputed when the direction changed."""
    collection = _state["collection"]
    preview = collection.get("light") or collection.new("light")
    key = tuple(round(v, 4) for v in light)
    if _state.get("light") != key:
        preview.image_size = (SIZE, SIZE)
        preview.image_pixels_float.foreach_set(sphere_pixels(light).ravel())
        _state["light"] = key
    return preview.icon_id


def draw(layout, context, settings) -> None:
    """The preview, under the light settings; nothing when there is no direction to show."""
    if "collection" not in _state:
        return
    light = panel_light(context, settings)
    if light is None:
        return
    row = layout.row()
    row.alignment = "CENTER"
    row.template_icon(icon_value=preview_icon(light), scale=4.0)
