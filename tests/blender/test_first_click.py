"""The artist's first clicks in Blender's factory scene (the cube, the point lamp "Light", the
camera): defaults that succeed, results at the 3-D cursor that never take over earlier ones, a clear
report for a lamp that is not a Sun, and a panel in artist words."""

import itertools
import re
import types

import bpy
import numpy as np
import pytest
from mathutils import Vector

import shadecut
from shadecut import synthetic
from shadecut.blender import CLASSES, panels, reconstruct_job
from shadecut.blender.properties import ShadeCutReconstructSettings
from test_addon import add_sun, scene_state

LIGHT = (1.0, 0.0, 1.0)
RESEARCH_SETTINGS = {"method", "labels", "data_weight", "integrator"}
# Longer names are cut off ("Data wei...") in the sidebar's default width.
MAX_NAME_LENGTH = 14


@pytest.fixture
def factory_scene():
    bpy.ops.wm.read_factory_settings()
    shadecut.register()
    yield bpy.context.scene
    shadecut.unregister()


def _sphere(tmp_path):
    scene = synthetic.sphere(light=LIGHT, size=64)
    path = tmp_path / "sphere.png"
    shadecut.save_image(path, scene.image, scene.mask)
    return bpy.data.images.load(str(path))


def _bricks(tmp_path):
    path = tmp_path / "bricks.png"
    shadecut.save_image(path, synthetic.bricks((0.6, 0.3, 1.0), size=64).image)
    return bpy.data.images.load(str(path))


def _color_grid(_tmp_path):
    bpy.ops.image.new(name="Color grid", width=128, height=128, generated_type="COLOR_GRID")
    return bpy.data.images["Color grid"]


@pytest.fixture
def sphere_image(factory_scene, tmp_path):
    image = _sphere(tmp_path)
    factory_scene.shadecut.image = image
    return image


class Reports:
    def report(self, kind, message):
        self.last = (kind, message)


def mesh_coordinates(obj):
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co


@pytest.mark.parametrize("make_image, name", [(_sphere, "sphere"), (_bricks, "bricks"), (_color_grid, "Color grid")])
def test_the_first_click_succeeds_with_the_defaults(factory_scene, tmp_path, make_image, name):
    """Only the image is chosen: every other setting is as the add-on starts."""
    factory_scene.shadecut.image = make_image(tmp_path)
    cube = [tuple(row) for row in bpy.data.objects["Cube"].matrix_world]
    objects_before = set(bpy.data.objects)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    (result,) = set(bpy.data.objects) - objects_before
    assert result.name == name and result.type == "MESH" and len(result.data.vertices) > 0
    assert [tuple(row) for row in bpy.data.objects["Cube"].matrix_world] == cube


def test_the_result_lands_at_the_3d_cursor(factory_scene, sphere_image):
    factory_scene.cursor.location = (3.0, -2.0, 1.5)
    factory_scene.cursor.rotation_euler = (0.3, 0.2, 0.1)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    result = bpy.context.active_object
    assert tuple(result.location) == pytest.approx((3.0, -2.0, 1.5))
    assert tuple(result.rotation_euler) == (0.0, 0.0, 0.0)  # upright, as the image was seen


def _result_datablocks(obj):
    """The names of what a result brought: its object, mesh, material, textures and images."""
    names = {"objects": {obj.name}, "meshes": {obj.data.name},
             "materials": {material.name for material in obj.data.materials}}
    names["textures"] = {modifier.texture.name for modifier in obj.modifiers if modifier.type == "DISPLACE"}
    names["images"] = {texture.image.name for texture in map(bpy.data.textures.get, names["textures"])}
    names["images"] |= {image.name for image in bpy.data.images if image.name.startswith(f"{obj.name} normals")}
    return names


@pytest.mark.parametrize("output", ["MESH", "DISPLACE"])
def test_a_second_result_of_the_same_image_leaves_the_first_alone(factory_scene, sphere_image, output):
    settings = factory_scene.shadecut
    settings.output, settings.normal_map = output, True
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    first = bpy.context.active_object
    first_names, first_co = _result_datablocks(first), mesh_coordinates(first)
    assert first_names["images"] and (output == "MESH" or first_names["textures"])

    settings.depth_scale = 2.0  # a different surface, so that overwritten data would show
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    second = bpy.context.active_object
    assert (first.name, second.name) == ("sphere", "sphere.001")
    second_names = _result_datablocks(second)
    for kind, names in second_names.items():
        assert names.isdisjoint(first_names[kind]), kind
        assert all(name.startswith("sphere.001") for name in names), names
    assert _result_datablocks(first) == first_names
    np.testing.assert_array_equal(mesh_coordinates(first), first_co)


def test_a_point_lamp_is_reported_and_changes_nothing(factory_scene, sphere_image):
    settings = factory_scene.shadecut
    settings.light_source, settings.light_object = "OBJECT", bpy.data.objects["Light"]
    before = scene_state()
    with pytest.raises(RuntimeError, match=re.escape("Light 'Light' is a point light")) as raised:
        bpy.ops.shadecut.reconstruct()
    assert "Pick a Sun, or set Light to Estimate" in str(raised.value)
    assert scene_state() == before


def test_sun_without_a_pick_takes_the_scenes_only_sun(factory_scene, sphere_image):
    lamp = bpy.data.objects["Light"]
    lamp.data.type = "SUN"
    lamp.rotation_euler = Vector(LIGHT).to_track_quat("Z", "Y").to_euler()
    settings = factory_scene.shadecut
    settings.light_source = "OBJECT"
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_allclose(job.light, np.array(LIGHT) / np.sqrt(2), atol=1e-6)
    job.run()
    reports = Reports()
    assert reconstruct_job.finish_job(reports, bpy.context, job) == {"FINISHED"}
    assert "light of the scene's only Sun 'Light'" in reports.last[1]
    assert settings.light_object is None  # used, not picked for the artist


@pytest.mark.parametrize("suns, message", [
    (0, "No Sun picked, and the scene has none"),
    (2, "No Sun picked, and the scene has 2 ('Sun', 'Sun.001'): pick one"),
])
def test_sun_without_a_pick_and_not_one_sun_is_reported(factory_scene, sphere_image, suns, message):
    for _ in range(suns):
        add_sun(LIGHT)
    factory_scene.shadecut.light_source = "OBJECT"
    before = scene_state()
    with pytest.raises(RuntimeError, match=re.escape(message)):
        bpy.ops.shadecut.reconstruct()
    assert scene_state() == before


def property_groups():
    return [cls for cls in CLASSES if issubclass(cls, bpy.types.PropertyGroup)]


def settings_of(group):
    return [prop for prop in group.bl_rna.properties if prop.identifier not in {"rna_type", "name"}]


@pytest.mark.parametrize("group", property_groups(), ids=lambda group: group.__name__)
def test_every_setting_has_a_tooltip_and_a_short_name(factory_scene, group):
    assert settings_of(group)
    for prop in settings_of(group):
        assert prop.description.strip(), f"{prop.identifier} has no tooltip"
        assert len(prop.name) <= MAX_NAME_LENGTH, prop.name
        for item in getattr(prop, "enum_items", ()):
            assert item.description.strip(), f"{prop.identifier}: {item.identifier} has no tooltip"


class RecordingLayout:
    """Stands in for a panel's layout and records the settings drawn into it."""

    def __init__(self, drawn):
        self.drawn = drawn

    def column(self, **_options):
        return RecordingLayout(self.drawn)

    row = column

    def prop(self, _data, identifier, **_options):
        self.drawn.append(identifier)

    def operator(self, *_arguments, **_options):
        return types.SimpleNamespace()

    def template_icon(self, **_options):  # the light preview (light_preview.draw): no setting
        pass

    def template_list(self, _list_type, _list_id, _data, collection, _active_data, active, **_options):
        self.drawn += [collection, active]  # the Photographs list and its selected row


def drawn_settings(draw, settings):
    drawn = []
    draw(RecordingLayout(drawn), settings)
    return drawn


@pytest.mark.parametrize("space", ["VIEW_3D", "IMAGE_EDITOR"])
def test_the_research_settings_are_in_a_closed_advanced_sub_panel(factory_scene, space):
    panel = next(cls for cls in CLASSES if issubclass(cls, bpy.types.Panel) and cls.bl_space_type == space
                 and getattr(cls, "bl_parent_id", "") and cls.bl_label == "Advanced")
    parent = getattr(bpy.types, panel.bl_parent_id)
    assert parent.bl_space_type == space and parent.bl_region_type == panel.bl_region_type == "UI"
    assert "DEFAULT_CLOSED" in panel.bl_options

    settings = factory_scene.shadecut
    advanced = drawn_settings(panels.draw_advanced_settings, settings)
    assert RESEARCH_SETTINGS <= set(advanced)
    main = set()
    light_sources = [item.identifier for item in settings.bl_rna.properties["light_source"].enum_items]
    for scene_kind, light_source, rows in itertools.product(("object", "relief"), light_sources, (0, 4)):
        settings.scene, settings.light_source, settings.frame = scene_kind, light_source, "CAMERA"
        settings.photographs.clear()  # with several photographs, Estimate shows its hint
        for _ in range(rows):
            settings.photographs.add()
        drawn = drawn_settings(panels.draw_reconstruct_settings, settings)
        assert drawn[0] == "scene"  # what the image shows comes first
        main |= set(drawn)
    assert main.isdisjoint(RESEARCH_SETTINGS)
    assert main | set(advanced) == {prop.identifier for prop in settings_of(ShadeCutReconstructSettings)}


def test_no_height_limit_and_automatic_density_are_said_in_words(factory_scene):
    """Max height and Density once showed 0 for "no limit" and "automatic": each is now a checkbox
    with a word ("Limit", "Auto") beside a value that is greyed out while it does not apply."""
    texts = {}

    class TextLayout(RecordingLayout):
        def column(self, **_options):
            return TextLayout(self.drawn)

        row = column

        def prop(self, _data, identifier, text=None, **_options):
            self.drawn.append(identifier)
            texts[identifier] = (text, getattr(self, "active", True))

    settings = factory_scene.shadecut
    panels.draw_reconstruct_settings(TextLayout([]), settings)
    assert texts["limit_height"][0] == "Limit" and texts["auto_density"][0] == "Auto"
    assert texts["max_height"] == ("", False) and texts["density"] == ("", False)  # off by default: greyed
    assert settings.max_height > 0 and settings.density >= 1  # no 0 stands for a mode
    settings.limit_height, settings.auto_density = True, False
    panels.draw_reconstruct_settings(TextLayout([]), settings)
    assert texts["max_height"] == ("", True) and texts["density"] == ("", True)
