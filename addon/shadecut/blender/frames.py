"""Directions from the Blender scene expressed in the image's camera frame (README, "Conventions").

The camera frame is x right, y up, z toward the viewer. That is exactly a Blender camera's local
frame (it looks down its -Z), so a world vector enters the frame by the camera's inverse rotation.
An image without a camera lies in the world XY plane seen from +Z: the frame is the world's.
"""

from __future__ import annotations

import math

import bpy
from mathutils import Matrix, Quaternion, Vector

from .wording import with_article

# An axis of an object's world matrix shorter than this is scaled to zero: it has no orientation.
MIN_AXIS = 1e-9


class FrameError(ValueError):
    """A light or camera that cannot give a direction; the message says what to do."""


def _checked_axes(obj: bpy.types.Object, role: str) -> Matrix:
    """The 3 x 3 part of ``obj``'s world matrix; FrameError when scale zero (or NaN) leaves it without
    a direction. ``role`` names the object in the message ("Sun", "Camera")."""
    matrix = obj.matrix_world.to_3x3()
    lengths = [column.length for column in matrix.col]
    if not all(math.isfinite(value) for row in matrix for value in row):
        raise FrameError(f"{role} '{obj.name}' has a transform that is not finite (NaN or infinite): "
                         "reset its rotation and scale")
    if min(lengths) < MIN_AXIS or abs(matrix.determinant()) < MIN_AXIS ** 3:
        raise FrameError(f"{role} '{obj.name}' (or a parent) is scaled to zero, so it has no direction: "
                         "give it a non-zero scale")
    return matrix


def world_rotation(obj: bpy.types.Object, role: str) -> Quaternion:
    """The rotation of ``obj``'s world matrix; FrameError when it has none (see :func:`_checked_axes`)."""
    return _checked_axes(obj, role).to_quaternion()


def sun_direction_world(light_object: bpy.types.Object) -> Vector:
    """Unit vector toward a Sun light, in world coordinates, as Blender lights the scene with it.

    A sun shines along the -Z axis of its world matrix, so the light lies along that matrix's Z
    column. Not its rotation: a mirrored sun (a negative scale) has a reflection there, whose
    quaternion points up to 180 degrees away from where Cycles and EEVEE take the light from.
    """
    if light_object is None:
        raise FrameError("No light chosen: pick a Sun in the ShadeCut panel, or type a direction")
    if light_object.type != "LIGHT":
        raise FrameError(f"'{light_object.name}' is not a light: pick a Sun light object")
    if light_object.data.type != "SUN":
        raise FrameError(
            f"Light '{light_object.name}' is {with_article(light_object.data.type)} light: the method assumes a "
            "distant light, so use a Sun (or type the direction)"
        )
    return _checked_axes(light_object, "Sun").col[2].normalized()


def world_to_camera_frame(direction: Vector, camera: bpy.types.Object | None) -> Vector:
    """A world direction in the camera frame of ``camera``, or unchanged when there is none."""
    if camera is None:
        return Vector(direction)
    return world_rotation(camera, "Camera").inverted() @ Vector(direction)


def light_in_camera_frame(light_object: bpy.types.Object, camera: bpy.types.Object | None) -> Vector:
    """Unit vector toward the sun ``light_object`` in the camera frame (see the module's note)."""
    return world_to_camera_frame(sun_direction_world(light_object), camera).normalized()
