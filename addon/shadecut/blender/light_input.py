"""The lights of a reconstruction as the library takes them: unit directions in the camera frame,
read from a Sun of the scene (as seen from the top or from a camera) or typed; one per photograph
for the panel's Photographs."""

from __future__ import annotations

from typing import Optional

import bpy
import numpy as np

from .. import api
from .frames import FrameError, light_in_camera_frame
from .image_input import InputError
from .wording import short_number


def sun_light(context, settings, sun: bpy.types.Object) -> np.ndarray:
    """The direction toward ``sun`` in the frame the image was seen from (Seen from, Camera)."""
    context.view_layer.update()  # a script may have just moved the sun or the camera
    camera = None
    if settings.frame == "CAMERA":
        camera = settings.camera or context.scene.camera
        if camera is None:
            raise InputError("No camera: choose one in the ShadeCut panel, add one to the scene, "
                             "or set Seen from to Top view")
    try:
        return np.array(light_in_camera_frame(sun, camera))
    except FrameError as error:
        raise InputError(str(error)) from error


def unit_light(light, named: str = "The light") -> np.ndarray:
    """``light`` as the library's unit direction; InputError naming it (``named``) when it cannot be used."""
    try:
        return api.light_direction(light)
    except ValueError as error:
        shown = ", ".join(short_number(value) for value in light)
        raise InputError(f"{named} ({shown}) cannot be used: {error}") from error


def photograph_name(rows, index: int) -> str:
    """How messages name the photograph of row ``index``: "photograph 2 ('b.png')", counted from 1."""
    image = rows[index].image
    return f"photograph {index + 1}" + (f" ('{image.name}')" if image is not None else "")


def photograph_suns(context, rows) -> tuple[list[bpy.types.Object], str]:
    """The Sun of each photograph: the rows' own, or with none picked the scene's Suns in name order,
    one per photograph; and how the finish report names them."""
    picked = [row.sun for row in rows]
    if all(picked):
        for first in range(len(rows)):
            for second in range(first + 1, len(rows)):
                if picked[first] == picked[second]:
                    raise InputError(f"{photograph_name(rows, first).capitalize()} and {photograph_name(rows, second)} "
                                     f"both have Sun '{picked[first].name}': a second photograph under the same "
                                     "light adds nothing. Pick the Sun that lit each")
        return picked, "their Suns"
    if any(picked):
        missing = photograph_name(rows, picked.index(None))
        raise InputError(f"{missing.capitalize()} has no Sun: pick one for every photograph, or for none to use "
                         "the scene's Suns in name order")
    suns = sorted((obj for obj in context.scene.objects if obj.type == "LIGHT" and obj.data.type == "SUN"),
                  key=lambda sun: sun.name)
    if len(suns) != len(rows):
        raise InputError(f"{len(rows)} photographs but {len(suns)} Sun{'' if len(suns) == 1 else 's'} in the scene: "
                         "pick the Sun of each photograph in the list, or have one Sun per photograph "
                         "(taken in name order)")
    return suns, "the scene's Suns in name order (" + ", ".join(f"'{sun.name}'" for sun in suns) + ")"


def photograph_lights(context, settings, rows) -> tuple[Optional[np.ndarray], str]:
    """The unit light of each photograph row (K x 3, camera frame) and how the finish report names
    them; None (estimate) for one photograph with Light set to Estimate, which several cannot use."""
    if settings.light_source == "ESTIMATE":
        if len(rows) == 1:
            return None, "estimated light"
        raise InputError(f"Light is Estimate, which reads one photograph; {len(rows)} photographs need their "
                         "lights: set Light to Sun (one per photograph) or Direction (typed in each row)")
    if settings.light_source == "DIRECTION":
        raw, origin = [row.direction for row in rows], "their typed lights"
    else:
        suns, origin = photograph_suns(context, rows)
        raw = [sun_light(context, settings, sun) for sun in suns]
    lights = [unit_light(light, f"The light of {photograph_name(rows, index)}") for index, light in enumerate(raw)]
    return np.array(lights), origin
