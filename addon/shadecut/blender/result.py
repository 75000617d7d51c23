"""New datablocks that show a reconstruction: the mesh object, its material, optional images.

Everything here is created, never modified: the user's images, lights and objects stay as they were.
"""

from __future__ import annotations

import bpy
import numpy as np

from ..imaging import normal_colors, residual_share, unit_height
from .mesh import MeshError, depth_mesh
from .wording import with_article


UV_MAP = "UVMap"  # the result mesh's UV map (mesh.depth_mesh)
# The nodes wire_maps adds, by name: applying the maps again replaces them.
NORMAL_TEXTURE, NORMAL_NODE = "ShadeCut normals", "ShadeCut normal map"
HEIGHT_TEXTURE, HEIGHT_NODE = "ShadeCut height", "ShadeCut displacement"


def _float_image(name: str, rgba: np.ndarray) -> bpy.types.Image:
    """A new float image datablock holding (H, W, 4) data, row 0 at the top, not colour managed."""
    height, width = rgba.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(np.ascontiguousarray(rgba[::-1], dtype=np.float32).ravel())
    image.pack()  # generated pixels live only in memory; packing keeps them in the saved .blend
    return image


def albedo_image(name: str, albedo: np.ndarray, mask: np.ndarray) -> bpy.types.Image:
    """The de-lit colour, (H, W, 3) linear RGB or (H, W) grey albedo: the image's colour without its
    shading and shadows, a float image (alpha = mask) for the material's Base Color."""
    rgb = albedo if albedo.ndim == 3 else np.repeat(albedo[..., None], 3, axis=2)
    return _float_image(name, np.dstack([rgb, mask.astype(np.float32)]))


def normal_map_image(name: str, normals: np.ndarray, mask: np.ndarray) -> bpy.types.Image:
    """The normals as a tangent-space normal map of the result's UVs (imaging.normal_colors), alpha = mask.

    The result lies in its object's XY plane, image right = +X = increasing U, image up = +Y =
    increasing V, so the camera frame is the UVs' tangent frame. Colour and alpha are independent
    (channel packed): the colour of a masked-out pixel stays the flat normal.
    """
    image = _float_image(name, np.dstack([normal_colors(normals, mask), mask.astype(np.float32)]))
    image.alpha_mode = "CHANNEL_PACKED"
    return image


def height_image(name: str, height: np.ndarray) -> bpy.types.Image:
    """A 0..1 height image (H, W) (imaging.unit_height) as a grey float image, alpha 1."""
    return _float_image(name, np.dstack([height, height, height, np.ones_like(height)]))


def residual_image(name: str, residual: np.ndarray, albedo_map: np.ndarray, mask: np.ndarray) -> bpy.types.Image:
    """How far the photograph is from the result (Reconstruction.residual, (H, W)) as a share of the
    albedo there (imaging.residual_share), a grey float image, alpha = mask."""
    share = residual_share(residual, albedo_map)
    return _float_image(name, np.dstack([share, share, share, mask.astype(np.float32)]))


def _texture_node(nodes, image: bpy.types.Image, location) -> bpy.types.Node:
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.extension = "EXTEND"  # the UVs reach the image's edge pixels' centres: never wrap around
    texture.location = location
    return texture


def wire_maps(material: bpy.types.Material, normal_image: bpy.types.Image | None,
              height: tuple[bpy.types.Image, float, float] | None, *, shader: bpy.types.Node,
              output: bpy.types.Node, uv_map: str, muted: bool) -> None:
    """Adds to ``material``'s nodes the normal map (Image Texture -> Normal Map node, tangent space,
    ``uv_map``) into ``shader``'s Normal, and the height (image, zero level, scale in object units)
    through a Displacement node into ``output``'s Displacement; those two last links ``muted`` or not.
    The new nodes are named "ShadeCut ..."; ones of those names left by an earlier call are replaced."""
    nodes, links = material.node_tree.nodes, material.node_tree.links
    x, y = shader.location
    if normal_image is not None:
        for name in (NORMAL_TEXTURE, NORMAL_NODE):
            if name in nodes:
                nodes.remove(nodes[name])
        texture = _texture_node(nodes, normal_image, (x - 560, y - 320))
        texture.name, texture.label = NORMAL_TEXTURE, "Normal map"
        normal_map = nodes.new("ShaderNodeNormalMap")
        normal_map.name = NORMAL_NODE
        normal_map.space, normal_map.uv_map = "TANGENT", uv_map
        normal_map.location = (x - 220, y - 320)
        links.new(texture.outputs["Color"], normal_map.inputs["Color"])
        links.new(normal_map.outputs["Normal"], shader.inputs["Normal"]).is_muted = muted
    if height is not None:
        for name in (HEIGHT_TEXTURE, HEIGHT_NODE):
            if name in nodes:
                nodes.remove(nodes[name])
        image, zero, scale = height
        texture = _texture_node(nodes, image, (x - 560, y - 620))
        texture.name, texture.label = HEIGHT_TEXTURE, "Height map"
        displacement = nodes.new("ShaderNodeDisplacement")
        displacement.name = HEIGHT_NODE
        displacement.location = (output.location.x, output.location.y - 620)
        displacement.inputs["Midlevel"].default_value = zero
        displacement.inputs["Scale"].default_value = scale
        links.new(texture.outputs["Color"], displacement.inputs["Height"])
        links.new(displacement.outputs["Displacement"], output.inputs["Displacement"]).is_muted = muted


def _result_material(name: str, source_image: bpy.types.Image | None, normal_image: bpy.types.Image | None,
                     height: tuple[bpy.types.Image, float, float] | None) -> bpy.types.Material:
    """The result's material: the source image as Base Color; the normal map through a Normal Map
    node (tangent space, UV_MAP) into the Normal; the height (image, zero level, scale in scene
    units) through a Displacement node into the output's Displacement. Those two links are muted:
    the result's geometry already has the shape, and the maps would add it a second time. They are
    wired for a flat surface (see :func:`apply_maps`, or unmute them on a plane with the same UVs)."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    shader = nodes.get("Principled BSDF")
    x, y = shader.location
    if source_image is not None:
        texture = _texture_node(nodes, source_image, (x - 320, y))
        links.new(texture.outputs["Color"], shader.inputs["Base Color"])
    wire_maps(material, normal_image, height, shader=shader, output=nodes.get("Material Output"),
              uv_map=UV_MAP, muted=True)
    return material


def _displace(obj: bpy.types.Object, height: tuple[bpy.types.Image, float, float]) -> None:
    """A Displace modifier that pushes the flat grid up by the height image (see height_image),
    ``height`` = (image, zero level, scale in scene units)."""
    image, zero, scale = height
    texture = bpy.data.textures.new(image.name, type="IMAGE")
    texture.image = image
    texture.extension = "EXTEND"
    modifier = obj.modifiers.new("ShadeCut height", "DISPLACE")
    modifier.texture = texture
    modifier.texture_coords = "UV"
    modifier.uv_layer = UV_MAP
    modifier.direction = "Z"
    modifier.space = "LOCAL"
    modifier.mid_level = zero
    modifier.strength = scale


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
    height_map: bool = False,
    albedo: np.ndarray | None = None,
) -> bpy.types.Object:
    """Links a new object showing depth (H, W) pixel units to the active collection, at the 3-D
    cursor, and selects it.

    The object is called ``name``, or ``name.001`` and so on when that is taken; its mesh, material
    and images are named after the object's own name, so that a later result never takes over an
    earlier one's datablocks.
    ``displace``: a flat grid carrying a Displace modifier and a height image instead of real heights.
    ``normal_map``, ``height_map``: also a packed tangent-space normal map / height image, "<name>
    normals" / "<name> height", wired into the material (the displaced grid's height image is reused).
    ``albedo``: the de-lit colour (H, W, 3) or grey albedo (H, W), packed as "<name> albedo" and the
    material's Base Color in place of ``source_image``.
    Raises MeshError (see :func:`depth_mesh`, :func:`check_collection`) before creating anything;
    anything else raised on the way removes what was created before it goes on.
    """
    check_collection(context.collection)
    created = _Created()
    try:
        return _build_result(context, name, depth, normals, mask, created, source_image=source_image, width=width,
                             depth_scale=depth_scale, density=density, displace=displace, normal_map=normal_map,
                             height_map=height_map, albedo=albedo)
    except BaseException:
        created.remove()
        raise


def check_collection(collection: bpy.types.Collection) -> None:
    """MeshError when ``collection`` (the active one, which takes the result) cannot take a new object:
    one linked from a library is read-only, and Blender would refuse the link after everything else
    was made."""
    if collection.library is not None:
        raise MeshError(f"the active collection '{collection.name}' is linked from the library "
                        f"'{collection.library.filepath}' and cannot take a new object: make another "
                        "collection active in the Outliner")


class _Created:
    """The datablocks a result made so far, removed together when it fails half-way."""

    def __init__(self):
        self.blocks: list = []

    def add(self, block):
        self.blocks.append(block)
        return block

    def remove(self) -> None:
        kinds = {bpy.types.Object: bpy.data.objects, bpy.types.Mesh: bpy.data.meshes,
                 bpy.types.Material: bpy.data.materials, bpy.types.Image: bpy.data.images}
        for block in reversed(self.blocks):
            try:
                next(store for kind, store in kinds.items() if isinstance(block, kind)).remove(block)
            except ReferenceError:  # removed with its user already
                pass


def _build_result(context, name, depth, normals, mask, created: _Created, *, source_image, width, depth_scale,
                  density, displace, normal_map, height_map, albedo) -> bpy.types.Object:
    unit = width / depth.shape[1]
    height = None
    if displace or height_map:
        values, zero, span = unit_height(depth, mask)
        height = (values, zero, span * unit * depth_scale)
        if not np.isfinite(np.float32(height[2])):
            raise MeshError("the displacement strength would not be a finite number: lower the width or the depth scale")
    mesh = created.add(depth_mesh(name, np.zeros_like(depth) if displace else depth, mask,
                                  size=width, depth_scale=depth_scale, step=density))
    obj = created.add(bpy.data.objects.new(name, mesh))
    name = obj.name  # "<image>.001" when an earlier result has the image's name
    mesh.name = name
    obj.location = context.scene.cursor.location
    if height is not None:
        height = (created.add(height_image(f"{name} height", height[0])), *height[1:])
    if displace:
        _displace(obj, height)
    normal_image = created.add(normal_map_image(f"{name} normals", normals, mask)) if normal_map else None
    if albedo is not None:
        source_image = created.add(albedo_image(f"{name} albedo", albedo, mask))
    if source_image is not None or normal_image is not None or height_map:
        mesh.materials.append(created.add(_result_material(f"{name} shading", source_image, normal_image,
                                                           height if height_map else None)))

    context.collection.objects.link(obj)
    for other in context.view_layer.objects.selected:
        other.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    return obj


class TargetError(ValueError):
    """An object that cannot take the maps (see :func:`check_target`); the message says why."""


def _target_nodes(material: bpy.types.Material) -> tuple[bpy.types.Node, bpy.types.Node]:
    """The shader that takes the normal map (the one wired to the active output's Surface when it has
    a Normal input, else the first Principled BSDF) and the active Material Output."""
    nodes = material.node_tree.nodes
    outputs = [node for node in nodes if node.type == "OUTPUT_MATERIAL"]
    output = next((node for node in outputs if node.is_active_output), outputs[0] if outputs else None)
    if output is None:
        raise TargetError(f"Material '{material.name}' has no Material Output node: add one")
    surface = output.inputs["Surface"].links
    shader = surface[0].from_node if surface else None
    if shader is None or "Normal" not in shader.inputs:
        shader = next((node for node in nodes if node.type == "BSDF_PRINCIPLED"), None)
    if shader is None:
        raise TargetError(f"Material '{material.name}' has no shader with a Normal input (Principled BSDF): "
                          "add one, or remove the material to have a new one made")
    return shader, output


def check_target(obj: bpy.types.Object | None, *, normal_map: bool, height_map: bool) -> None:
    """Raises TargetError unless :func:`apply_maps` can put the maps on ``obj``'s active material."""
    if obj is None:
        raise TargetError("No active object: select the object (a plane with the image as texture) that gets "
                          "the maps, or set Apply to to New object")
    if obj.type != "MESH":
        raise TargetError(f"Active object '{obj.name}' is {with_article(obj.type)}, not a mesh: select a mesh with "
                          "UVs, or set Apply to to New object")
    if not obj.data.uv_layers:
        raise TargetError(f"Active object '{obj.name}' has no UV map, which the maps follow: unwrap it "
                          "(Edit Mode, U), or set Apply to to New object")
    if not (normal_map or height_map):
        raise TargetError("Tick Normal map or Height map (or both): they are what goes into the active "
                          "object's material")
    material = obj.active_material
    if material is not None:
        if material.library is not None or obj.data.library is not None:
            raise TargetError(f"Material '{material.name}' is linked from a library and cannot be edited")
        if material.use_nodes and material.node_tree is not None:
            _target_nodes(material)


def apply_maps(obj: bpy.types.Object, depth: np.ndarray, normals: np.ndarray, mask: np.ndarray, *,
               normal_map: bool, height_map: bool, depth_scale: float, max_height: float) -> bpy.types.Material:
    """Puts the normal map and/or the height image, "<object> normals" / "<object> height", into
    ``obj``'s active material (a new one when it has none), linked and not muted: ``obj`` is
    meant to be flat (the artist's textured plane), its active UV map laying the image out as the
    result's UVs do. Other nodes and links stay; earlier ShadeCut map nodes are replaced. The
    height's scale is in object units, the image spanning the object's X extent (``depth_scale``,
    ``max_height`` as for the result). Raises TargetError (:func:`check_target`) before changing anything."""
    check_target(obj, normal_map=normal_map, height_map=height_map)
    xs = [corner[0] for corner in obj.bound_box]
    width = (max(xs) - min(xs)) or 1.0
    height = None
    if height_map:
        values, zero, span = unit_height(depth, mask)
        scale = span * width / depth.shape[1] * limited_depth_scale(depth, mask, width, depth_scale, max_height)
        if not np.isfinite(np.float32(scale)):
            raise TargetError("the displacement scale would not be a finite number: lower the depth scale")
        height = (values, zero, scale)

    material = obj.active_material
    if material is None:
        material = bpy.data.materials.new(f"{obj.name} material")
        material.use_nodes = True
        if obj.material_slots:  # an empty slot
            obj.active_material = material
        else:
            obj.data.materials.append(material)
    elif not material.use_nodes or material.node_tree is None:
        colour = tuple(material.diffuse_color)
        material.use_nodes = True
        shader = next((node for node in material.node_tree.nodes if node.type == "BSDF_PRINCIPLED"), None)
        if shader is not None:
            shader.inputs["Base Color"].default_value = colour
    shader, output = _target_nodes(material)
    normal_image = normal_map_image(f"{obj.name} normals", normals, mask) if normal_map else None
    if height is not None:
        height = (height_image(f"{obj.name} height", height[0]), *height[1:])
    uv_layers = obj.data.uv_layers
    uv_map = next((layer.name for layer in uv_layers if layer.active_render), uv_layers.active.name)
    wire_maps(material, normal_image, height, shader=shader, output=output, uv_map=uv_map, muted=False)
    return material
