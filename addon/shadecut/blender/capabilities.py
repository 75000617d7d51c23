"""What the running Blender offers where Blender 3.x, 4.x and 5.x differ, asked of Blender itself (its
RNA properties, operators, enum items and colour configuration) rather than guessed from
``bpy.app.version``; each asks once and says clearly when the running Blender has none of the
known forms, instead of doing nothing.
"""

from __future__ import annotations

import functools
import os
import re
from pathlib import Path
from typing import Callable

import bpy


class MissingCapability(RuntimeError):
    """The running Blender has none of the forms of a feature that ShadeCut knows."""


def set_cast_shadow(light: bpy.types.Light, shadows: bool) -> None:
    """Whether Cycles traces shadows from ``light``: ``light.cycles.cast_shadow`` before 4.2, the
    light's own ``use_shadow`` since (where the old one is gone and setting it would store nothing).
    Before 4.2 a light's ``use_shadow`` is EEVEE's alone, so the Cycles property goes first."""
    cycles = getattr(light, "cycles", None)
    if cycles is not None and "cast_shadow" in cycles.bl_rna.properties:
        cycles.cast_shadow = shadows
    elif "use_shadow" in light.bl_rna.properties:
        light.use_shadow = shadows
    else:
        raise MissingCapability(f"this Blender ({bpy.app.version_string}) has neither Light.cycles.cast_shadow "
                                "nor Light.use_shadow: ShadeCut cannot switch a sun's shadows on or off")


# Mesh-file importers by suffix, newest first: the C++ importers (Blender 3.6+ for PLY and STL), then
# the Python add-ons of older Blenders (io_mesh_ply, io_mesh_stl), which 4.2 no longer has.
_MESH_IMPORTERS = {
    ".obj": (("wm", "obj_import"), ("import_scene", "obj")),
    ".ply": (("wm", "ply_import"), ("import_mesh", "ply")),
    ".stl": (("wm", "stl_import"), ("import_mesh", "stl")),
}


def mesh_importer(suffix: str) -> Callable[..., set]:
    """The operator of this Blender that imports a ``suffix`` mesh file (called with filepath=...)."""
    forms = _MESH_IMPORTERS.get(suffix.lower())
    if forms is None:
        raise MissingCapability(f"ShadeCut imports no '{suffix}' mesh files (only {', '.join(_MESH_IMPORTERS)})")
    for module, name in forms:
        if name in dir(getattr(bpy.ops, module)):
            return getattr(getattr(bpy.ops, module), name)
    tried = " or ".join(f"bpy.ops.{module}.{name}" for module, name in forms)
    raise MissingCapability(f"this Blender ({bpy.app.version_string}) has no {suffix} importer ({tried}): "
                            "enable its importer add-on, or save the mesh as .obj or .blend")


def eevee_engine() -> str:
    """The render engine id of EEVEE here: BLENDER_EEVEE, or BLENDER_EEVEE_NEXT in 4.2-4.5."""
    engines = [item.identifier for item in bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items]
    eevee = [engine for engine in engines if engine.startswith("BLENDER_EEVEE")]
    if not eevee:
        raise MissingCapability(f"this Blender ({bpy.app.version_string}) has no EEVEE engine (engines: {engines})")
    return eevee[0]


def set_multilayer_exr(image_settings) -> None:
    """Multilayer OpenEXR output in one part: the file format OPEN_EXR_MULTILAYER, which Blender 5.0+
    offers only once the media type (a setting older Blenders lack) is MULTI_LAYER_IMAGE, and there
    the interleaved layout, since 5.0 writes each pass as a part of its own otherwise."""
    if "media_type" in image_settings.bl_rna.properties:
        image_settings.media_type = "MULTI_LAYER_IMAGE"
    if "use_exr_interleave" in image_settings.bl_rna.properties:
        image_settings.use_exr_interleave = True
    try:
        image_settings.file_format = "OPEN_EXR_MULTILAYER"
    except TypeError as error:  # how bpy refuses an enum value
        raise MissingCapability(f"this Blender ({bpy.app.version_string}) writes no multilayer OpenEXR: {error}") from None


def colour_space_names() -> list[str]:
    """The colour spaces an image can be set to in this Blender, as its Color Space menu lists them."""
    settings = bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"]
    return [item.identifier for item in settings.enum_items]


def colour_config_path() -> Path:
    """The OpenColorIO configuration this Blender runs with: $OCIO when set, else its own."""
    if os.environ.get("OCIO"):
        return Path(os.environ["OCIO"])
    folder = bpy.utils.system_resource("DATAFILES", path="colormanagement")  # "" when it has none
    if not folder:
        raise MissingCapability(f"this Blender ({bpy.app.version_string}) has no colour management folder")
    return Path(folder) / "config.ocio"


@functools.lru_cache(maxsize=None)
def linear_colour_spaces() -> frozenset[str]:
    """The colour spaces of this Blender's menu whose stored values are linear in light (or data,
    used as stored), read from its OpenColorIO configuration (:func:`linear_in_config`)."""
    return frozenset(linear_in_config(colour_config_path().read_text(encoding="utf-8"))) & set(colour_space_names())


def linear_in_config(config: str) -> set[str]:
    """The names of an OpenColorIO configuration's colour spaces that are linear in light, or data
    whose values are used as stored, as the configuration itself declares them: ``isdata: true``, an
    ``encoding`` of scene-linear or data (OpenColorIO 2), or the family "Linear" that Blender's own
    configurations give their linear spaces (3.x writes "linear"; 4.x and 5.x group the Color Space
    menu by it), and the spaces named by the roles that are linear by definition (the reference, scene
    linear, data, and OpenColorIO 2's interchange spaces ACES2065-1 and CIE XYZ D65)."""
    header = config.split("\ncolorspaces:")[0]
    roles = dict(re.findall(r"^\s{2}(reference|scene_linear|data|aces_interchange|cie_xyz_d65_interchange):"
                            r"\s*(.+?)\s*$", header, re.MULTILINE))
    linear = {name.strip("\"'") for name in roles.values()}
    for block in re.split(r"\n\s*- !<ColorSpace>", config)[1:]:
        fields = {key: value.strip().strip("\"'") for key, value in
                  re.findall(r"^\s{4}(\w+):[ \t]*(.*)$", block.split("\n  - !<")[0], re.MULTILINE)}
        encoding = fields.get("encoding")  # when given, it decides
        if (fields.get("isdata") == "true" or encoding in ("scene-linear", "data")
                or (not encoding and fields.get("family", "").lower() == "linear")):
            linear.add(fields.get("name", ""))
    return linear
