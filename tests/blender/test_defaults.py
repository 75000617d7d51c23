"""The add-on's settings start from the library's defaults (held once, in C++)."""

import bpy
import numpy as np
import pytest

import shadecut
from shadecut import synthetic
from shadecut.blender.preferences import ShadeCutPreferences
from shadecut.blender.properties import ShadeCutReconstructSettings

DEFAULTS = shadecut.ReconstructOptions()


@pytest.fixture
def settings():
    shadecut.register()
    yield bpy.context.scene.shadecut
    shadecut.unregister()


def property_of(cls, name):
    return cls.bl_rna.properties[name]


def test_panel_and_preferences_defaults_equal_the_bound_defaults(settings):
    assert settings.labels == DEFAULTS.labels
    assert settings.data_weight == pytest.approx(DEFAULTS.data_weight)
    assert settings.integrator == DEFAULTS.integrator.name
    assert settings.fit_shading == DEFAULTS.fit_shading
    assert settings.scene == DEFAULTS.scene.name
    assert property_of(ShadeCutReconstructSettings, "labels").hard_min == shadecut.MIN_LABELS
    assert {item.identifier for item in property_of(ShadeCutReconstructSettings, "integrator").enum_items} == set(
        shadecut.Integrator.__members__)
    assert property_of(ShadeCutPreferences, "default_method").default == DEFAULTS.method.name
    assert property_of(ShadeCutPreferences, "threads").default == DEFAULTS.threads
    assert {item.identifier for item in property_of(ShadeCutPreferences, "default_method").enum_items} == set(
        shadecut.METHODS)


def test_every_setting_named_for_an_option_starts_at_its_table_default_within_its_range(settings):
    """The option table is the add-on's source too: a setting that is an option has its default and
    stays inside its range; an option without a setting takes the table's default in the call."""
    fields = {field["name"]: field for field in shadecut.option_fields()}
    shared = [name for name in ShadeCutReconstructSettings.__annotations__ if name in fields]
    assert {"scene", "labels", "data_weight", "integrator", "albedo_method", "fit_shading", "seamless"} <= set(shared)
    for name in shared:
        field, setting = fields[name], property_of(ShadeCutReconstructSettings, name)
        default = field["default"]
        expected = default.name if hasattr(default, "name") and hasattr(default, "value") else default
        if name == "method":  # "Default" is the preferences' method, whose default is the table's
            assert settings.method == "DEFAULT"
            assert property_of(ShadeCutPreferences, "default_method").default == expected
        elif isinstance(expected, float):
            assert getattr(settings, name) == pytest.approx(expected), name
        else:
            assert getattr(settings, name) == expected, name
        if field["low"] is not None and hasattr(setting, "hard_min"):
            assert setting.hard_min >= field["low"], name
        if field["high"] is not None and hasattr(setting, "hard_max"):
            assert setting.hard_max <= field["high"], name


def test_artist_sizes_by_default(settings):
    """A 4-megapixel working size, and a density chosen to keep the viewport interactive."""
    assert settings.max_resolution == 2048
    assert settings.auto_density and not settings.limit_height  # automatic density, heights as reconstructed
    assert settings.max_vertices == shadecut.MAX_VERTICES == 250_000


def test_the_first_click_needs_nothing_from_the_scene(settings):
    """Add-on defaults: the light is estimated (the factory scene has no Sun) and the subject is an object."""
    assert settings.light_source == "ESTIMATE"
    assert settings.light_object is None


@pytest.mark.parametrize("beyond", [0.0, -5.0, 90.0, 120.0])
def test_light_slant_is_held_inside_the_range_the_library_takes(settings, beyond):
    """Light slant set at or past an end of its slider clamps to the table's bound, which the library
    takes: four photographs' lights are estimated at it, where at 0 or 90 degrees they were refused
    after the click as one same light or lights at the horizon."""
    field = {field["name"]: field for field in shadecut.option_fields()}["light_slant"]
    settings.light_slant = beyond
    assert settings.light_slant == pytest.approx(field["low"] if beyond < 45.0 else field["high"])
    sphere = synthetic.sphere((0.0, 0.0, 1.0), size=48)
    tilts = np.radians([90.0, 180.0, 270.0, 0.0])
    around = np.stack([np.cos(tilts), np.sin(tilts), np.ones(4)], axis=1)
    photographs = [shadecut.render(sphere.normals, light, 0.8, sphere.mask) for light in around]
    result = shadecut.reconstruct(photographs, None, sphere.mask, light_slant=settings.light_slant)
    assert result.stats.light_estimated and np.isfinite(result.lights).all()
    with pytest.raises(ValueError, match="light_slant must be in"):
        shadecut.reconstruct(photographs, None, sphere.mask, light_slant=beyond)
