"""New datablocks that show a reconstruction: the mesh object, its material, optional images.

Everything here is created, never modified: the user's images, lights and objects stay as they were.
"""

from __future__ import annotations

import bpy
import numpy as np

from .mesh import MeshError, depth_mesh


def _float_image(name: str, rgba: np.ndarray) -> bpy.types.Image:
    """A new float image datablock holding (H, W, 4) data, row 0 at the top, not colour managed."""
    height, width = rgba.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(np.ascontiguousarray(rgba[::-1], dtype=np.float32).ravel())
    image.pack()  # generated pixels live only in memory; packing keeps them in the saved .blend
    return image


def normal_map_image(name: str, normals: np.ndarray, mask: np.ndarray) -> bpy.types.Image:
    """The normals encoded as (n + 1) / 2 in RGB, alpha = mask (camera frame, README conventions)."""
    rgba = np.dstack([(normals + 1.0) / 2.0, mask.astype(np.float32)])
    return _float_image(name, rgba)


def _image_material(name: str, image: bpy.types.Image) -> bpy.types.Material:
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    shader = nodes.get("Principled BSDF")
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.location = (shader.location.x - 320, shader.location.y)
    links.new(texture.outputs["Color"], shader.inputs["Base Color"])
    return material


def _displace(obj: bpy.types.Object, name: str, depth: np.ndarray, mask: np.ndarray, strength: float) -> None:
    height = np.where(mask, depth, 0.0).astype(np.float32)
    rgba = np.dstack([height, height, height, np.ones_like(height)])
    texture = bpy.data.textures.new(f"{name} height", type="IMAGE")
    texture.image = _float_image(f"{name} height", rgba)
    texture.extension = "EXTEND"
    modifier = obj.modifiers.new("ShadeCut height", "DISPLACE")
    modifier.texture = texture
    modifier.texture_coords = "UV"
    modifier.uv_layer = "UVMap"
    modifier.direction = "Z"
    modifier.space = "LOCAL"
    modifier.mid_level = 0.0
    modifier.strength = strength


def limited_depth_scale(depth: np.ndarray, mask: np.ndarray, width: float, depth_scale: float,
                        max_height: float) -> float:
    """``depth_scale``, lowered where needed so that the result of ``width`` scene units is at most
    ``max_height`` scene units high (0 = no limit)."""
    height = float(np.ptp(depth[mask])) * width / depth.shape[1] * depth_scale if mask.any() else 0.0
    if max_height > 0 and height > max_height:
        return depth_scale * max_height / height
    return depth_scale


def result_object(
    context,
    name: str,
    depth: np.ndarray,
    normals: np.ndarray,
    mask: np.ndarray,
    *,
    source_image: bpy.types.Image | None,
    width: float,
    depth_scale: float,
    density: int,
    displace: bool,
    normal_map: bool,
) -> bpy.types.Object:
    """Links a new object showing depth (H, W) pixel units to the active collection, at the 3-D
    cursor, and selects it.

    The object is called ``name``, or ``name.001`` and so on when that is taken; its mesh, material
    and images are named after the object's own name, so that a later result never takes over an
    earlier one's datablocks.
    ``displace``: a flat grid carrying a Displace modifier and a height image instead of real heights.
    Raises MeshError (see :func:`depth_mesh`) before creating anything.
    """
    unit = width / depth.shape[1]
    if displace and not np.isfinite(np.float32(unit * depth_scale)):
        raise MeshError("the displacement strength would not be a finite number: lower the width or the depth scale")
    mesh = depth_mesh(name, np.zeros_like(depth) if displace else depth, mask,
                      size=width, depth_scale=depth_scale, step=density)
    obj = bpy.data.objects.new(name, mesh)
    name = obj.name  # "<image>.001" when an earlier result has the image's name
    mesh.name = name
    obj.location = context.scene.cursor.location
    if source_image is not None:
        mesh.materials.append(_image_material(f"{name} shading", source_image))
    if displace:
        _displace(obj, name, depth, mask, unit * depth_scale)
    if normal_map:
        normal_map_image(f"{name} normals", normals, mask)

    context.collection.objects.link(obj)
    for other in context.view_layer.objects.selected:
        other.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    return obj
