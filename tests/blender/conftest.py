from pathlib import Path

import bpy
import pytest

import shadecut

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
