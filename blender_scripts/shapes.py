"""The shape catalogue of the synthetic datasets: every shape built as Blender objects, and mesh files.

Each builder takes the dataset's seed and returns unit-sized mesh objects not linked to any scene,
facing -Y (the fitted camera's view of shadecut.blender.lambertian). Used by make_dataset.py and
measure_lambertian.py, which put this folder and the repository's addon/ folder on ``sys.path``
(``shadecut`` must be importable before this module is).
"""

from __future__ import annotations

import math
import zlib
from pathlib import Path

import bpy
import bmesh
import numpy as np

from shadecut.blender.capabilities import mesh_importer
from shadecut.blender.mesh import depth_mesh
from shadecut.synthetic import read_depth_text

MOZART = Path(__file__).resolve().parents[1] / "data" / "mozart" / "moz256.depth"
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".blend")


class MeshFileError(Exception):
    """A mesh file that cannot be read, or that holds no mesh; the message says which and why."""


def shape_rng(seed: int, *names: str) -> np.random.Generator:
    """A generator that depends only on the seed and the names (not on other shapes or shards)."""
    return np.random.default_rng([seed, *(zlib.crc32(name.encode()) for name in names)])


def _object(name: str, mesh: bpy.types.Mesh, rotation=(0.0, 0.0, 0.0)) -> bpy.types.Object:
    ob = bpy.data.objects.new(f"ShadeCut {name}", mesh)
    ob.rotation_euler = rotation
    return ob


def _smooth(mesh: bpy.types.Mesh) -> bpy.types.Mesh:
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
    mesh.update()
    return mesh


def _bmesh_mesh(name: str, build) -> bpy.types.Mesh:
    work = bmesh.new()
    try:
        build(work)
        mesh = bpy.data.meshes.new(name)
        work.to_mesh(mesh)
    finally:
        work.free()
    return _smooth(mesh)


def _revolution_mesh(name: str, points: np.ndarray, wrap_v: bool) -> bpy.types.Mesh:
    """A quad mesh from a (U, V, 3) grid of points closed around U (and V when ``wrap_v``).

    Quads (i, j), (i+1, j), (i+1, j+1), (i, j+1) face along dP/du x dP/dv, outward for the surfaces
    below.
    """
    nu, nv = points.shape[:2]
    index = np.arange(nu * nv).reshape(nu, nv)
    i = np.arange(nu)[:, None]
    j = np.arange(nv if wrap_v else nv - 1)[None, :]
    quads = np.stack(np.broadcast_arrays(index[i, j], index[(i + 1) % nu, j], index[(i + 1) % nu, (j + 1) % nv],
                                         index[i, (j + 1) % nv]), axis=-1).reshape(-1, 4)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(nu * nv)
    mesh.vertices.foreach_set("co", points.reshape(-1).astype(np.float32))
    mesh.loops.add(quads.size)
    mesh.loops.foreach_set("vertex_index", quads.reshape(-1).astype(np.int32))
    mesh.polygons.add(len(quads))
    mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(quads), 4, dtype=np.int32))
    mesh.update(calc_edges=True)
    return _smooth(mesh)


def _sphere_mesh(name: str, segments: int, rings: int) -> bpy.types.Mesh:
    """A unit UV sphere about Z: triangle fans at the poles, quads between its rings, every face's
    corners in one fixed order.

    Not bmesh's create_uvsphere: in Blender 5 its faces' first corners vary from one call to the next,
    so Cycles splits a quad along either diagonal and the same seed renders a few pixels differently.
    """
    polar = np.pi * np.arange(1, rings) / rings
    azimuth = 2 * np.pi * np.arange(segments) / segments
    ring_points = np.stack(np.broadcast_arrays(np.sin(polar)[:, None] * np.cos(azimuth), np.sin(polar)[:, None]
                                               * np.sin(azimuth), np.cos(polar)[:, None]), axis=-1)
    points = np.concatenate([[(0.0, 0.0, 1.0)], ring_points.reshape(-1, 3), [(0.0, 0.0, -1.0)]])
    south = len(points) - 1

    def index(ring, segment):
        return 1 + (ring - 1) * segments + segment % segments

    faces = [(0, index(1, s), index(1, s + 1)) for s in range(segments)]
    faces += [(index(r, s), index(r + 1, s), index(r + 1, s + 1), index(r, s + 1))
              for r in range(1, rings - 1) for s in range(segments)]
    faces += [(south, index(rings - 1, s + 1), index(rings - 1, s)) for s in range(segments)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(points.tolist(), [], faces)
    mesh.update(calc_edges=True)
    return _smooth(mesh)


def make_sphere(seed: int) -> list:
    return [_object("sphere", _sphere_mesh("sphere", segments=128, rings=64))]


def make_torus(seed: int) -> list:
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 96, endpoint=False), np.linspace(0, 2 * np.pi, 48, endpoint=False),
                       indexing="ij")
    major, minor = 1.0, 0.4
    points = np.stack([(major + minor * np.cos(v)) * np.cos(u), (major + minor * np.cos(v)) * np.sin(u),
                       minor * np.sin(v)], axis=-1)
    # Axis tilted 60 degrees from the image's up toward the viewer: the hole shows, seen obliquely.
    return [_object("torus", _revolution_mesh("torus", points, wrap_v=True), (math.radians(60), 0, 0))]


def make_suzanne(seed: int) -> list:
    ob = _object("suzanne", _bmesh_mesh("suzanne", lambda bm: bmesh.ops.create_monkey(bm)))
    ob.modifiers.new("Subdivision", "SUBSURF").levels = 2
    return [ob]


def make_vase(seed: int) -> list:
    """A lathe vase (open top, belly, neck, lip), leaning 25 degrees toward the viewer so that the inside
    of the mouth (a concave surface) shows."""
    u, h = np.meshgrid(np.linspace(0, 2 * np.pi, 96, endpoint=False), np.linspace(0.0, 2.0, 80), indexing="ij")
    radius = 0.3 + 0.4 * np.exp(-((h - 0.6) / 0.45) ** 2) + 0.12 * np.exp(-((h - 2.0) / 0.2) ** 2)
    points = np.stack([radius * np.cos(u), radius * np.sin(u), h - 1.0], axis=-1)
    return [_object("vase", _revolution_mesh("vase", points, wrap_v=False), (math.radians(25), 0, 0))]


def _height_field_object(name: str, depth: np.ndarray, mask: np.ndarray) -> bpy.types.Object:
    # depth_mesh builds the field seen from +Z; turning it 90 degrees about X makes it face -Y.
    return _object(name, depth_mesh(name, depth, mask, size=2.0), (math.radians(90), 0, 0))


def make_mozart(seed: int) -> list:
    depth = read_depth_text(MOZART)
    return [_height_field_object("mozart", depth, depth > 0)]


def make_bumps(seed: int) -> list:
    """Six Gaussian bumps and dents at seeded places, sizes and heights on a 128 x 128 field."""
    rng = shape_rng(seed, "bumps", "layout")
    size = 128
    rows, cols = np.mgrid[0:size, 0:size] / (size - 1) - 0.5
    depth = np.zeros((size, size))
    for sign in (1, -1, 1, -1, 1, -1):
        cx, cy = rng.uniform(-0.32, 0.32, 2)
        sigma = rng.uniform(0.06, 0.12)
        amplitude = sign * rng.uniform(0.08, 0.15)
        depth += amplitude * np.exp(-((cols - cx) ** 2 + (rows - cy) ** 2) / (2 * sigma**2))
    return [_height_field_object("bumps", depth * size, np.ones((size, size), bool))]


BUILDERS = {"sphere": make_sphere, "torus": make_torus, "suzanne": make_suzanne, "vase": make_vase,
            "mozart": make_mozart, "bumps": make_bumps}
CATALOGUE = tuple(BUILDERS)


def load_mesh_file(path: Path) -> list:
    """The mesh objects of a file, unlinked from every scene; MeshFileError when there are none."""
    before = set(bpy.data.objects)
    suffix = path.suffix.lower()
    try:
        if suffix == ".blend":
            with bpy.data.libraries.load(str(path), link=False) as (source, target):
                target.objects = list(source.objects)
        else:
            mesh_importer(suffix)(filepath=str(path))
    except (OSError, RuntimeError, ValueError) as error:  # RuntimeError: also MissingCapability
        raise MeshFileError(f"cannot read mesh {path}: {error}") from None
    new = [ob for ob in bpy.data.objects if ob not in before]
    for ob in new:
        for collection in list(ob.users_collection):
            collection.objects.unlink(ob)
    meshes = [ob for ob in new if ob.type == "MESH" and len(ob.data.vertices) > 0]
    for ob in new:
        if ob not in meshes:
            bpy.data.objects.remove(ob)
    if not meshes:
        raise MeshFileError(f"cannot read mesh {path}: it holds no mesh with vertices")
    return meshes


def remove_objects(objects: list) -> None:
    """Deletes objects made by a builder or by load_mesh_file, and their meshes once nothing uses them."""
    for ob in objects:
        mesh = ob.data
        bpy.data.objects.remove(ob)
        if mesh.users == 0:
            bpy.data.meshes.remove(mesh)
