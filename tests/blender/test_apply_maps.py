"""Apply to = Active object: the maps go, live, into the selected object's material (the artist's
plane textured with the photo), and nothing else of the object changes."""

import bpy
import numpy as np
import pytest

LIGHT = (1.0, 0.0, 1.0)


def textured_plane(image, material=True):
    """A 2 x 2 plane with UVs whose material shows ``image`` through an active Image Texture node."""
    bpy.ops.mesh.primitive_plane_add(size=2.0)
    plane = bpy.context.active_object
    if material:
        material = bpy.data.materials.new("Photo")
        material.use_nodes = True
        nodes = material.node_tree.nodes
        texture = nodes.new("ShaderNodeTexImage")
        texture.name, texture.image = "Photo colour", image
        material.node_tree.links.new(texture.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
        nodes.active = texture
        plane.data.materials.append(material)
    return plane


def settings_for_target(image=None, **values):
    settings = bpy.context.scene.shadecut
    settings.image = image
    settings.light_source, settings.light_direction = "DIRECTION", LIGHT
    settings.target = "ACTIVE_MATERIAL"
    for key, value in values.items():
        setattr(settings, key, value)
    return settings


def mesh_state(mesh):
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    uv = np.empty(2 * len(mesh.loops), np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    return co, uv, len(mesh.edges), len(mesh.polygons)


def scene_state():
    return {key: sorted(item.name for item in getattr(bpy.data, key))
            for key in ("objects", "meshes", "materials", "images", "textures")}


def links_of(tree):
    return {(link.from_node.name, link.from_socket.identifier, link.to_node.name, link.to_socket.identifier,
             link.is_muted) for link in tree.links}


def test_maps_go_live_into_the_active_objects_material(addon, sphere_png):
    image = bpy.data.images.load(str(sphere_png[1]))
    plane = textured_plane(image)
    material = plane.active_material
    tree = material.node_tree
    nodes_before, links_before = {node.name for node in tree.nodes}, links_of(tree)
    mesh_before = mesh_state(plane.data)
    objects_before = set(bpy.data.objects.keys())
    settings_for_target(normal_map=True, height_map=True)  # the image: the plane's selected texture node

    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}

    assert set(bpy.data.objects.keys()) == objects_before and bpy.context.active_object == plane
    assert plane.active_material == material and len(plane.data.materials) == 1
    for before, after in zip(mesh_before, mesh_state(plane.data)):
        np.testing.assert_array_equal(before, after)
    assert nodes_before <= {node.name for node in tree.nodes}
    assert links_before <= links_of(tree)  # the photo still feeds the Base Color
    shader, output = tree.nodes["Principled BSDF"], tree.nodes["Material Output"]
    normal_map = next(node for node in tree.nodes if node.type == "NORMAL_MAP")
    displacement = next(node for node in tree.nodes if node.type == "DISPLACEMENT")
    assert normal_map.space == "TANGENT" and normal_map.uv_map == "UVMap"
    to_normal, = shader.inputs["Normal"].links
    assert to_normal.from_node == normal_map and not to_normal.is_muted
    to_output, = output.inputs["Displacement"].links
    assert to_output.from_node == displacement and not to_output.is_muted
    for node, socket, name in ((normal_map, "Color", "normals"), (displacement, "Height", "height")):
        texture = node.inputs[socket].links[0].from_node
        assert texture.type == "TEX_IMAGE" and texture.image.name == f"Plane {name}"
        assert texture.image.packed_file is not None and texture.image.colorspace_settings.name == "Non-Color"
    truth, _ = sphere_png
    assert normal_map.inputs["Color"].links[0].from_node.image.size[:] == truth.image.shape[::-1]
    assert displacement.inputs["Scale"].default_value > 0

    # Again: the ShadeCut nodes are replaced, not piled up.
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert sum(node.type == "NORMAL_MAP" for node in tree.nodes) == 1
    assert sum(node.type == "DISPLACEMENT" for node in tree.nodes) == 1


def test_an_object_without_a_material_gets_one(addon, sphere_png):
    image = bpy.data.images.load(str(sphere_png[1]))
    plane = textured_plane(image, material=False)
    settings_for_target(image, normal_map=True)
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    material = plane.active_material
    assert material is not None and len(plane.data.materials) == 1
    links = material.node_tree.nodes["Principled BSDF"].inputs["Normal"].links
    assert links and links[0].from_node.type == "NORMAL_MAP" and not links[0].is_muted
    assert not any(node.type == "DISPLACEMENT" for node in material.node_tree.nodes)


@pytest.mark.parametrize("case", ["no UVs", "no map ticked", "no active object", "not a mesh"])
def test_an_unusable_target_is_an_error_that_changes_nothing(addon, sphere_png, case):
    image = bpy.data.images.load(str(sphere_png[1]))
    plane = textured_plane(image)
    if case == "no UVs":
        plane.data.uv_layers.remove(plane.data.uv_layers[0])
    elif case == "no active object":
        bpy.context.view_layer.objects.active = None
    elif case == "not a mesh":
        bpy.ops.object.empty_add()
    settings_for_target(image, normal_map=case != "no map ticked")
    before, tree_before = scene_state(), links_of(plane.active_material.node_tree)
    message = {"no UVs": "has no UV map", "no map ticked": "Tick Normal map", "no active object": "No active object",
               "not a mesh": "Active object 'Empty' is an empty, not a mesh"}[case]
    with pytest.raises(RuntimeError, match=message):  # an ERROR report raises in background mode
        bpy.ops.shadecut.reconstruct()
    assert scene_state() == before and links_of(plane.active_material.node_tree) == tree_before


def test_undo_takes_the_maps_out_again(addon, sphere_png):
    """Background mode pushes no undo step for an operator called from Python (ui_session.py checks
    the one step in a real window, for a new object): the flags are checked, and that undoing past
    the operator restores the material and drops the images."""
    assert {"REGISTER", "UNDO"} <= bpy.types.SHADECUT_OT_reconstruct.bl_options
    image = bpy.data.images.load(str(sphere_png[1]))
    plane = textured_plane(image)
    settings_for_target(normal_map=True, height_map=True)
    bpy.ops.ed.undo_push(message="before")
    before = {node.name for node in plane.active_material.node_tree.nodes}
    assert bpy.ops.shadecut.reconstruct() == {"FINISHED"}
    assert len(bpy.data.materials["Photo"].node_tree.nodes) == len(before) + 4
    bpy.ops.ed.undo_push(message="after")
    bpy.ops.ed.undo()
    assert {node.name for node in bpy.data.materials["Photo"].node_tree.nodes} == before
    assert "Plane normals" not in bpy.data.images
