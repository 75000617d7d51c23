"""Issue 45 on the scanned materials photographed in Blender (blender_scripts/material_photographs.py):
Cycles renders with the material's colours, the shadows it casts on itself and the light bouncing
between its parts; four or eight photographs read together give at most half the error of one read
alone, on every material of the test half."""

import importlib.util
import sys

import bpy
import numpy as np
import pytest

from shadecut import materials

SIZE = 64  # pixels on a side of the materials' centre: a few seconds per material
SAMPLES = 128  # Cycles samples with bounces: noise well below the shading the test compares


@pytest.fixture(scope="module")
def photographed(repo):
    """blender_scripts/material_photographs.py, the module of docs/results.md's table."""
    spec = importlib.util.spec_from_file_location("material_photographs", repo / "blender_scripts" / "material_photographs.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    if not module.MATERIALS.is_dir():
        pytest.skip(f"the scanned materials are not at {module.MATERIALS} (../shared/data/materials)")
    return module


@pytest.mark.parametrize("count", [4, 8])
@pytest.mark.parametrize("name", materials.TEST)
def test_several_photographs_with_shadows_and_bounces_halve_one_photographs_error(photographed, name, count):
    material = materials.load_material(photographed.MATERIALS / name)
    found = photographed.errors(photographed.read(material, SIZE, count, SAMPLES))
    print(f"{name}, {count} photographs: {found.several:.2f} deg, one alone {found.alone:.2f}, flat {found.flat:.2f}")
    assert found.several <= 0.5 * found.alone, found
    assert found.several <= found.plain + 0.05, found  # what the photographs leave out is not worse than keeping it


def test_nothing_of_the_render_stays_in_the_file(photographed):
    """The mesh, its material, the colour image and every render's temporary scene are removed."""
    before = {kind: set(getattr(bpy.data, kind).keys()) for kind in ("objects", "meshes", "materials", "images", "scenes")}
    material = materials.load_material(photographed.MATERIALS / materials.TEST[0])
    photographed.read(material, 16, 4, 1)
    after = {kind: set(getattr(bpy.data, kind).keys()) for kind in before}
    assert all(after[kind] - before[kind] <= {"Render Result"} for kind in before), (before, after)


def test_a_size_that_does_not_divide_the_maps_is_refused(photographed):
    material = materials.load_material(photographed.MATERIALS / materials.TEST[0])
    with pytest.raises(ValueError, match="cannot be rendered at 600 px"):
        photographed.surface_depth(material, 600)
    assert np.isfinite(photographed.surface_depth(material, 16)[0]).all()
