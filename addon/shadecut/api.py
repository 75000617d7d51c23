"""The Python API of ShadeCut: thin, documented wrappers over the compiled ``_core`` module.

Arrays: an image is (H, W) float32 linear intensity, row 0 at the top; normals are (H, W, 3) float32
in the camera frame (x right, y up, z toward the viewer); depth is (H, W) float32 in pixel units,
larger = closer; masks are (H, W) bool. Bad input raises ValueError with a message that says what.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Callable, Optional, Sequence

import numpy as np

from .compatibility import core_problem

try:
    from . import _core
except ImportError as error:  # the extension is produced by the CMake build, for one Python
    raise ImportError(core_problem() or f"shadecut's compiled module _core does not load: {error}") from error

Cancelled = _core.Cancelled
Cancelled.__doc__ = "Raised when a progress callback returns False."

ProgressCallback = Callable[[float, str], Optional[bool]]

ReconstructOptions = _core.ReconstructOptions
ReconstructOptions.__doc__ = """Every setting of :func:`reconstruct`, with its default.

The defaults are held once, in C++ (the option table, ``native/src/pipeline/option_table.cpp``); print
``ReconstructOptions()`` to see them. ``ReconstructOptions(labels=24)`` starts from the defaults,
``options.replace(labels=24)`` from another set; an unknown name raises TypeError. Enum fields take
the enum or its name: ``method="lee_rosenfeld"``. The meaning of each field: docs/python_api.md.
"""
Reconstruction = _core.Reconstruction
MethodDefaults = _core.MethodDefaults
ReconstructStats = _core.ReconstructStats
Method = _core.Method
Integrator = _core.Integrator
LightMethod = _core.LightMethod
AlbedoMethod = _core.AlbedoMethod
SceneKind = _core.SceneKind
CutOutOutcome = _core.CutOutOutcome
CutOutOptions = _core.CutOutOptions
CutOutOptions.__doc__ = """The settings of :func:`cut_out`, with their defaults (held in C++:
``native/include/shadecut/pipeline/cut_out.hpp``; the meaning of each: docs/python_api.md)."""

MIN_LABELS: int = _core.MIN_LABELS
"""The fewest tilt labels ``labels`` may be."""

MAX_THREADS: int = _core.MAX_THREADS
"""The most threads ``threads`` may ask for."""

OPTION_NAMES: tuple = tuple(_core.OPTION_NAMES)
"""The names of :class:`ReconstructOptions`' fields, the keywords :func:`reconstruct` takes."""


def option_fields() -> list:
    """The option table: one dict per field of :class:`ReconstructOptions`, by stage, with its
    ``name``, ``group``, ``kind`` (flag, whole, number, name), ``default`` (and ``default_text``),
    ``choices``, ``range`` (in words, with ``low``, ``high``, ``low_open``, ``high_open``), one line
    of ``help`` and the command line's other ``flags``."""
    return _core.option_fields()

METHODS: tuple = tuple(_core.METHODS)
"""Every reconstruction method's name, for ``reconstruct(..., method=...)``."""

LIGHT_METHODS: tuple = tuple(_core.LIGHT_METHODS)
"""Every light estimator's name, for :func:`estimate_light` and ``reconstruct(..., light_method=...)``."""


@dataclass
class LoadedImage:
    """An image file read by :func:`load_image`."""

    image: np.ndarray  # (H, W) float32 linear intensity (Rec. 709 luminance of a colour file)
    mask: np.ndarray  # (H, W) bool: alpha > 0.5, or all True without alpha
    has_alpha: bool
    color_space: str  # how the stored values were read: "linear" or "srgb"
    colour: Optional[np.ndarray] = None  # (H, W, 3) float32 linear RGB of a colour file; None for grey


def _real(values) -> np.ndarray:
    """``values`` as an array; ValueError for complex numbers, whose imaginary part a cast would drop."""
    array = np.asarray(values)
    if np.iscomplexobj(array):
        raise ValueError("shadecut: complex values given; images, normals and depth maps are real")
    return array


def _whole(name: str, value, low: int, high: int = 2**31 - 1) -> int:
    """``value`` as a whole number in [low, high]; TypeError or ValueError naming ``name`` and the range."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"shadecut: {name} is a whole number from {low} to {high}; got {value!r} ({type(value).__name__})")
    if not low <= int(value) <= high:
        raise ValueError(f"shadecut: {name} must be from {low} to {high}; got {value}")
    return int(value)


def _albedo(albedo) -> Optional[float]:
    """One albedo for the whole image, or None; a per-pixel array or a string is refused with what to do."""
    if albedo is None:
        return None
    if isinstance(albedo, (str, bytes)) or np.ndim(albedo) != 0 or isinstance(albedo, (bool, np.bool_)):
        raise TypeError(f"shadecut: albedo is one number (> 0) for the whole surface, or None to estimate it; got "
                        f"{type(albedo).__name__}{' of shape ' + str(np.shape(albedo)) if np.ndim(albedo) else ''}. "
                        "A painted surface's albedo per pixel is read with albedo_method='retinex'")
    return float(albedo)


def _progress(progress) -> Optional[ProgressCallback]:
    if progress is not None and not callable(progress):
        raise TypeError(f"shadecut: progress is a function progress(fraction, stage) or None; got {type(progress).__name__}")
    return progress


def _options(options, kind: type, example: str):
    """``options`` when of ``kind`` (None: the defaults), else TypeError with an example."""
    if options is not None and not isinstance(options, kind):
        raise TypeError(f"shadecut: options must be a {kind.__name__}, not a {type(options).__name__}: "
                        f"options={kind.__name__}({example}), or the fields as keywords ({example})")
    return options or kind()


def _mask(mask) -> Optional[np.ndarray]:
    return None if mask is None else np.ascontiguousarray(mask, dtype=bool)


def _vector3(light: Sequence[float]) -> list[float]:
    vector = np.asarray(light, dtype=float).reshape(-1)
    if vector.shape != (3,):
        raise ValueError(f"shadecut: the light must have 3 components (x, y, z); got shape {np.shape(light)}")
    return vector.tolist()


def light_direction(light: Sequence[float]) -> np.ndarray:
    """``light`` as the unit vector every layer uses: (3,) float64, camera frame.

    Raises ValueError for a vector that is not 3 finite numbers, is zero, or lies at or below the
    image's horizon (S_z <= 0): shape from shading needs light from the viewer's side.
    """
    return _core.light_direction(_vector3(light))


LIGHT_SIDES: tuple = tuple(_core.LIGHT_SIDES)
"""The sides of the image a light can be named by, for :func:`light_from_side` and ``reconstruct``."""

SIDE_LIGHT_SLANT_DEGREES: float = _core.SIDE_LIGHT_SLANT_DEGREES
"""The slant from the viewer of a light named only by its side (docs/conventions.md, "Light")."""

FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS: int = _core.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS
"""The fewest photographs ``reconstruct`` finds the lights of when given none."""


def light_from_side(side: str, slant_degrees: float = SIDE_LIGHT_SLANT_DEGREES) -> np.ndarray:
    """The unit direction (3,) toward a light from the image's ``side`` (one of :data:`LIGHT_SIDES`:
    "top", "left", "bottom-right", ...) at ``slant_degrees`` from the viewer, in (0, 90).

    A light that nobody measured, as in a multi-angle capture: its slant fixes the depth's scale, not
    its forms (another slant gives the same photographs of a deeper or flatter surface). ValueError
    for another word or slant.
    """
    if not isinstance(side, str):
        raise TypeError(f"shadecut: a light's side is a word such as 'top'; got {side!r}")
    return _core.light_from_side(side, float(slant_degrees))


def reconstruct(
    image,
    light: Optional[Sequence[float]] = None,
    mask=None,
    albedo: Optional[float] = None,
    *,
    options: Optional[ReconstructOptions] = None,
    progress: Optional[ProgressCallback] = None,
    **overrides,
) -> Reconstruction:
    """Reconstructs normals and depth from one Lambertian photograph, or from several of one view,
    each under its own light.

    Args:
        image: one photograph, (H, W) linear intensity or (H, W, 3) linear RGB under one white light,
            at least 2 x 2, finite, >= 0; or several: a list of such photographs, a (K, H, W, 3)
            stack, or a (K, H, W) stack with ``light`` K x 3. The shape is read from a colour image's
            Rec. 709 luminance; its colour tells paint from shading (``albedo_method="retinex"``) and
            gives ``albedo_colour``. Several photographs are read by photometric stereo where three
            or more light a pixel, and the graph cut chooses where two leave two normals
            (docs/method.md, "Several photographs").
        light: direction toward the distant light in the camera frame, S_z > 0; normalized here; or
            the side of the image it comes from ("top", "left", ...: :func:`light_from_side`); with
            several photographs, K such directions or sides, one per photograph, in order.
            None = estimated from the image by the ``light_method`` option (see :func:`estimate_light`),
            and then also the albedo unless given; ``stats.light_estimated`` says so. Several
            photographs: four or more lit from around at one slant give their lights, with the hint
            in the options ``light_slant`` and ``first_light_tilt`` (docs/method.md, "Lights of
            several photographs").
        mask: (H, W) bool pixels to reconstruct; None = every pixel.
        albedo: > 0; None = estimated with the light, or with a given light by the ``albedo_method``
            option (:func:`estimate_albedo`); with several photographs, per pixel from them.
        options: a :class:`ReconstructOptions`; None = the defaults.
        progress: called as progress(fraction, stage); a false answer raises :class:`Cancelled`.
        **overrides: fields of :class:`ReconstructOptions` to change (``method="lee_rosenfeld"``,
            ``labels=24``, ...); an unknown name raises TypeError.

    Returns:
        a :class:`Reconstruction`: ``normals``, ``depth``, ``mask``, ``albedo``, ``albedo_map``,
        ``light`` (and ``lights``, one per photograph), ``residual`` (how far the photographs are from it) and
        ``stats`` (a :class:`ReconstructStats`).
    """
    chosen = _options(options, ReconstructOptions, "labels=24").replace(**overrides)
    images, lights = _photographs(image, light)
    return _core.reconstruct(images, lights, _mask(mask), _albedo(albedo), chosen, _progress(progress))


def _photographs(image, light) -> tuple[list, Optional[list]]:
    """The photographs of a reconstruct() call and their lights (None: estimated)."""
    if isinstance(light, str):
        light = light_from_side(light)
    elif isinstance(light, (list, tuple)) and any(isinstance(item, str) for item in light):
        light = [light_from_side(item) if isinstance(item, str) else _vector3(item) for item in light]
    several_lights = light is not None and np.ndim(light) == 2
    if isinstance(image, (list, tuple)):
        images = [_real(photograph) for photograph in image]
    else:
        array = _real(image)
        stacked = array.ndim == 4 or (array.ndim == 3 and several_lights and len(light) == array.shape[0] > 1)
        images = list(array) if stacked else [array]
    if light is None:
        return images, None
    if several_lights:
        return images, [_vector3(direction) for direction in light]
    if len(images) > 1:
        raise ValueError(f"shadecut: {len(images)} photographs but one light; give one light per photograph "
                         "(a K x 3 array)")
    return images, [_vector3(light)]


@dataclass
class CutOut:
    """The object found by :func:`cut_out`."""

    mask: np.ndarray  # (H, W) bool: the object (its holes filled); the best guess when not found
    outcome: CutOutOutcome  # found, busy_border, no_object or low_contrast
    outline_contrast: float  # share of the mask's outline that differs from the background
    background_noise: float  # the border's robust spread about its smooth fit (display-encoded units)
    border_share: float  # share of the image's border that fits a plain background
    message: str  # one sentence for the user

    @property
    def found(self) -> bool:
        return self.outcome == CutOutOutcome.found


def cut_out(image, options: Optional[CutOutOptions] = None, *, progress: Optional[ProgressCallback] = None,
            **overrides) -> CutOut:
    """Cuts an object out of a plain background: the mask :func:`reconstruct` uses for
    ``scene="object"`` when given no mask (its ``cut_out`` option).

    Args:
        image: (H, W) linear intensity or (H, W, 3) linear RGB, finite, >= 0, at least 2 x 2.
        options: a :class:`CutOutOptions`; None = the defaults.
        progress: called as ``progress(fraction, "cut_out")`` after each round; returning False raises
            :class:`Cancelled`. Without one, Ctrl+C stops the call.
        **overrides: its fields to change (``smoothness=20``).

    Returns:
        a :class:`CutOut`. ``outcome`` is ``found`` when an object stands apart from a plain (possibly
        graded) background along most of its outline; ``busy_border`` when the image's border is no
        plain background (a texture, a relief filling the frame); ``no_object`` when nothing does;
        ``low_contrast`` when too little of the outline is seen (a dark background meeting the
        object's shadow). Method: docs/method.md, "Cutting out".
    """
    chosen = _options(options, CutOutOptions, "smoothness=20")
    if overrides:
        copy = CutOutOptions()
        for name in dir(chosen):
            if not name.startswith("_"):
                setattr(copy, name, getattr(chosen, name))
        for name, value in overrides.items():
            if not hasattr(copy, name) or name.startswith("_"):
                raise TypeError(f"shadecut: unknown cut-out option '{name}'")
            setattr(copy, name, value)
        chosen = copy
    mask, outcome, contrast, noise, share, message = _core.cut_out(_real(image), chosen, _progress(progress))
    return CutOut(mask=mask, outcome=outcome, outline_contrast=float(contrast), background_noise=float(noise),
                  border_share=float(share), message=message)


def render(depth_or_normals, light: Sequence[float], albedo: float = 1.0, mask=None) -> np.ndarray:
    """Lambertian image albedo * max(0, S . N) of a height field (H, W) or a normal map (H, W, 3).

    Pixels outside ``mask`` are 0. A height field's normals come from :func:`normals_from_depth`.
    """
    surface = _real(depth_or_normals)
    normals = normals_from_depth(surface, mask) if surface.ndim == 2 else surface
    return _core.render_normals(normals, _vector3(light), float(albedo), _mask(mask))


def normals_from_depth(depth, mask=None) -> np.ndarray:
    """Camera-frame unit normals normalize(-dz/dx, -dz/dy, 1) of a height field, (H, W, 3)."""
    return _core.normals_from_depth(_real(depth), _mask(mask))


def integrate(normals, mask=None, method: str = "poisson", max_slope: float = 10.0) -> np.ndarray:
    """Depth (H, W) from camera-frame normals (H, W, 3); each mask component's minimum is 0. A normal
    facing away from the viewer (n_z < 0) is a ValueError: see fold_back_facing."""
    return _core.integrate(_real(normals), _mask(mask), method, max_slope)


def fold_back_facing(normals, mask=None) -> tuple[np.ndarray, int]:
    """A copy of the normals (H, W, 3) in which every masked one facing away from the viewer
    (n_z < 0), which no depth map has, is the grazing normal of the same tilt; and how many there
    were. reconstruct() does this before integrating."""
    folded, count = _core.fold_back_facing(_real(normals), _mask(mask))
    return folded, int(count)


AMBIGUOUS_RESIDUAL_RATIO: float = _core.AMBIGUOUS_RESIDUAL_RATIO
"""``stats.orientation_ambiguous`` is set when the result's inversion renders less than this many
times as far from the image (mean squared residual) as the result itself."""


def flip(depth, normals, mask=None) -> tuple[np.ndarray, np.ndarray]:
    """The surface turned inside out: the other answer an image lit from near the viewer allows.

    Args:
        depth: (H, W) pixel units, larger = closer.
        normals: (H, W, 3) camera-frame unit normals.
        mask: (H, W) bool, the surface's pixels; None = every pixel.

    Returns:
        copies (depth, normals): depth z -> -z with each 4-connected component of the mask shifted
        so that its minimum is 0 again (the gauge of every reconstructed depth; outside the mask it is
        left as it is), normals (nx, ny, nz) -> (-nx, -ny, nz). Flipping twice gives the surface back.
        ``flip(result.depth, result.normals, result.mask)`` inverts a :func:`reconstruct` result, the
        thing to do when ``result.stats.orientation_ambiguous`` says the image could not choose.
    """
    return _core.flip_surface(_real(depth), _real(normals), _mask(mask))


def angular_error_map(n1, n2, mask=None) -> np.ndarray:
    """Per-pixel angle between two normal maps in degrees, NaN outside the mask."""
    return _core.angular_error_map(_real(n1), _real(n2), _mask(mask))


def angular_error(n1, n2, mask=None) -> float:
    """Mean angle between two normal maps, in degrees, over the pixels of the mask (None = all)
    where both maps have a normal (a zero vector has none)."""
    return _core.mean_angular_error(_real(n1), _real(n2), _mask(mask))


def mask_components(mask) -> tuple[np.ndarray, int]:
    """The 4-connected parts of a mask: (labels (H, W) int32, -1 outside and 0 .. count - 1 inside,
    numbered in raster order of each part's first pixel; count)."""
    labels, count = _core.mask_components(_mask(mask))
    return labels, int(count)


def erode_mask(mask, pixels: int) -> np.ndarray:
    """The mask shrunk by ``pixels`` steps of 4-neighbour erosion (the image border erodes too)."""
    return _core.erode_mask(_mask(mask), _whole("pixels", pixels, 0))


def method_defaults(method: str | Method) -> MethodDefaults:
    """The values ``method`` (a name in :data:`METHODS`, or a :class:`Method`) uses for the options
    left None: ``min_curvature``, ``undefined_weight``, ``tolerance``, ``iterations``, ``smoothness``
    (0 where the method does not use one). Tuned: docs/parameters.md."""
    return _core.method_defaults(getattr(method, "name", method))


def estimate_light(image, mask=None, method: Optional[str] = None,
                   albedo: Optional[float] = None, scene: str = "object") -> tuple[np.ndarray, float]:
    """Estimates (light, albedo) of a Lambertian image: light a (3,) unit vector toward the light.

    ``method``: "lee_rosenfeld" (Lee & Rosenfeld 1985: tilt from the mean direction of the intensity
    gradients, slant from the mean and mean squared intensity of a sphere without attached shadow),
    "zheng_chellappa" (tilt from the mean gradient, slant from the moments of a sphere with its
    attached shadow) or "relief" (a surface filling the frame: tilt axis from the image's spectrum,
    the light from above, slant from its median and brightest intensities). The first two assume
    normals spread like a sphere's over the mask, which should cover the object only; their
    measured biases: docs/comparison_methods.md. None = the one
    :func:`reconstruct` uses for ``scene`` (:meth:`ReconstructOptions.light_method_used`). The image
    is read clipped at ``albedo`` (None = :func:`estimate_albedo`'s), above which a highlight would
    pull the light toward it, as :func:`reconstruct` does; "relief" takes ``albedo`` as the albedo
    and otherwise reads it from the relief's brightest pixels. ValueError for a mask of fewer than
    16 pixels, whose shading has no statistics to read.
    """
    if method is None:
        method = ReconstructOptions(scene=scene).light_method_used()
    light, albedo = _core.estimate_light(_real(image), _mask(mask), getattr(method, "name", method), albedo)
    return np.asarray(light), float(albedo)


def estimate_albedo(image, mask=None, method: Optional[str] = None,
                    window: Optional[tuple[float, float, float]] = None) -> float:
    """The albedo :func:`reconstruct` uses when a light but no albedo is given.

    ``method``: "top_fit" (the intensity at which a line fitted to the squared intensities of the
    object's brightest 20-60 %, against their share of its area, reaches share 0: highlights and
    saturated spots brighter than that window do not move it; the brightest value when it agrees
    with the fit) or "brightest" (the largest value of the 3 x 3 median-filtered image). None =
    the ``albedo_method`` default of :class:`ReconstructOptions`.
    ``window``: top_fit's (from, to, agreement): the shares of the area fitted and how far (relative)
    the brightest value may exceed the fit and still be taken as the albedo of a clean image; None =
    the tuned default.
    """
    if method is None:
        method = ReconstructOptions().albedo_method
    if window is not None and (np.ndim(window) != 1 or len(window) != 3):
        raise ValueError(f"shadecut: window is three numbers (from, to, agreement); got {window!r}")
    return _core.estimate_albedo(_real(image), _mask(mask), getattr(method, "name", method),
                                 None if window is None else tuple(float(v) for v in window))


def estimate_reflectance(image, mask=None, shading=None, *, options: Optional[ReconstructOptions] = None,
                         **overrides) -> np.ndarray:
    """The paint of a painted object, as :func:`reconstruct` with ``albedo_method="retinex"`` reads
    it before the shape: an intrinsic decomposition (Retinex with colour, docs/method.md, Paint).

    Args:
        image: (H, W) linear intensity or (H, W, 3) linear RGB under one white light, finite, >= 0.
        mask: (H, W) bool pixels of the object; None = every pixel.
        shading: (H, W) shading of a surface found before, any scale (e.g. :func:`render` of its
            normals); None = each paint edge's shading step is bridged from the image's steps beside
            it, as the first pass does. Where it is given, the step across each paint edge is the
            image's less this shading's, as every later pass does.
        options: a :class:`ReconstructOptions` whose ``retinex_*`` fields and ``scene`` (a relief
            reads edges up to its border) are used; None = the defaults.
        **overrides: fields of :class:`ReconstructOptions` to change.

    Returns:
        (H, W) float32 reflectance relative to the object's bright paint: 1 at its 90th percentile
        over the mask, 1 outside it. The image divided by it is the shading image of one albedo.
    """
    chosen = _options(options, ReconstructOptions, "retinex_rim=2").replace(**overrides)
    return _core.estimate_reflectance(_real(image), _mask(mask), chosen, None if shading is None else _real(shading))


def _image_files():
    """The compiled module for image and mesh files, which links OpenImageIO; imported when first used,
    since the Blender add-on's zip does not ship it (Blender reads the images there)."""
    try:
        from . import _imageio
    except ImportError as error:
        raise ImportError(
            "shadecut's image and mesh files need its module _imageio (OpenImageIO), which the Blender "
            "add-on does not ship: in Blender, open the image in Blender; elsewhere build ShadeCut from "
            "source (README.md)") from error
    return _imageio


LUMINANCE_WEIGHTS: tuple = tuple(_core.LUMINANCE_WEIGHTS)
"""The Rec. 709 weights (red, green, blue) of the linear intensity read from linear RGB: what
``reconstruct`` and ``load_image`` take from a colour image."""


def load_image(path: str | os.PathLike, color_space: str = "auto", max_pixels: Optional[int] = None) -> LoadedImage:
    """Reads an image file as linear intensity through OpenImageIO.

    8/16-bit PNG, TIFF, JPEG and float EXR among others. ``color_space="auto"``: float files are
    linear, integer files sRGB unless they say they are linear. Colour becomes Rec. 709 luminance
    (``image``) and is kept as linear RGB (``colour``, None for a grey file); alpha becomes the mask.
    Raises OSError for a missing, unreadable or truncated file, for a path that is not a regular
    file (a named pipe, a device) without opening it, and before reading any pixel for one whose
    header declares more than ``max_pixels`` pixels (None = 2^28).
    """
    files = _image_files()
    # A header's width and height are 32-bit, so a limit above 2^63 (the reader's integer) is no limit.
    limit = files.DEFAULT_MAX_PIXELS if max_pixels is None else min(int(max_pixels), 2**63 - 1)
    image, mask, has_alpha, color_space_used, colour = files.load_image(os.fspath(path), color_space, limit)
    return LoadedImage(image=image, mask=mask, has_alpha=has_alpha, color_space=color_space_used, colour=colour)


def save_image(path: str | os.PathLike, image, mask=None) -> None:
    """Writes linear intensity (H, W) or linear RGB (H, W, 3): float for .exr/.tif, 16-bit sRGB PNG
    otherwise (alpha = mask)."""
    _image_files().save_image(os.fspath(path), _real(image), _mask(mask))


def save_depth(path: str | os.PathLike, depth, mask=None) -> None:
    """Writes depth: float .exr/.tif (data) or 16-bit PNG scaled to the masked range (a picture)."""
    _image_files().save_depth(os.fspath(path), _real(depth), _mask(mask))


def save_normals(path: str | os.PathLike, normals, mask=None) -> None:
    """Writes normals: float .exr/.tif, or an 8-bit PNG normal map (n + 1) / 2."""
    _image_files().save_normals(os.fspath(path), _real(normals), _mask(mask))


def height_field_mesh(depth, mask=None, step: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The mesh of a height field sampled every ``step`` pixels, the one :func:`save_mesh` writes.

    Returns:
        vertices (V, 3) float32 at (column, -row, depth) in pixel units, one per sampled masked
        pixel in raster order; quads (F, 4) int32 joining four sampled masked neighbours, corners
        top-left, bottom-left, bottom-right, top-right (counter-clockwise seen from +z); uvs (V, 2)
        float32, each vertex's pixel centre in the image with v up.
    """
    return _core.height_field_mesh(_real(depth), _mask(mask), int(step))


# The vertex budget of a result mesh unless asked otherwise (the add-on's Vertex limit, batch.py's
# meshes): half a million triangles, which Material Preview redraws interactively on a modest GPU.
MAX_VERTICES = 250_000


def vertex_step(mask, max_vertices: int = MAX_VERTICES) -> int:
    """The smallest sampling step (for :func:`height_field_mesh` and :func:`save_mesh`) that leaves at
    most ``max_vertices`` vertices on ``mask`` (H, W) bool; 1 when every masked pixel fits."""
    mask = _mask(mask)
    _whole("max_vertices", max_vertices, 1, 2**62)
    height, width = mask.shape
    return next(step for step in range(1, max(height, width) + 1)
                if np.count_nonzero(mask[::step, ::step]) <= max_vertices)


def save_mesh(path: str | os.PathLike, depth, mask=None, step: int = 1) -> None:
    """Writes the height field sampled every ``step`` pixels as a .ply or .obj triangle mesh, vertices
    at (column, -row, depth) in pixel units (:func:`height_field_mesh`'s)."""
    _image_files().save_mesh(os.fspath(path), _real(depth), _mask(mask), _whole("step", step, 1))
