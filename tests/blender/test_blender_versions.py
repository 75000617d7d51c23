"""What differs between Blender 3.x, 4.x and 5.x, checked in whichever Blender runs the suite
(scripts/test.sh runs it in 3.4, and scripts/blender_versions.sh in Debian 13's and sid's): sun
shadows, mesh importers, the EEVEE engine id and the colour spaces Reconstruct accepts."""

import importlib.util
import math

import bpy
import numpy as np
import pytest

from shadecut import imaging
from shadecut.blender import capabilities, lambertian
from shadecut.blender.image_input import InputError, image_pixels

LIGHT = (1.0, 0.4, 1.0)
ALBEDO = 0.8


def wall_and_cube():
    """A wall facing the camera and a cube in front of it that shades part of it under LIGHT."""
    bpy.ops.mesh.primitive_plane_add(size=4, location=(0, 1, 0), rotation=(math.pi / 2, 0, 0))
    wall = bpy.context.active_object
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0, -0.5, 0))
    return [wall, bpy.context.active_object]


def test_a_render_with_shadows_off_has_no_cast_shadow():
    """Where the cube's shadow falls with shadows on, the wall without them has the Lambertian value
    of a wall in full light: albedo times the cosine between its normal (the view axis) and LIGHT."""
    objects = wall_and_cube()
    kwargs = dict(light=LIGHT, resolution=(64, 64), albedo=ALBEDO)
    shadowed = lambertian.render_lambertian(objects, shadows=True, **kwargs)
    unshadowed = lambertian.render_lambertian(objects, shadows=False, **kwargs)
    shade = shadowed.shadow_mask
    assert shade.sum() > 50
    full_light = ALBEDO * LIGHT[2] / np.linalg.norm(LIGHT)
    assert np.all(shadowed.image[shade] < 0.1 * full_light)  # the shadow is there with shadows on
    np.testing.assert_allclose(unshadowed.image[shade], full_light, atol=1e-3)


def test_the_shadow_switch_is_stored_where_cycles_reads_it():
    light = bpy.data.lights.new("sun", "SUN")
    cycles = getattr(light, "cycles", None)
    reads_old_switch = cycles is not None and "cast_shadow" in cycles.bl_rna.properties
    for shadows in (False, True):
        capabilities.set_cast_shadow(light, shadows)
        assert (cycles.cast_shadow if reads_old_switch else light.use_shadow) is shadows


def test_eevee_is_an_engine_of_this_blender():
    engine = capabilities.eevee_engine()
    bpy.context.scene.render.engine = engine
    assert bpy.context.scene.render.engine == engine


TETRAHEDRON = [(0, 0, 0), (1, 0, 0), (0, 0, 1), (0, -1, 0)]
FACES = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]


def write_ascii_stl(path):
    lines = ["solid tetra"]
    for face in FACES:
        lines += ["facet normal 0 0 0", "outer loop", *(f"vertex {x} {y} {z}" for x, y, z in
                                                         (TETRAHEDRON[i] for i in face)), "endloop", "endfacet"]
    path.write_text("\n".join(lines + ["endsolid tetra", ""]))


def write_ascii_ply(path):
    header = ["ply", "format ascii 1.0", "element vertex 4", *(f"property float {axis}" for axis in "xyz"),
              "element face 4", "property list uchar int vertex_indices", "end_header"]
    body = [" ".join(map(str, vertex)) for vertex in TETRAHEDRON] + [f"3 {a} {b} {c}" for a, b, c in FACES]
    path.write_text("\n".join(header + body + [""]))


@pytest.fixture
def shapes(repo):
    """blender_scripts/shapes.py, which reads the mesh files of make_dataset.py."""
    spec = importlib.util.spec_from_file_location("shapes", repo / "blender_scripts" / "shapes.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("suffix, write", [(".stl", write_ascii_stl), (".ply", write_ascii_ply)])
def test_mesh_files_import_with_this_blenders_importer(tmp_path, shapes, suffix, write):
    path = tmp_path / f"tetra{suffix}"
    write(path)
    (mesh,) = shapes.load_mesh_file(path)
    positions = {tuple(round(c, 6) for c in vertex.co) for vertex in mesh.data.vertices}
    assert positions == {tuple(map(float, vertex)) for vertex in TETRAHEDRON}
    assert len(mesh.data.polygons) == 4


def test_an_unknown_mesh_suffix_is_refused_clearly():
    with pytest.raises(capabilities.MissingCapability, match=r"no '\.xyz' mesh files \(only \.obj, \.ply, \.stl\)"):
        capabilities.mesh_importer(".xyz")


def grey_image(space: str, levels=(0.25, 0.75)):
    """A 2 x 2 8-bit grey image of the given stored levels (top row first) in colour space ``space``."""
    image = bpy.data.images.new(f"grey {space}", 2, 2, alpha=False, float_buffer=False)
    image.colorspace_settings.name = space
    rows = [[level] * 3 + [1.0] for level in levels for _ in range(2)]
    image.pixels.foreach_set(np.array(rows[::-1], np.float32).ravel())  # Blender's row 0 is the bottom
    return image


def test_the_linear_spaces_include_this_blenders_scene_linear_and_data_spaces():
    linear = capabilities.linear_colour_spaces()
    names = capabilities.colour_space_names()
    assert "Non-Color" in linear and "sRGB" not in linear
    assert linear <= set(names)
    # Blender's float images default to its scene-linear space, whatever this version names it.
    float_image = bpy.data.images.new("float", 2, 2, float_buffer=True)
    assert float_image.colorspace_settings.name in linear


def test_every_linear_space_of_this_blender_is_read_as_linear():
    for space in sorted(capabilities.linear_colour_spaces()):
        image = grey_image(space)
        intensity, mask, _, _ = image_pixels(image)
        stored = np.array([[0.25, 0.25], [0.75, 0.75]])
        np.testing.assert_allclose(intensity, np.round(stored * 255) / 255, atol=1e-6, err_msg=space)
        assert mask.all()


def test_srgb_is_decoded():
    intensity, _, _, _ = image_pixels(grey_image("sRGB"))
    np.testing.assert_allclose(intensity[:, 0], imaging.srgb_to_linear(np.round(np.array([0.25, 0.75]) * 255) / 255),
                               rtol=1e-5)


def test_a_space_neither_srgb_nor_linear_gets_advice_this_blender_can_follow():
    others = [name for name in capabilities.colour_space_names()
              if name != "sRGB" and name not in capabilities.linear_colour_spaces()]
    assert others, "every colour space of this Blender is linear or sRGB: nothing to refuse"
    with pytest.raises(InputError) as refused:
        image_pixels(grey_image(others[0]))
    advice = str(refused.value).split("linear one (")[1].rstrip(")").split(", ")
    assert set(advice) == capabilities.linear_colour_spaces()
    assert "sRGB" in str(refused.value)


def test_linear_in_config_reads_what_the_configuration_declares():
    """Each way a configuration declares a linear space: a role, the Linear family (any case), data,
    an OpenColorIO 2 encoding; curves, logs and looks are not linear."""
    config = """roles:
  reference: XYZ E
  scene_linear: Wide
  data: Data
colorspaces:
  - !<ColorSpace>
    name: XYZ E
    family: Chromaticity
  - !<ColorSpace>
    name: Wide
    family: Linear
    to_reference: !<MatrixTransform> {matrix: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}
  - !<ColorSpace>
    name: Old linear
    family: linear
  - !<ColorSpace>
    name: Curve
    family: Display
    to_reference: !<FileTransform> {src: srgb.spi1d, interpolation: linear}
  - !<ColorSpace>
    name: Log encoded
    family: Linear
    encoding: log
  - !<ColorSpace>
    name: ACES
    encoding: scene-linear
  - !<ColorSpace>
    name: Data
    isdata: true
  - !<ColorSpace>
    name: Raw
    isdata: true
looks:
  - !<Look>
    name: Punchy
    family: Linear
"""
    assert capabilities.linear_in_config(config) == {"XYZ E", "Wide", "Old linear", "ACES", "Data", "Raw"}
