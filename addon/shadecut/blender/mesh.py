"""Height fields as Blender meshes, built from numpy arrays in one pass per attribute.

Per-vertex Python loops and ``from_pydata`` take tens of seconds for a million vertices; writing
flat arrays with ``foreach_set`` takes about one (docs/blender_addon.md, "Big images", for the
measurement).
"""

from __future__ import annotations

import bpy
import numpy as np

from ..api import height_field_mesh


# Blender copies an index array in one block only when its items have the property's own type,
# unsigned 32-bit; any other type is converted item by item, about ten times slower.
INDEX = np.uint32


class MeshError(ValueError):
    """A height field that would make an empty or broken mesh; the message says why."""


def grid_geometry(depth: np.ndarray, mask: np.ndarray, *, size: float, depth_scale: float, step: int):
    """The vertices, quads and UVs of a height field in scene units, sampled every ``step`` pixels.

    Args:
        depth: (H, W) pixel units, larger = closer to the viewer.
        mask: (H, W) bool; every sampled masked pixel becomes a vertex, a quad joins four of them.
        size: width in scene units of the W pixels; u = size / W scene units per pixel.
        depth_scale: heights are depth * u * depth_scale.
        step: sampling stride in pixels (1 = one vertex per masked pixel).

    Returns:
        co: (V, 3) float32, the core's mesh (:func:`shadecut.height_field_mesh`) scaled by u and
            centred on the origin: the image seen from +Z, row 0 at the top.
        quads: (F, 4) int32 vertex indices, counter-clockwise seen from +Z.
        uv: (V, 2) float32, the pixel centre in the source image (v up, as Blender's UVs).
    """
    height, width = mask.shape
    unit = size / width
    co, quads, uv = height_field_mesh(depth, mask, step)
    with np.errstate(over="ignore", invalid="ignore"):  # depth_mesh refuses what is not finite
        co[:, 0] = (co[:, 0] - (width - 1) / 2) * unit
        co[:, 1] = (co[:, 1] + (height - 1) / 2) * unit
        co[:, 2] *= unit * depth_scale
    return co, quads, uv


def grid_edges(quads: np.ndarray, vertex_count: int) -> tuple[np.ndarray, np.ndarray]:
    """The edges of a grid of quads, and each loop's edge, without Blender's generic edge search
    (``calc_edges``), which takes seconds on millions of quads.

    The quads' corners are top-left, bottom-left, bottom-right, top-right (as
    :func:`shadecut.height_field_mesh` makes them), so every vertex starts at most one edge down and
    one to its right: numbering those two kinds in vertex order numbers every edge once.

    Returns:
        edges: (E, 2) uint32 vertex pairs, the edges down first, then the edges to the right.
        loop_edges: (F, 4) uint32, the edge from each corner to the next one of its quad.
    """
    top_left, bottom_left, bottom_right, top_right = quads.T
    below = np.full(vertex_count, -1, np.int32)
    below[top_left], below[top_right] = bottom_left, bottom_right
    right = np.full(vertex_count, -1, np.int32)
    right[top_left], right[bottom_left] = top_right, bottom_right
    tops, lefts = np.flatnonzero(below >= 0), np.flatnonzero(right >= 0)
    edges = np.empty((len(tops) + len(lefts), 2), INDEX)
    edges[:len(tops), 0], edges[:len(tops), 1] = tops, below[tops]
    edges[len(tops):, 0], edges[len(tops):, 1] = lefts, right[lefts]
    edge_down = np.cumsum(below >= 0, dtype=np.int32) - 1
    edge_right = np.cumsum(right >= 0, dtype=np.int32) + (len(tops) - 1)
    loop_edges = np.empty(quads.shape, INDEX)
    loop_edges[:, 0], loop_edges[:, 1] = edge_down[top_left], edge_right[bottom_left]
    loop_edges[:, 2], loop_edges[:, 3] = edge_down[top_right], edge_right[top_left]
    return edges, loop_edges


def depth_mesh(
    name: str,
    depth: np.ndarray,
    mask: np.ndarray,
    *,
    size: float = 2.0,
    depth_scale: float = 1.0,
    step: int = 1,
) -> bpy.types.Mesh:
    """A new mesh datablock of a height field (not linked to any scene).

    Geometry as :func:`grid_geometry`; faces only where four sampled neighbours are in the mask;
    smooth shading; a UV map "UVMap" that maps the source image onto the surface. Raises MeshError,
    before creating anything, when there would be no face or a vertex that is not finite.
    """
    co, quads, uv = grid_geometry(depth, mask, size=size, depth_scale=depth_scale, step=step)
    if len(quads) == 0:
        raise MeshError(f"sampling every {step} pixels of the {mask.shape[1]} x {mask.shape[0]} result leaves "
                        "no face: lower the density")
    if not np.isfinite(co).all():
        raise MeshError("the vertices would not be finite numbers: lower the width or the depth scale")

    edges, loop_edges = grid_edges(quads, len(co))
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(co))
    mesh.vertices.foreach_set("co", co.ravel())
    mesh.edges.add(len(edges))
    mesh.edges.foreach_set("vertices", edges.ravel())
    mesh.loops.add(quads.size)
    mesh.loops.foreach_set("vertex_index", quads.view(INDEX).ravel())  # indices >= 0: the same bits
    mesh.loops.foreach_set("edge_index", loop_edges.ravel())
    mesh.polygons.add(len(quads))
    mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=INDEX))
    mesh.polygons.foreach_set("loop_total", np.full(len(quads), 4, dtype=INDEX))
    mesh.polygons.foreach_set("use_smooth", np.ones(len(quads), dtype=bool))
    uv_layer = mesh.uv_layers.new(name="UVMap", do_init=False)  # every UV is written next
    # A UV pair viewed as one 8-byte item: numpy gathers those several times faster than pairs.
    uv_layer.data.foreach_set("uv", uv.view(np.uint64).ravel()[quads.ravel()].view(np.float32))
    mesh.update()
    return mesh
