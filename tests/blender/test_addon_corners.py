"""The add-on in a scene's odd states (issue 48): a library-linked collection active (finding 4),
Flip in Edit Mode and on an object sharing a result's material (finding 10), an EXR whose NaN lies
only where its alpha is transparent (finding 15), a JPEG cut in half (finding 12), a photograph stored sideways with its EXIF orientation (finding 9), a multi-page TIFF (finding 14), an albedo typed below the image (finding 21)."""

import bpy
import numpy as np
import pytest

import shadecut

from shadecut.blender import reconstruct_job
from test_addon import scene_state
from test_addon_errors import Reports, sphere_with_its_light, write_file
from test_flip import heights, image_of, normal_map_pixels


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


def test_an_albedo_typed_below_the_image_is_warned_of(addon, sphere_png):
    """Below the image's brightness the surface is read as facing the light wherever it is brighter:
    the user hears so (finding 21), not only sees a flattened result."""
    settings = sphere_with_its_light(sphere_png)
    settings.auto_albedo, settings.albedo = False, 0.4
    job = reconstruct_job.prepare_job(bpy.context)
    job.run()
    reports = Reports()
    assert reconstruct_job.finish_job(reports, bpy.context, job) == {"FINISHED"}
    assert reports.last[0] == {"WARNING"} and "brighter than the albedo given (0.400)" in reports.last[1]
    settings.auto_albedo = True
    job = reconstruct_job.prepare_job(bpy.context)
    job.run()
    assert job.result.stats.albedo_message == ""


def frontal_result(tmp_path) -> bpy.types.Object:
    settings = bpy.context.scene.shadecut
    settings.image, settings.normal_map = image_of(tmp_path / "frontal.png", (0.0, 0.0, 1.0)), True
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    return bpy.context.active_object


def test_flip_in_edit_mode_inverts_the_heights_it_reports(addon, tmp_path):
    """In Edit Mode the heights were written to the mesh, which leaving Edit Mode overwrote: only the
    normal map was inverted, while the report said both."""
    obj = frontal_result(tmp_path)
    before, colours = heights(obj), normal_map_pixels(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    assert bpy.ops.shadecut.flip() == {"FINISHED"}
    bpy.ops.object.mode_set(mode="OBJECT")
    np.testing.assert_allclose(heights(obj)[:, 2], before[:, 2].max() - before[:, 2], atol=1e-5)
    np.testing.assert_allclose(normal_map_pixels(obj)[:, :2], 1.0 - colours[:, :2], atol=1e-6)


def test_flipping_an_object_that_shares_a_results_material_leaves_the_result_alone(addon, tmp_path):
    """A plane given the result's material flipped the result's normal map (its heights not)."""
    result = frontal_result(tmp_path)
    material, colours = result.active_material, normal_map_pixels(result)
    bpy.ops.mesh.primitive_plane_add()
    plane = bpy.context.active_object
    plane.data.materials.append(material)
    assert bpy.ops.shadecut.flip() == {"FINISHED"}
    assert result.active_material == material
    np.testing.assert_array_equal(normal_map_pixels(result), colours)
    assert plane.active_material != material
    np.testing.assert_allclose(normal_map_pixels(plane)[:, :2], 1.0 - colours[:, :2], atol=1e-6)


def test_the_flip_report_names_what_was_inverted(addon, tmp_path):
    from shadecut.blender.flip_operator import flip_object

    result = frontal_result(tmp_path)
    bpy.ops.mesh.primitive_plane_add()
    plane = bpy.context.active_object
    plane.data.materials.append(result.active_material)
    assert flip_object(plane) == ["normal map"]
    assert flip_object(result) == ["heights", "normal map"]


def test_an_exr_with_nan_only_under_its_transparent_alpha_is_refused_as_the_library_refuses_it(addon, tmp_path):
    """The library and the command line refuse it; the add-on reconstructed it."""
    pixels = np.full((16, 16, 4), 0.5, np.float32)
    pixels[..., 3] = 1.0
    pixels[:4, :, 3] = 0.0  # the top rows transparent
    pixels[1, 2, :3] = np.nan
    path = write_file(tmp_path / "nan_outside.exr", pixels)
    loaded = shadecut.load_image(path)
    assert not loaded.mask[1, 2]
    with pytest.raises(ValueError, match="NaN or infinite"):
        shadecut.reconstruct(loaded.image, mask=loaded.mask, light=(0.0, 0.0, 1.0))
    bpy.context.scene.shadecut.light_source = "DIRECTION"
    before = scene_state()
    with pytest.raises(RuntimeError, match=r"'nan_outside.exr' has 1 NaN or infinite pixel \(1 of them where its "
                                           r"alpha is transparent\)"):
        bpy.ops.shadecut.reconstruct(filepath=path)
    assert scene_state() == before


def test_a_jpeg_cut_in_half_is_refused_by_file_and_as_the_panels_image(addon, sphere_png, tmp_path):
    """Blender decodes it (grey rows where the data stopped); the library and the command line refuse it."""
    import OpenImageIO as oiio

    truth, png = sphere_png
    buffer = oiio.ImageBuf(str(png))
    assert buffer.write(str(tmp_path / "whole.jpg")), buffer.geterror()
    data = (tmp_path / "whole.jpg").read_bytes()
    cut = tmp_path / "cut.jpg"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(OSError):
        shadecut.load_image(cut)
    settings = bpy.context.scene.shadecut
    settings.light_source = "DIRECTION"
    before = scene_state()
    with pytest.raises(RuntimeError, match="'.*cut.jpg': the file is cut short"):
        bpy.ops.shadecut.reconstruct(filepath=str(cut))
    assert scene_state() == before
    settings.image = bpy.data.images.load(str(cut))
    assert tuple(settings.image.size) == (96, 96)  # Blender read it
    with pytest.raises(RuntimeError, match="Image 'cut.jpg': the file is cut short"):
        bpy.ops.shadecut.reconstruct()


def jpeg_stored_with(path, upright, orientation):
    """A grey JPEG whose stored rows are ``upright`` (H, W) turned as a camera declaring EXIF
    ``orientation`` stores them (6: the upright picture turned a quarter counter-clockwise)."""
    import OpenImageIO as oiio

    stored = {1: upright, 3: upright[::-1, ::-1], 6: np.rot90(upright, 1), 8: np.rot90(upright, -1)}[orientation]
    codes = np.round(np.clip(stored, 0, 1) ** (1 / 2.2) * 255).astype(np.uint8)[..., None]
    spec = oiio.ImageSpec(codes.shape[1], codes.shape[0], 1, oiio.UINT8)
    spec.attribute("Orientation", orientation)
    spec.attribute("Compression", "jpeg:100")
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), codes)
    assert buffer.write(str(path)), buffer.geterror()
    return str(path)


@pytest.mark.parametrize("orientation", [3, 6, 8])
def test_a_photograph_stored_sideways_is_reconstructed_upright(addon, tmp_path, orientation):
    """A phone's portrait is stored sideways (orientation 6): Blender shows it so, every viewer
    upright, and the light the user gives is the one seen upright. Reconstructed as stored, the
    sphere lit from the right came out with a mean error of about 50 degrees."""
    from shadecut import synthetic
    from shadecut.blender import image_input

    truth = synthetic.sphere(light=(1.0, 0.0, 1.0), size=96)
    upright = np.where(truth.mask, truth.image, 0.0)
    path = jpeg_stored_with(tmp_path / "portrait.jpg", upright, orientation)
    image = bpy.data.images.load(path)
    intensity, mask, _, _ = image_input.image_pixels(image)
    assert np.abs(intensity - upright).mean() < 0.01  # JPEG's error, not a turned picture's
    settings = bpy.context.scene.shadecut
    settings.image, settings.scene = image, "object"
    settings.light_source, settings.light_direction = "DIRECTION", (1.0, 0.0, 1.0)
    job = reconstruct_job.prepare_job(bpy.context)
    job.mask = truth.mask  # the outline is not what is tested (a JPEG has no alpha)
    job.run()
    assert job.error is None, job.error
    error = shadecut.angular_error(job.result.normals, truth.normals, truth.mask & job.result.mask)
    assert error < 15.0, error


# The stored rows of a file declaring each EXIF orientation, made from the upright picture (the
# rule's inverse of what a viewer does: 6 is stored turned a quarter counter-clockwise).
STORED = {1: lambda u: u, 2: lambda u: u[:, ::-1], 3: lambda u: u[::-1, ::-1], 4: lambda u: u[::-1],
          5: lambda u: u.T, 6: lambda u: np.rot90(u, 1), 7: lambda u: u[::-1, ::-1].T, 8: lambda u: np.rot90(u, -1)}


@pytest.mark.parametrize("orientation", range(1, 9))
def test_a_tiff_is_read_upright_or_refused_where_blender_turns_it_in_part(addon, tmp_path, orientation):
    """Blender 3.4 turns a TIFF by its tag itself, but only mirrors a quarter turn (refused: 5 to 8);
    4.3 and 5.2 ignore the tag, and the add-on turns every orientation."""
    import OpenImageIO as oiio
    from shadecut.blender import image_input
    from shadecut.blender.orientation_probe import blender_turns_tiffs

    upright = (np.random.default_rng(orientation).permutation(60) * 4).reshape(6, 10).astype(np.uint8)
    stored = np.ascontiguousarray(STORED[orientation](upright))
    spec = oiio.ImageSpec(stored.shape[1], stored.shape[0], 1, oiio.UINT8)
    spec.attribute("Orientation", orientation)
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), stored[..., None])
    assert buffer.write(str(tmp_path / "turned.tif")), buffer.geterror()
    image = bpy.data.images.load(str(tmp_path / "turned.tif"))
    if blender_turns_tiffs() and orientation > 4:
        with pytest.raises(image_input.InputError, match="'turned.tif' is stored turned by a quarter .* save it upright"):
            image_input.image_pixels(image)
        return
    intensity, _, _, _ = image_input.image_pixels(image)
    assert intensity.shape == upright.shape
    np.testing.assert_array_equal(np.argsort(intensity.ravel()), np.argsort(upright.ravel()))  # decoding keeps order


def test_a_tiff_of_several_pages_is_refused_by_file_and_as_the_panels_image(addon, tmp_path):
    """Blender reads its first page without a word."""
    import OpenImageIO as oiio

    path = tmp_path / "pages.tif"
    spec = oiio.ImageSpec(12, 8, 1, oiio.UINT8)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), (spec, spec))
    assert out.write_image(np.full((8, 12, 1), 100, np.uint8))
    assert out.open(str(path), spec, "AppendSubimage")
    assert out.write_image(np.full((8, 12, 1), 200, np.uint8))
    out.close()
    settings = bpy.context.scene.shadecut
    settings.light_source = "DIRECTION"
    with pytest.raises(RuntimeError, match="'.*pages.tif': the file is a TIFF of several pages"):
        bpy.ops.shadecut.reconstruct(filepath=str(path))
    settings.image = bpy.data.images.load(str(path))
    with pytest.raises(RuntimeError, match="Image 'pages.tif': the file is a TIFF of several pages"):
        bpy.ops.shadecut.reconstruct()


def test_a_two_channel_tiff_without_alpha_is_grey_and_opaque_in_the_addon(addon, tmp_path):
    """Its second channel is not taken for a mask (the library's reader, in C++, does so)."""
    from shadecut.blender import image_input

    pixels = np.zeros((8, 12, 2), np.float32)
    pixels[..., 0], pixels[..., 1] = 0.6, np.linspace(0.0, 1.0, 12)[None, :]
    image = bpy.data.images.load(write_file(tmp_path / "rg.tif", pixels))
    intensity, mask, _, _ = image_input.image_pixels(image)
    assert mask.all()


def test_a_mask_drawn_upright_fits_a_photograph_stored_sideways(addon, tmp_path):
    """The mask is compared with the image as shown: a portrait stored sideways is as tall as its mask."""
    from shadecut import synthetic
    from shadecut.blender import image_input

    truth = synthetic.sphere(light=(1.0, 0.0, 1.0), size=96)
    upright, mask = truth.image[:, 12:84], truth.mask[:, 12:84]  # 72 wide, 96 tall
    source = bpy.data.images.load(jpeg_stored_with(tmp_path / "portrait.jpg", np.where(mask, upright, 0.0), 6))
    assert tuple(source.size) == (96, 72)  # as stored
    drawn = bpy.data.images.load(write_file(tmp_path / "mask.png", np.where(mask, 255, 0).astype(np.uint8)[..., None]))
    np.testing.assert_array_equal(image_input.picked_mask(drawn, source, 0), mask)


def test_an_exr_whose_channels_name_no_picture_is_refused(addon, tmp_path):
    """Blender 3.4 reads an EXR of channels foo and bar as black, 5.2 reads bar as the picture."""
    import OpenImageIO as oiio

    spec = oiio.ImageSpec(12, 8, 2, oiio.FLOAT)
    spec.channelnames = ("foo", "bar")
    buffer = oiio.ImageBuf(spec)
    buffer.set_pixels(oiio.ROI(), np.random.default_rng(0).random((8, 12, 2)).astype(np.float32))
    assert buffer.write(str(tmp_path / "foobar.exr"))
    bpy.context.scene.shadecut.light_source = "DIRECTION"
    with pytest.raises(RuntimeError, match=r"'.*foobar.exr': the file is an EXR whose channels \(bar, foo\) name no "
                                           r"colour \(R, G, B\) or grey \(Y\)"):
        bpy.ops.shadecut.reconstruct(filepath=str(tmp_path / "foobar.exr"))
