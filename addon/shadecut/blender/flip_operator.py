"""Flip: a ShadeCut result turned inside out (a dome into its hollow), in one undo step.

Under a light near the viewer the image cannot tell a surface from its inversion, and the
Reconstruct operator says so (:func:`report_orientation`'s warning, from
``stats.orientation_ambiguous``); this operator gives the other answer. It inverts what the result object shows, the way :func:`shadecut.flip` inverts a
depth map and its normals (depth z -> -z, lowest point at 0 again; normals (nx, ny, nz) ->
(-nx, -ny, nz)):

- the mesh's heights (z -> top - z in the object's frame) when they are real heights;
- the height image of a displaced grid or of the material's height map (h -> 1 - h, its zero level
  likewise, so that every displacement changes sign);
- the tangent-space normal map (red and green, the normal's x and y, -> 1 - value).

The images are replaced by inverted copies rather than changed in place: image pixels are not part
of Blender's undo, the images a material or modifier points to are, so Ctrl+Z gives the result back.
A material with the maps that another object uses too is copied for the flipped object first, so
that a plane sharing a result's material flips alone. In Edit Mode the edit mesh is changed.
"""

from __future__ import annotations

from typing import Optional

import bmesh
import bpy
import numpy as np

from .result import HEIGHT_NODE, HEIGHT_TEXTURE, NORMAL_TEXTURE

RESULT_PROPERTY = "shadecut_result"  # set on the objects the Reconstruct operator builds
DISPLACE_MODIFIER = "ShadeCut height"  # result._displace's modifier


AMBIGUOUS_WARNING = ("The image cannot tell this shape from its inversion (a dome from a hollow: the light is "
                     "near the viewer); the outline, or for a relief the light from above, chose. If it came out "
                     "the wrong way, click Flip")


def report_orientation(operator, result) -> None:
    """After a reconstruction: warns when the image could not choose the result's orientation
    (``stats.orientation_ambiguous``), pointing to Flip."""
    if result.stats.orientation_ambiguous:
        operator.report({"WARNING"}, AMBIGUOUS_WARNING)


def _inverted_image(image: bpy.types.Image, channels: tuple[int, ...]) -> bpy.types.Image:
    """A packed float copy of ``image`` with ``channels`` (0 = red, ...) turned to 1 - value."""
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(-1, 4)
    for channel in channels:
        pixels[:, channel] = 1.0 - pixels[:, channel]
    copy = bpy.data.images.new(image.name, width, height, alpha=True, float_buffer=True)
    copy.colorspace_settings.name = image.colorspace_settings.name
    copy.alpha_mode = image.alpha_mode
    copy.pixels.foreach_set(pixels.ravel())
    copy.pack()
    return copy


def _material_nodes(obj: bpy.types.Object):
    for slot in obj.material_slots:
        if slot.material is not None and slot.material.use_nodes:
            yield slot.material.node_tree.nodes


def _displace_modifier(obj: bpy.types.Object) -> Optional[bpy.types.Modifier]:
    modifier = obj.modifiers.get(DISPLACE_MODIFIER)
    return modifier if modifier is not None and modifier.type == "DISPLACE" else None


def flippable(obj: Optional[bpy.types.Object]) -> bool:
    """Whether ``obj`` shows a ShadeCut result: a result object, or one whose material got its maps."""
    if obj is None or obj.type != "MESH":
        return False
    if obj.get(RESULT_PROPERTY):
        return True
    return any(NORMAL_TEXTURE in nodes or HEIGHT_TEXTURE in nodes for nodes in _material_nodes(obj))


def _flip_heights(mesh: bpy.types.Mesh) -> None:
    """z -> top - z on every vertex; in Edit Mode on the edit mesh, which Blender writes back over the
    mesh's vertices when the mode is left (a change to those alone would be lost)."""
    if mesh.is_editmode:
        edit = bmesh.from_edit_mesh(mesh)
        if edit.verts:
            top = max(vertex.co.z for vertex in edit.verts)
            for vertex in edit.verts:
                vertex.co.z = top - vertex.co.z
        bmesh.update_edit_mesh(mesh)
        return
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    z = co[2::3]
    if z.size:
        co[2::3] = z.max() - z
    mesh.vertices.foreach_set("co", co)
    mesh.update()


def _own_materials(obj: bpy.types.Object) -> None:
    """Gives ``obj`` its own copy of each material with ShadeCut maps that something else uses too
    (another object, a result sharing it): flipping ``obj`` must not turn another object's maps over."""
    for slot in obj.material_slots:
        material = slot.material
        if material is not None and material.use_nodes and material.users > 1 and any(
                name in material.node_tree.nodes for name in (NORMAL_TEXTURE, HEIGHT_TEXTURE)):
            slot.material = material.copy()


def flip_object(obj: bpy.types.Object) -> list[str]:
    """Inverts the result ``obj`` shows (see the module's docstring); what was inverted, in words."""
    done = []
    modifier = _displace_modifier(obj)
    if modifier is None and obj.get(RESULT_PROPERTY):
        _flip_heights(obj.data)
        done.append("heights")
    if modifier is not None and modifier.texture is not None and modifier.texture.image is not None:
        modifier.texture.image = _inverted_image(modifier.texture.image, (0, 1, 2))
        modifier.mid_level = 1.0 - modifier.mid_level
        done.append("heights")
    _own_materials(obj)
    inverted: dict[str, bpy.types.Image] = {}  # one copy per image, shared as the original was
    for nodes in _material_nodes(obj):
        for name, channels, what in ((NORMAL_TEXTURE, (0, 1), "normal map"), (HEIGHT_TEXTURE, (0, 1, 2), "height map")):
            texture = nodes.get(name)
            if texture is None or texture.image is None:
                continue
            key = f"{name}/{texture.image.name}"
            if key not in inverted:
                inverted[key] = _inverted_image(texture.image, channels)
            texture.image = inverted[key]
            done.append(what)
        displacement = nodes.get(HEIGHT_NODE)
        if displacement is not None:
            displacement.inputs["Midlevel"].default_value = 1.0 - displacement.inputs["Midlevel"].default_value
    return list(dict.fromkeys(done))


class SHADECUT_OT_flip(bpy.types.Operator):
    """Turn the active ShadeCut result inside out (a dome into its hollow): the other answer when the
    light was near the viewer and the reconstruction said the image could not tell"""

    bl_idname = "shadecut.flip"
    bl_label = "Flip"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return flippable(context.active_object)

    def execute(self, context):
        obj = context.active_object
        done = flip_object(obj)
        if not done:
            self.report({"WARNING"}, f"'{obj.name}' shows no ShadeCut heights or maps to flip: nothing changed")
            return {"CANCELLED"}
        inverted = " and ".join(done) if len(done) < 3 else ", ".join(done[:-1]) + " and " + done[-1]
        self.report({"INFO"}, f"'{obj.name}' flipped: its {inverted} {'is' if len(done) == 1 else 'are'} inverted "
                              "(Ctrl+Z undoes it)")
        return {"FINISHED"}
