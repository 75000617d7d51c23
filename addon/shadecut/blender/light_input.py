"""The lights of a reconstruction as the library takes them: unit directions in the camera frame,
read from a Sun of the scene (as seen from the top or from a camera), typed, or named by the side of
the image they came from (a photograph's file name can name it); one per photograph for the panel's
Photographs."""

from __future__ import annotations

import math
import os
import re
from typing import Optional

import bpy
import numpy as np

from .. import api
from .frames import FrameError, light_in_camera_frame
from .image_input import InputError
from .wording import sentence_start, short_number

# A photograph row whose file name named no side: its side is for the user to pick.
UNPICKED_SIDE = "UNPICKED"
# A side word of the library standing whole between separators; the longest first, so that
# "rug-top-left" reads 'top-left', not 'top'.
_SIDE_WORD = re.compile("(?<![a-z0-9])(" + "|".join(re.escape(side) for side in
                                                     sorted(api.LIGHT_SIDES, key=len, reverse=True))
                        + ")(?![a-z0-9])")


def side_in_file_name(file_name: str) -> Optional[str]:
    """The side of the image (one of ``api.LIGHT_SIDES``) that a file name names as a whole word of its
    stem, case-insensitive: 'above.jpg', 'rug_top.png', 'IMG_Left.jpg', 'bottom right.png'; None when
    it names none, or two different ones."""
    stem = os.path.splitext(os.path.basename(file_name))[0].lower()
    found = {match.group(1) for match in _SIDE_WORD.finditer(re.sub(r"[\s_]+", "-", stem))}
    return found.pop() if len(found) == 1 else None


def side_of_image(image: Optional[bpy.types.Image]) -> Optional[str]:
    """The side named by the file name of ``image`` (its name when it has no file); None without one."""
    if image is None:
        return None
    return side_in_file_name(bpy.path.basename(image.filepath) or image.name)


def side_origin(sides: list[str]) -> str:
    """How the finish report names lights taken from sides of the image: at the library's one slant,
    which nobody measured, so the depth's scale is a guess."""
    named = ", ".join(sides)
    return (f"light{'s' if len(sides) > 1 else ''} from the side{'s' if len(sides) > 1 else ''} of the image "
            f"({named}) at {short_number(api.SIDE_LIGHT_SLANT_DEGREES)} degrees from the viewer: a guess, "
            "which the depth's scale follows")


def side_light(side: str, named: str, why: str = "") -> np.ndarray:
    """The unit light from ``side`` (the library's rule); InputError when no side was picked for
    ``named`` ("Photograph 2 ('x.png')", "The image"), saying ``why`` none was."""
    if side == UNPICKED_SIDE:
        raise InputError(f"{named} has no side of the image for its light{why}: pick the side the light came from")
    return api.light_from_side(side)


def side_tilt(side: str) -> float:
    """The direction in the image plane, degrees (0 = from the right, 90 = from the top), of the light
    from ``side``: the library's first_light_tilt for a first photograph lit from that side."""
    light = api.light_from_side(side)
    return math.degrees(math.atan2(light[1], light[0]))


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


def _refuse_repeated(rows, keys: list, same, fix: str) -> None:
    """InputError naming the first two photographs whose lights have the same key: ``same(first,
    second)`` says how they are the same, ``fix`` what to do."""
    seen: dict = {}
    for index, key in enumerate(keys):
        if key in seen:
            first = seen[key]
            raise InputError(f"{sentence_start(photograph_name(rows, first))} and {photograph_name(rows, index)} "
                             f"{same(first, index)}: a second photograph under the same light adds nothing. {fix}")
        seen[key] = index


def photograph_sides(rows) -> np.ndarray:
    """The unit light of each row from its side of the image; InputError for a row without a side, or
    two rows lit from the same side ('above' is 'top')."""
    lights = [side_light(row.side, sentence_start(photograph_name(rows, index)), " (its file name names none)")
              for index, row in enumerate(rows)]
    sides = [row.side for row in rows]
    _refuse_repeated(rows, [tuple(np.round(light, 9)) for light in lights],
                     lambda first, second: (f"are both lit from the {sides[first]}" if sides[first] == sides[second]
                                            else f"are lit from '{sides[first]}' and '{sides[second]}', one side"),
                     "Pick the side that lit each")
    return np.array(lights)


def photograph_suns(context, rows) -> tuple[list[bpy.types.Object], str]:
    """The Sun of each photograph: the rows' own, or with none picked the scene's Suns in name order,
    one per photograph; and how the finish report names them."""
    picked = [row.sun for row in rows]
    if all(picked):
        _refuse_repeated(rows, [sun.name for sun in picked], lambda first, _: f"both have Sun '{picked[first].name}'",
                         "Pick the Sun that lit each")
        return picked, "their Suns"
    if any(picked):
        missing = photograph_name(rows, picked.index(None))
        raise InputError(f"{sentence_start(missing)} has no Sun: pick one for every photograph, or for none to use "
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
    them; None (estimate) with Light set to Estimate, for one photograph or for enough to find theirs."""
    if settings.light_source == "ESTIMATE":
        return None, _estimated_origin(len(rows))
    if settings.light_source == "SIDE":
        return photograph_sides(rows), side_origin([row.side for row in rows])
    if settings.light_source == "DIRECTION":
        raw, origin = [row.direction for row in rows], "their typed lights"
    else:
        suns, origin = photograph_suns(context, rows)
        raw = [sun_light(context, settings, sun) for sun in suns]
    lights = [unit_light(light, f"The light of {photograph_name(rows, index)}") for index, light in enumerate(raw)]
    return np.array(lights), origin


def _estimated_origin(count: int) -> str:
    """How the finish report names the estimated light of ``count`` photographs; InputError for
    too few to estimate the lights of several."""
    if count == 1:
        return "estimated light"
    if count < api.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS:
        raise InputError(f"Light is Estimate, which finds the lights of {api.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS} or more "
                         f"photographs lit from around the subject; {count} photographs need their lights: set Light "
                         "to Sun (one per photograph), Direction (typed in each row) or Side of the image (picked in "
                         f"each row), or add photographs to have {api.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS} or more")
    return "estimated lights"
