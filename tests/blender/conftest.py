from pathlib import Path

import bpy
import pytest

import shadecut
from shadecut import synthetic

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def empty_scene():
    """Every test starts from Blender's factory scene emptied of objects, and leaves no operator
    state behind for the next one."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture
def addon():
    """The add-on registered for one test."""
    shadecut.register()
    yield
    shadecut.unregister()


@pytest.fixture
def sphere_png(tmp_path):
    """A sphere under light (1, 0, 1) rendered by the core and saved as a 16-bit PNG, the mask as
    alpha: (its synthetic.Scene, the path)."""
    scene = synthetic.sphere(light=(1.0, 0.0, 1.0), size=96)
    path = tmp_path / "sphere.png"
    shadecut.save_image(path, scene.image, scene.mask)
    return scene, path
