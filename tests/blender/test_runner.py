import bpy


def test_runs_inside_blender():
    assert bpy.app.background
