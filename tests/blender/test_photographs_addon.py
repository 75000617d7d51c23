"""Several photographs of one view in the add-on (issue 45): picked in the file browser at once, each
lit by its own Sun or typed light, reconstructed in one click into a mesh with the normal map and the
de-lit albedo wired; undo removes it, Esc cancels, bad input is a report that leaves nothing behind."""

import re
import threading
from pathlib import Path
from types import SimpleNamespace

import bpy
import numpy as np
import pytest

import shadecut
from shadecut import synthetic
from shadecut.blender import reconstruct_job, reconstruct_operator
from shadecut.blender.light_input import UNPICKED_SIDE, side_in_file_name, side_tilt
from shadecut.blender.result import NORMAL_NODE, NORMAL_TEXTURE
from test_addon import add_sun, pixels_of, scene_state
from test_addon_errors import Reports
from window_steps import run_in_window

# Four lights about 40 degrees from the viewer, from the top, the left, the bottom and the right.
AROUND = np.array([[0.0, 0.64, 0.77], [-0.64, 0.0, 0.77], [0.0, -0.64, 0.77], [0.64, 0.0, 0.77]])
ALBEDO = 0.8
SIZE = 96
UI_SESSION = Path(__file__).with_name("photographs_ui_session.py")
FELT_RUG = Path(__file__).resolve().parents[3] / "shared" / "data" / "multi_angle" / "felt_rug"
# Photographs named by the side of their light, as a multi-angle capture names them: the file names and sides.
SIDE_NAMED = {"sphere_top.png": "top", "IMG_Left.png": "left", "bottom.png": "bottom", "scan right.png": "right"}


@pytest.fixture
def sphere_photographs(tmp_path):
    """A sphere (albedo 0.8) under each light of AROUND, rendered by the core and saved as 16-bit PNGs,
    the mask as alpha: (the synthetic.Scene, the directory, the file names in AROUND's order)."""
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=SIZE)
    names = [f"sphere_{index}.png" for index in range(len(AROUND))]
    for name, light in zip(names, AROUND):
        shadecut.save_image(tmp_path / name, shadecut.render(scene.normals, light, ALBEDO, scene.mask), scene.mask)
    return scene, tmp_path, names


def add_photographs(directory, names):
    """The Add button's operator as the file browser calls it with ``names`` selected in ``directory``."""
    return bpy.ops.shadecut.photographs_add(directory=str(directory), files=[{"name": name} for name in names])


def with_typed_lights(sphere_photographs, lights=AROUND):
    """The four photographs in the panel's list, each with its light typed; the settings."""
    _, directory, names = sphere_photographs
    assert add_photographs(directory, names) == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    settings.light_source = "DIRECTION"
    for row, light in zip(settings.photographs, lights):
        row.direction = light
    return settings


def decoded_normal_map(obj):
    """The camera-frame normals (H, W, 3) of the result's normal map, row 0 at the top."""
    image = obj.active_material.node_tree.nodes[NORMAL_TEXTURE].image
    width, height = image.size
    colours = pixels_of(image).reshape(height, width, 4)[::-1, :, :3]
    return 2.0 * colours - 1.0


def test_four_photographs_in_one_click_give_the_true_normals_and_the_maps_wired(addon, sphere_photographs):
    truth = sphere_photographs[0]
    with_typed_lights(sphere_photographs)
    objects_before = set(bpy.data.objects)

    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}

    new = set(bpy.data.objects) - objects_before
    assert len(new) == 1
    obj = new.pop()
    assert obj.name == "sphere_0" and obj.type == "MESH" and len(obj.data.vertices) == np.count_nonzero(truth.mask)
    # Four Lambertian photographs fix the normal outright: the library's own bound (tests/python/
    # test_photographs.py), which the 16-bit files' rounding (1 part in 65535) leaves untouched.
    assert truth.mean_error(decoded_normal_map(obj)) < 1.0
    # The mesh's own vertex normals, from the heights the normals integrate to: as true.
    normals = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("normal", normals)
    mesh_normals = np.zeros_like(truth.normals)
    mesh_normals[truth.mask] = normals.reshape(-1, 3)
    assert truth.mean_error(mesh_normals) < 1.0

    nodes = obj.active_material.node_tree.nodes
    shader = nodes["Principled BSDF"]
    base_colour = shader.inputs["Base Color"].links[0].from_node
    assert base_colour.image.name == "sphere_0 albedo"  # the de-lit albedo, not a shaded photograph
    albedo = pixels_of(base_colour.image).reshape(SIZE, SIZE, 4)[::-1]
    inside = shadecut.erode_mask(truth.mask, 2)
    # No shading left in it: the 16-bit files' rounding (1 part in 65535) allows 1e-3.
    assert np.abs(albedo[inside][:, :3] - ALBEDO).max() < 1e-3
    assert nodes[NORMAL_TEXTURE].outputs["Color"].links[0].to_node == nodes[NORMAL_NODE]
    assert nodes[NORMAL_NODE].outputs["Normal"].links[0].to_node == shader


def test_the_finish_report_says_where_the_graph_cut_chose_which_of_four_to_leave_out(addon, tmp_path):
    """A shiny sphere: where one photograph's highlight misses the others' fit the graph cut chose which
    of the four to leave out, and the report counts those pixels as the library does."""
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=SIZE)
    names = [f"shiny_{index}.png" for index in range(len(AROUND))]
    for name, light in zip(names, AROUND):
        half = light / np.linalg.norm(light) + [0.0, 0.0, 1.0]
        highlight = 0.5 * np.clip(scene.normals @ (half / np.linalg.norm(half)), 0.0, None) ** 50
        image = shadecut.render(scene.normals, light, 0.6, scene.mask) + (highlight * scene.mask).astype(np.float32)
        shadecut.save_image(tmp_path / name, image, scene.mask)
    with_typed_lights((scene, tmp_path, names))
    job = reconstruct_job.prepare_job(bpy.context)
    job.run()
    operator = Reports()
    assert reconstruct_job.finish_job(operator, bpy.context, job) == {"FINISHED"}
    four = job.result.stats.four_fit_pixels
    assert four > 0
    assert (f"; {four:,} where one of four disagreed (a highlight or a cast shadow): the graph cut chose which to "
            "leave out)") in operator.last[1]


def test_lamps_near_the_subject_at_the_typed_distance(addon, tmp_path):
    """Four photographs under lamps one picture width away, their directions typed and Lamp distance
    set: the normals are those of the library's near-lamp reading (tests/python/test_near_lamps.py)."""
    scene = synthetic.bumps((0.0, 0.0, 1.0), size=SIZE)
    names = [f"bumps_{index}.png" for index in range(len(AROUND))]
    # Albedo 0.5: a lamp this near lights the nearest pixels up to 1.3 times its strength at the centre,
    # which a file holds only below 1.
    for name, photograph in zip(names, synthetic.lit_by_lamps(scene, AROUND, 1.0, 0.5)):
        shadecut.save_image(tmp_path / name, photograph)
    settings = with_typed_lights((scene, tmp_path, names))
    settings.scene = "relief"
    settings.light_distance = 1.0
    objects_before = set(bpy.data.objects)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    obj = (set(bpy.data.objects) - objects_before).pop()
    assert scene.mean_error(decoded_normal_map(obj)) < 1.0
    settings.light_distance = 0.0  # read as distant, the same photographs are far off: the setting is used
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    obj = (set(bpy.data.objects) - objects_before - {obj}).pop()
    assert scene.mean_error(decoded_normal_map(obj)) > 10.0


def test_the_scenes_suns_in_name_order_light_the_photographs(addon, sphere_photographs):
    """No Sun picked in any row: the scene's Suns, one per photograph, sorted by name (Top view: the
    world's frame is the image's)."""
    truth, directory, names = sphere_photographs
    assert add_photographs(directory, names) == {"FINISHED"}
    for index, light in reversed(list(enumerate(AROUND))):  # made out of order: the names decide
        add_sun(light, name=f"Lamp {index}")
    bpy.context.scene.shadecut.light_source = "OBJECT"
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_allclose(job.light, AROUND / np.linalg.norm(AROUND, axis=1, keepdims=True), atol=1e-6)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert truth.mean_error(decoded_normal_map(bpy.context.active_object)) < 1.0


def test_a_sun_picked_per_photograph_gives_its_light(addon, sphere_photographs):
    settings = with_typed_lights(sphere_photographs)
    settings.light_source = "OBJECT"
    for index, (row, light) in enumerate(zip(settings.photographs, AROUND)):
        row.sun = add_sun(light, name=f"Z {3 - index}")  # names against the rows' order: the picks decide
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_allclose(job.light, AROUND / np.linalg.norm(AROUND, axis=1, keepdims=True), atol=1e-6)


def test_one_photograph_in_the_list_is_the_single_image(addon, sphere_photographs):
    _, directory, names = sphere_photographs
    settings = bpy.context.scene.shadecut
    settings.light_source, settings.light_direction = "DIRECTION", AROUND[3]
    settings.image = bpy.data.images.load(str(directory / names[3]))
    alone = reconstruct_job.prepare_job(bpy.context)
    alone.run()
    assert add_photographs(directory, [names[3]]) == {"FINISHED"}
    settings.photographs[0].direction = AROUND[3]
    listed = reconstruct_job.prepare_job(bpy.context)
    listed.run()
    np.testing.assert_array_equal(listed.image, alone.image)
    np.testing.assert_array_equal(listed.result.depth, alone.result.depth)
    np.testing.assert_array_equal(listed.result.normals, alone.result.normals)


@pytest.mark.parametrize("lit_from", ["typed lights", "sides named by the files"])
def test_undo_removes_the_result(addon, request, lit_from):
    """Background mode pushes no undo step for an operator called from Python (see test_flip): the
    flags are checked, and undoing past the operator takes the result out again."""
    assert {"REGISTER", "UNDO"} <= bpy.types.SHADECUT_OT_reconstruct.bl_options
    if lit_from == "typed lights":
        with_typed_lights(request.getfixturevalue("sphere_photographs"))
    else:
        assert add_photographs(*request.getfixturevalue("side_photographs")[1:]) == {"FINISHED"}
    name = Path(bpy.context.scene.shadecut.photographs[0].image.name).stem  # the result's, after the first
    bpy.ops.ed.undo_push(message="before")
    before = scene_state()
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert name in bpy.data.objects
    bpy.ops.ed.undo_push(message="after")
    bpy.ops.ed.undo()
    assert name not in bpy.data.objects
    assert scene_state() == before


class Event:
    def __init__(self, kind):
        self.type = kind


def test_esc_cancels_the_running_job_and_leaves_nothing(addon, sphere_photographs):
    """The operator's modal handler given Esc while the photographs' job runs on its worker thread."""
    with_typed_lights(sphere_photographs)
    before = scene_state()
    job = reconstruct_job.prepare_job(bpy.context)
    started = threading.Event()
    progress = job.progress

    def held_progress(fraction, stage):  # the worker waits at its first progress call for the Esc
        started.set()
        while not job.cancel:
            threading.Event().wait(0.01)
        return progress(fraction, stage)

    job.progress = held_progress
    worker = threading.Thread(target=job.run)
    worker.start()
    assert started.wait(60)
    operator = Reports()
    operator._job, operator._thread = job, worker
    operator._end_modal = lambda context: None  # no timer or progress bar in background mode
    window = SimpleNamespace(progress_update=lambda value: None)
    context = SimpleNamespace(window_manager=window, workspace=SimpleNamespace(status_text_set=lambda text: None),
                              scene=bpy.context.scene, collection=bpy.context.collection,
                              view_layer=bpy.context.view_layer)
    assert reconstruct_operator.SHADECUT_OT_reconstruct.modal(operator, context, Event("ESC")) == {"RUNNING_MODAL"}
    assert job.cancel
    worker.join(60)
    assert reconstruct_operator.SHADECUT_OT_reconstruct.modal(operator, context, Event("TIMER")) == {"CANCELLED"}
    assert isinstance(job.error, shadecut.Cancelled) and "cancelled" in operator.last[1]
    assert scene_state() == before


def resized(directory, name):
    """A 64 x 64 photograph beside the 96 x 96 ones."""
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=64)
    shadecut.save_image(directory / name, shadecut.render(scene.normals, AROUND[3], ALBEDO, scene.mask), scene.mask)
    return name


def _bad_setup(case, sphere_photographs):
    settings = with_typed_lights(sphere_photographs)
    rows = settings.photographs
    if case == "sizes":
        rows[3].image = bpy.data.images.load(str(sphere_photographs[1] / resized(sphere_photographs[1], "small.png")))
    elif case == "same light":
        rows[3].direction = rows[0].direction
    elif case == "below the horizon":
        rows[2].direction = (0.3, 0.2, -1.0)
    elif case == "estimate with three":
        rows.remove(3)
        settings.light_source = "ESTIMATE"
    elif case == "no image":
        rows.add()
    elif case in ("same side", "synonym sides", "no side"):
        settings.light_source = "SIDE"
        sides = {"same side": ("left", "top", "bottom", "left"), "synonym sides": ("above", "left", "top", "right"),
                 "no side": (UNPICKED_SIDE, "top", "bottom", "left")}[case]
        for row, side in zip(rows, sides):
            row.side = side
    else:
        settings.light_source = "OBJECT"
        suns = [add_sun(light, name=f"Sun {index}") for index, light in enumerate(AROUND)]
        if case == "three suns":
            bpy.data.objects.remove(suns[3])
        elif case == "one sun missing":
            for row, sun in zip(rows[:3], suns):
                row.sun = sun
        elif case == "same sun":
            for row in rows:
                row.sun = suns[0]


@pytest.mark.parametrize("case, message", [
    ("sizes", "Photograph 4 ('small.png') is 64 x 64 pixels but the first ('sphere_0.png') is 96 x 96"),
    ("three suns", "4 photographs but 3 Suns in the scene"),
    ("one sun missing", "Photograph 4 ('sphere_3.png') has no Sun"),
    ("same sun", "both have Sun 'Sun 0': a second photograph under the same light adds nothing"),
    ("same light", "adds nothing"),
    ("below the horizon", "The light of photograph 3 ('sphere_2.png') (0.3, 0.2, -1) cannot be used"),
    ("estimate with three", "Light is Estimate, which finds the lights of 4 or more photographs lit from around the "
                            "subject; 3 photographs need their lights: set Light to Sun (one per photograph), "
                            "Direction (typed in each row) or Side of the image (picked in each row), or add "
                            "photographs to have 4 or more"),
    ("no image", "Photograph 5 has no image"),
    ("same side", "Photograph 1 ('sphere_0.png') and photograph 4 ('sphere_3.png') are both lit from the left: "
                  "a second photograph under the same light adds nothing"),
    ("synonym sides", "Photograph 1 ('sphere_0.png') and photograph 3 ('sphere_2.png') are lit from 'above' and "
                      "'top', one side: a second photograph under the same light adds nothing"),
    ("no side", "Photograph 1 ('sphere_0.png') has no side of the image for its light (its file name names none)"),
])
def test_bad_photographs_are_a_report_and_leave_nothing_behind(addon, sphere_photographs, case, message):
    _bad_setup(case, sphere_photographs)
    before = scene_state()
    # An ERROR report raises in background mode; CANCELLED is the operator's result behind it.
    with pytest.raises(RuntimeError, match=re.escape(message)) as raised:
        bpy.ops.shadecut.reconstruct()
    assert "Traceback" not in str(raised.value)
    assert scene_state() == before


def test_adding_photographs_is_all_or_nothing(addon, sphere_photographs):
    _, directory, names = sphere_photographs
    before = scene_state()
    with pytest.raises(RuntimeError, match="there is no such file"):
        add_photographs(directory, [*names[:2], "missing.png"])
    assert scene_state() == before and len(bpy.context.scene.shadecut.photographs) == 0
    (directory / "empty").mkdir()
    with pytest.raises(RuntimeError, match="holds no image file"):
        add_photographs(directory / "empty", [])


def test_a_folder_without_a_file_picked_adds_its_images_in_name_order(addon, sphere_photographs):
    _, directory, names = sphere_photographs
    (directory / "notes.txt").write_text("not a photograph")
    assert add_photographs(directory, []) == {"FINISHED"}
    assert [row.image.name for row in bpy.context.scene.shadecut.photographs] == names


def test_in_a_real_window_one_click_undo_and_esc():
    """photographs_ui_session.py in a Blender window under Xvfb, where the panel is drawn and the
    operator runs modal with its timer, its undo step and Esc, as for a user."""
    result = run_in_window(UI_SESSION)
    print(result.stdout[-2000:])
    assert result.returncode == 0 and "ui: all checks passed" in result.stdout, result.stdout + result.stderr
    assert "Traceback" not in result.stdout + result.stderr, result.stdout + result.stderr


def test_alphas_that_do_not_overlap_are_refused(addon, sphere_photographs):
    """Each photograph has opaque pixels, but none is opaque in all: no common outline to reconstruct."""
    settings = with_typed_lights(sphere_photographs)
    directory = sphere_photographs[1]
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=SIZE)
    elsewhere = np.zeros_like(scene.mask)
    elsewhere[:4, :4] = True  # a corner the sphere does not reach
    shadecut.save_image(directory / "corner.png", np.full(scene.mask.shape, 0.5, np.float32), elsewhere)
    settings.photographs[3].image = bpy.data.images.load(str(directory / "corner.png"))
    before = scene_state()
    with pytest.raises(RuntimeError, match="No pixel is opaque in every photograph"):
        bpy.ops.shadecut.reconstruct()
    assert scene_state() == before


def test_colour_photographs_give_their_de_lit_colour_as_base_color(addon, tmp_path):
    """A sphere painted (0.8, 0.64, 0.48) under the four lights: the Base Color is that paint,
    without the shading of any photograph."""
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=SIZE)
    paint = ALBEDO * np.array([1.0, 0.8, 0.6], np.float32)
    names = [f"painted_{index}.png" for index in range(len(AROUND))]
    for name, light in zip(names, AROUND):
        shading = shadecut.render(scene.normals, light, 1.0, scene.mask)
        shadecut.save_image(tmp_path / name, shading[..., None] * paint, scene.mask)
    with_typed_lights((scene, tmp_path, names))
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    obj = bpy.context.active_object
    assert scene.mean_error(decoded_normal_map(obj)) < 1.0
    base_colour = obj.active_material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].links[0].from_node
    albedo = pixels_of(base_colour.image).reshape(SIZE, SIZE, 4)[::-1, :, :3]
    # 16-bit files round each value to 1 part in 65535 (sRGB-coded): the paint comes back to 1e-3.
    assert np.abs(albedo[shadecut.erode_mask(scene.mask, 2)] - paint).max() < 1e-3


# How far from the viewer AROUND's lights stand (all alike): the Light slant the estimate is told.
AROUND_SLANT = float(np.degrees(np.arccos(AROUND[0, 2] / np.linalg.norm(AROUND[0]))))


def with_estimated_lights(sphere_photographs, first_light_side="top"):
    """The four photographs in the list with Light left at Estimate (their file names name no side),
    the hint their renders' slant and the side the first is lit from; the settings."""
    _, directory, names = sphere_photographs
    assert add_photographs(directory, names) == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    assert settings.light_source == "ESTIMATE"
    settings.light_slant, settings.first_light_side = AROUND_SLANT, first_light_side
    return settings


def test_four_photographs_with_estimate_find_their_lights_and_the_true_normals(addon, sphere_photographs):
    truth = sphere_photographs[0]
    with_estimated_lights(sphere_photographs)
    objects_before = set(bpy.data.objects)
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.light is None and job.options["first_light_tilt"] == 90.0  # the first render is lit from the top
    job.run()
    operator = Reports()
    assert reconstruct_job.finish_job(operator, bpy.context, job) == {"FINISHED"}
    assert len(set(bpy.data.objects) - objects_before) == 1
    # Four exact Lambertian renders (16-bit rounding only) at the slant told, the first lit from the
    # side told: nothing is left to guess, so the lights found are the true ones, to a tenth of a degree ...
    true_lights = AROUND / np.linalg.norm(AROUND, axis=1, keepdims=True)
    off = np.degrees(np.arccos(np.clip(np.sum(job.result.lights * true_lights, axis=1), -1.0, 1.0)))
    assert job.result.stats.light_estimated and off.max() < 0.1
    # ... and then the normals as the typed lights give them: within that test's bound of 1 degree.
    assert truth.mean_error(decoded_normal_map(bpy.context.active_object)) < 1.0
    found = "; ".join(", ".join(f"{round(float(v), 3) + 0.0:.3f}" for v in light) for light in job.result.lights)
    assert (f"4 photographs under lights estimated from them ({found}) at {AROUND_SLANT:.4g} degrees from the viewer "
            "(Light slant, which the depth's scale follows), their turn about the viewer uncertain by "
            f"{job.result.stats.light_uncertainty:.1f} degrees") in operator.last[1]
    assert "-0.000" not in operator.last[1]  # a component that rounds to zero is written without its sign


def test_an_objects_outline_overrules_the_first_lights_side(addon, sphere_photographs):
    """Told the first photograph was lit from the bottom (it was lit from the top), the estimate takes
    every light the other way round; the sphere's outline shows that reading inside out and turns
    them back: the sphere comes out a sphere, and the report says why the lights are not where told."""
    truth = sphere_photographs[0]
    with_estimated_lights(sphere_photographs, first_light_side="bottom")
    job = reconstruct_job.prepare_job(bpy.context)
    assert job.options["first_light_tilt"] == pytest.approx(-90.0)
    job.run()
    operator = Reports()
    assert reconstruct_job.finish_job(operator, bpy.context, job) == {"FINISHED"}
    assert job.result.lights[0][1] > 0 and job.result.stats.lights_turned_by_outline
    assert truth.mean_error(decoded_normal_map(bpy.context.active_object)) < 1.0
    assert "turned by half a circle from First light's side: the object's outline showed it inside out" in operator.last[1]


@pytest.mark.parametrize("side, tilt", [("right", 0.0), ("top", 90.0), ("above", 90.0), ("left", 180.0),
                                        ("bottom", -90.0), ("top-left", 135.0), ("bottom-right", -45.0)])
def test_a_side_is_its_tilt_in_the_image(side, tilt):
    assert side_tilt(side) == pytest.approx(tilt)


def test_the_hint_starts_at_the_librarys_defaults(addon):
    settings = bpy.context.scene.shadecut
    assert settings.light_slant == shadecut.ReconstructOptions().light_slant
    assert side_tilt(settings.first_light_side) == pytest.approx(shadecut.ReconstructOptions().first_light_tilt)


@pytest.mark.parametrize("file_name, side", [
    ("above.jpg", "above"), ("rug_top.png", "top"), ("IMG_Left.JPG", "left"), ("scan-top-left.png", "top-left"),
    ("bottom right.tif", "bottom-right"), ("felt_BELOW_2.jpg", "below"), ("top_right", "top-right"),
    ("topography.png", None), ("IMG_0042.jpg", None), ("left_vs_right.png", None), ("copyright.png", None),
])
def test_a_side_is_read_as_a_whole_word_of_the_file_name(file_name, side):
    assert side_in_file_name(file_name) == side


@pytest.fixture
def side_photographs(tmp_path):
    """The sphere (albedo 0.8) under the library's light from each side that SIDE_NAMED names, saved
    as 16-bit PNGs under those names: (the synthetic.Scene, the directory, the file names)."""
    scene = synthetic.sphere((0.0, 0.0, 1.0), size=SIZE)
    for name, side in SIDE_NAMED.items():
        photograph = shadecut.render(scene.normals, shadecut.light_from_side(side), ALBEDO, scene.mask)
        shadecut.save_image(tmp_path / name, photograph, scene.mask)
    return scene, tmp_path, list(SIDE_NAMED)


def test_photographs_named_by_side_are_lit_from_it_in_one_click(addon, side_photographs):
    truth, directory, names = side_photographs
    assert add_photographs(directory, names) == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    assert [row.side for row in settings.photographs] == list(SIDE_NAMED.values())
    assert settings.light_source == "SIDE"  # every file named its side: nothing to type
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    # The renders are exact Lambertian images under the very lights the sides give (16-bit rounding
    # only): the normals are fixed outright wherever three light a pixel, as with typed lights.
    assert truth.mean_error(decoded_normal_map(bpy.context.active_object)) < 1.0


def test_the_finish_report_says_the_sides_slant_is_a_guess(addon, side_photographs):
    assert add_photographs(*side_photographs[1:]) == {"FINISHED"}
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_array_equal(job.light, [shadecut.light_from_side(side) for side in SIDE_NAMED.values()])
    job.run()
    operator = Reports()
    assert reconstruct_job.finish_job(operator, bpy.context, job) == {"FINISHED"}
    slant = f"{shadecut.SIDE_LIGHT_SLANT_DEGREES:g} degrees from the viewer"
    assert f"4 photographs under lights from the sides of the image (top, left, bottom, right) at {slant}: a guess, " \
           "which the depth's scale follows" in operator.last[1]


def test_a_file_name_without_a_side_leaves_the_light_as_it_was(addon, sphere_photographs, side_photographs):
    _, directory, names = side_photographs
    assert add_photographs(directory, names[:3]) == {"FINISHED"}
    assert add_photographs(sphere_photographs[1], sphere_photographs[2][:1]) == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    assert settings.photographs[3].side == UNPICKED_SIDE  # for the user to pick; the reconstruction says so
    settings.light_source = "DIRECTION"
    assert add_photographs(directory, names[3:]) == {"FINISHED"}
    assert settings.light_source == "DIRECTION"  # one row still has no side: the choice stays the user's


def test_one_image_lit_from_a_side(addon, side_photographs):
    _, directory, names = side_photographs
    settings = bpy.context.scene.shadecut
    settings.image = bpy.data.images.load(str(directory / names[1]))
    settings.light_source = "SIDE"
    with pytest.raises(RuntimeError, match=re.escape("The image has no side of the image for its light")):
        bpy.ops.shadecut.reconstruct()
    settings.light_side = "left"
    job = reconstruct_job.prepare_job(bpy.context)
    np.testing.assert_array_equal(job.light, shadecut.light_from_side("left"))


def test_the_felt_rugs_four_photographs_by_their_file_names(addon):
    """Four real photographs lit from above, below, left and right, no light measured: added as a
    user picks them, they need nothing typed and give a mesh with its normal map and de-lit albedo."""
    if not FELT_RUG.is_dir():
        pytest.skip(f"the felt rug's photographs are not in {FELT_RUG}")
    names = ["above.jpg", "below.jpg", "left.jpg", "right.jpg"]
    assert add_photographs(FELT_RUG, names) == {"FINISHED"}
    settings = bpy.context.scene.shadecut
    assert [row.side for row in settings.photographs] == ["above", "below", "left", "right"]
    assert settings.light_source == "SIDE"
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    obj = bpy.context.active_object
    assert obj.name == "above" and obj.type == "MESH" and len(obj.data.vertices) == 512 * 384  # the whole rug
    nodes = obj.active_material.node_tree.nodes
    base_colour = nodes["Principled BSDF"].inputs["Base Color"].links[0].from_node
    assert base_colour.image.name == "above albedo" and tuple(base_colour.image.size) == (512, 384)
    assert nodes[NORMAL_TEXTURE].outputs["Color"].links[0].to_node == nodes[NORMAL_NODE]
