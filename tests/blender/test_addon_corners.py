"""The add-on in a scene's odd states (issue 48): a library-linked collection active (finding 4)."""

import bpy
import pytest

from shadecut.blender import reconstruct_job
from test_addon import scene_state
from test_addon_errors import Reports, sphere_with_its_light


def linked_collection_active(tmp_path) -> bpy.types.Collection:
    """A collection linked from another .blend into the scene and made the active one (read-only)."""
    shelf = bpy.data.collections.new("Shelf")
    library = tmp_path / "library.blend"
    bpy.data.libraries.write(str(library), {shelf})
    bpy.data.collections.remove(shelf)
    with bpy.data.libraries.load(str(library), link=True) as (source, target):
        target.collections = ["Shelf"]
    linked = target.collections[0]
    assert linked.library is not None
    bpy.context.scene.collection.children.link(linked)
    view_layer = bpy.context.view_layer
    view_layer.active_layer_collection = view_layer.layer_collection.children[linked.name]
    assert bpy.context.collection == linked
    return linked


def test_a_linked_active_collection_is_refused_before_the_work(addon, sphere_png, tmp_path):
    """Blender refuses to link the result into it: the operator ended in a traceback and left the
    result's object, mesh, material and albedo image behind."""
    sphere_with_its_light(sphere_png)
    linked_collection_active(tmp_path)
    before = scene_state()
    with pytest.raises(RuntimeError, match="the active collection 'Shelf' is linked from the library .* make "
                                           "another collection active in the Outliner") as raised:
        bpy.ops.shadecut.reconstruct()
    assert "Traceback" not in str(raised.value)
    assert scene_state() == before


def test_a_collection_made_linked_during_the_work_leaves_nothing_behind(addon, sphere_png, tmp_path):
    """The active collection may change while the job runs on its thread: the result is refused
    when it is built, with nothing of it left in bpy.data."""
    sphere_with_its_light(sphere_png)
    job = reconstruct_job.prepare_job(bpy.context)
    job.run()
    linked_collection_active(tmp_path)
    before = scene_state()
    reports = Reports()
    assert reconstruct_job.finish_job(reports, bpy.context, job) == {"CANCELLED"}
    assert reports.last[0] == {"ERROR"} and "linked from the library" in reports.last[1]
    assert scene_state() == before
