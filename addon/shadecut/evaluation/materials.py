"""One photograph of a scanned material (issue 46): ShadeCut beside what an artist does without it.

Each material of a half (``shadecut.materials``) is rendered Lambertian under each light
(``materials.lambertian_photographs``: albedo x max(0, n . s), no bounce; no shadow, or with
``cast_shadows`` black where the relief hides the light), and every render is read by:

- **flat**: the normal (0, 0, 1) everywhere, what leaving the surface flat gives;
- **image as height**, what a Bump node makes of the photograph plugged in as its height: the
  photograph's linear luminance (Rec. 709, ``shadecut.LUMINANCE_WEIGHTS``; Blender converts an image's
  colour to a height the same way) times a strength, its normals by ``shadecut.normals_from_depth``.
  The strength is a height in pixel units per unit of luminance, one of :data:`STRENGTHS` (Invert
  off). Two strengths are reported: the one chosen on the training half (:func:`training_strength`:
  the strength of least mean error over the training renders), and per render the best one knowing
  the true normals (an oracle bound no artist has);
- **ShadeCut**: ``shadecut.reconstruct(photograph, light, scene="relief")`` with the true light, and
  with the light estimated (``light=None``), every other option default;
- **ShadeCut given the true shading**, an oracle of what telling paint from relief perfectly would
  leave: the photograph's luminance divided by the true albedo's, reconstructed with ``albedo=1``,
  the true light given and estimated.

The metric is ``shadecut.angular_error`` against the measured normal map, in degrees, over every
pixel. A row is one (material, light, method); ``below_flat`` says whether it beats flat on that render.
"""

from __future__ import annotations

import csv
import io
import json
import os
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np

from .. import angular_error, normals_from_depth, reconstruct
from ..imaging import luminance
from ..atomic_write import write_text
from ..materials import TEST, TRAINING, Material, lambertian_photographs, lights_around, load_material
from .metrics import light_error
from .report import provenance

FLAT = "flat"
HEIGHT_TRAINED = "image as height (training-chosen strength)"
HEIGHT_BEST = "image as height (best strength, knowing the truth)"
SHADECUT_TRUE = "ShadeCut, true light"
SHADECUT_ESTIMATED = "ShadeCut, light estimated"
SHADING_TRUE = "ShadeCut given the true shading, true light"
SHADING_ESTIMATED = "ShadeCut given the true shading, light estimated"
METHODS = (FLAT, HEIGHT_TRAINED, HEIGHT_BEST, SHADECUT_TRUE, SHADECUT_ESTIMATED, SHADING_TRUE, SHADING_ESTIMATED)
# ShadeCut's rows: (method, light given, read the true shading instead of the photograph).
_SHADECUT_READINGS = ((SHADECUT_TRUE, True, False), (SHADECUT_ESTIMATED, False, False),
                      (SHADING_TRUE, True, True), (SHADING_ESTIMATED, False, True))

LIGHT_COUNT = 4  # from the top, the left, the bottom and the right (materials.lights_around)
SLANT_DEGREES = 40.0
# The image-as-height strengths tried: height (pixels) per unit of linear luminance, eight to a power
# of ten from 0.01 (a map within a degree of flat) to 1000 (far steeper than any material of the set).
STRENGTHS = np.geomspace(0.01, 1000.0, 41)
CSV_COLUMNS = ("material", "light_azimuth_deg", "light_slant_deg", "method", "mean_deg", "below_flat",
               "strength", "light_error_deg", "error")
FILES = ("materials.json", "materials.csv", "materials.md")


def default_lights() -> np.ndarray:
    """(4, 3) unit lights at :data:`SLANT_DEGREES` from the viewer: from the top, left, bottom, right."""
    return lights_around(LIGHT_COUNT, SLANT_DEGREES)


def flat_normals(shape: Sequence[int]) -> np.ndarray:
    """(H, W, 3) float32 normal map facing the viewer everywhere; ``shape`` is (H, W)."""
    normals = np.zeros((*shape[:2], 3), np.float32)
    normals[..., 2] = 1.0
    return normals


def image_as_height(photograph: np.ndarray, strength: float) -> np.ndarray:
    """(H, W, 3) unit normals of the photograph's linear luminance x ``strength`` read as a height in
    pixel units (brighter = higher), as a Bump node reads it; ``photograph`` (H, W) or (H, W, 3) linear."""
    return normals_from_depth(strength * luminance(photograph))


def height_errors(photograph: np.ndarray, truth: np.ndarray, strengths: Sequence[float] = STRENGTHS) -> np.ndarray:
    """Mean angular error (degrees) of :func:`image_as_height` against ``truth`` (H, W, 3), one per strength."""
    return np.array([angular_error(image_as_height(photograph, s), truth) for s in strengths])


def renders(material: Material, lights: np.ndarray, cast_shadows: bool = False) -> list[tuple[np.ndarray, np.ndarray]]:
    """(light, photograph) pairs: the material rendered Lambertian under each of ``lights`` (K, 3),
    with ``cast_shadows`` black where the relief hides the light (``materials.lambertian_photographs``)."""
    photographs = lambertian_photographs(material, lights, cast_shadows=cast_shadows)
    return list(zip(np.asarray(lights, dtype=np.float64), photographs))


def load_half(folder: os.PathLike | str, names: Sequence[str]) -> list[Material]:
    """The materials ``names`` of ``folder``, each checked by ``load_material`` (ValueError naming the
    missing or damaged file; a missing folder is named as such)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"shadecut: the materials folder {folder} does not exist")
    return [load_material(folder / name) for name in names]


def training_errors(folder: os.PathLike | str, lights: Optional[np.ndarray] = None,
                    names: Sequence[str] = TRAINING, cast_shadows: bool = False) -> np.ndarray:
    """Per strength of :data:`STRENGTHS`, the mean image-as-height error (degrees) over the renders of
    the training materials ``names`` of ``folder``, each under each light (default
    :func:`default_lights`; ``cast_shadows`` as :func:`renders`). A material of the test half among ``names`` is refused (ValueError): a
    strength chosen from it would have seen the test."""
    leaked = sorted(set(names) & set(TEST))
    if leaked:
        raise ValueError(f"shadecut: {', '.join(leaked)} belong to the test half; a strength is chosen on "
                         f"training materials only ({', '.join(TRAINING)})")
    lights = default_lights() if lights is None else lights
    errors = [height_errors(photograph, material.normals)
              for material in load_half(folder, names) for _, photograph in renders(material, lights, cast_shadows)]
    return np.mean(errors, axis=0)


def training_strength(errors: np.ndarray) -> float:
    """The one documented procedure: the strength of least mean error over the training renders
    (``errors`` from :func:`training_errors`)."""
    return float(STRENGTHS[int(np.argmin(errors))])


def _row(material: str, light: np.ndarray, method: str, mean_deg: Optional[float], **extra) -> dict:
    """A row; the light named by its azimuth (0 = from the right, 90 = from the top) and slant, degrees."""
    azimuth = round(float(np.degrees(np.arctan2(light[1], light[0]))), 6) % 360.0
    slant = round(float(np.degrees(np.arccos(light[2] / np.linalg.norm(light)))), 6)
    return {"material": material, "light_azimuth_deg": azimuth, "light_slant_deg": slant,
            "method": method, "mean_deg": mean_deg, **extra}


def true_shading(material: Material, photograph: np.ndarray) -> np.ndarray:
    """(H, W) float32: the photograph's luminance over the true albedo's (0 where the albedo is black)."""
    albedo = luminance(material.albedo)
    return np.where(albedo > 0, luminance(photograph) / np.where(albedo > 0, albedo, 1.0), 0.0).astype(np.float32)


def _shadecut_row(material: Material, photograph: np.ndarray, light: np.ndarray, reading: tuple, options: dict) -> dict:
    """ShadeCut's row on one render (one of _SHADECUT_READINGS); a refused call is a failed row."""
    method, given, shading = reading
    image, albedo = (true_shading(material, photograph), {"albedo": 1.0}) if shading else (photograph, {})
    try:
        result = reconstruct(image, light if given else None, scene="relief", **{**options, **albedo})
    except ValueError as error:
        return _row(material.name, light, method, None, error=str(error).removeprefix("shadecut: "))
    extra = {} if given else {"light_error_deg": light_error(result.light, light)}
    return _row(material.name, light, method, angular_error(result.normals, material.normals), **extra)


def render_rows(material: Material, light: np.ndarray, photograph: np.ndarray, strength: float,
                options: Optional[dict] = None) -> list[dict]:
    """The rows of one render, one per :data:`METHODS`: image as height at ``strength`` (the
    training-chosen one) and at the best of :data:`STRENGTHS` for this render; ``options`` are
    reconstruct() options (none: every default)."""
    errors = height_errors(photograph, material.normals)
    best = int(np.argmin(errors))
    trained = angular_error(image_as_height(photograph, strength), material.normals)
    flat = angular_error(flat_normals(photograph.shape), material.normals)
    rows = [_row(material.name, light, FLAT, flat),
            _row(material.name, light, HEIGHT_TRAINED, trained, strength=float(strength)),
            _row(material.name, light, HEIGHT_BEST, float(errors[best]), strength=float(STRENGTHS[best]))]
    rows += [_shadecut_row(material, photograph, light, reading, options or {}) for reading in _SHADECUT_READINGS]
    for row in rows:
        row["below_flat"] = None if row["method"] == FLAT or row["mean_deg"] is None else bool(row["mean_deg"] < flat)
    return rows


def evaluate_materials(folder: os.PathLike | str, names: Sequence[str], lights: np.ndarray, strength: float,
                       options: Optional[dict] = None, log: Callable[[str], None] = lambda line: None,
                       cast_shadows: bool = False) -> list[dict]:
    """Every row (:func:`render_rows`) of every material ``names`` of ``folder`` under each of
    ``lights`` (K, 3) (``cast_shadows`` as :func:`renders`), image as height at the training-chosen
    ``strength``."""
    lights = np.asarray(lights, dtype=np.float64)
    loaded = load_half(folder, names)
    rows = []
    for material in loaded:
        for light, photograph in renders(material, lights, cast_shadows):
            rows += render_rows(material, light, photograph, strength, options)
        means = summarize_materials([r for r in rows if r["material"] == material.name])
        log(f"materials: {material.name}: " + "; ".join(f"{m} {s['mean_deg']:.2f}°" for m, s in means.items()
                                                        if s["mean_deg"] is not None))
    return rows


def summarize_materials(rows: Sequence[dict]) -> dict:
    """Per method: the mean error over its rows (None if one failed), the renders below flat, the
    render count, failures, and the median light error (estimated light only, else None)."""
    summary = {}
    for method in METHODS:
        own = [r for r in rows if r["method"] == method]
        errors = [r["mean_deg"] for r in own]
        failed = sum(e is None for e in errors)
        light_errors = [r["light_error_deg"] for r in own if "light_error_deg" in r]
        summary[method] = {
            "mean_deg": float(np.mean(errors)) if own and not failed else None,
            "below_flat": None if method == FLAT else sum(bool(r["below_flat"]) for r in own),
            "renders": len(own), "failed": failed,
            "median_light_error_deg": float(np.median(light_errors)) if light_errors else None,
        }
    return summary


def summary_table(summary: dict) -> str:
    """Markdown: per method the mean error, the renders below flat and the median light error."""
    lines = ["| method | mean ° | renders below flat | light error, median ° |", "|---|---|---|---|"]
    for method, part in summary.items():
        below = "—" if part["below_flat"] is None else f"{part['below_flat']} of {part['renders']}"
        lines.append(f"| {method} | {_cell(part['mean_deg'])} | {below} | {_cell(part['median_light_error_deg'])} |")
    return "\n".join(lines)


def material_table(rows: Sequence[dict]) -> str:
    """Markdown: per material (rows) the mean error of each method over its lights (columns)."""
    names = list(dict.fromkeys(r["material"] for r in rows))
    lines = ["| material | " + " | ".join(METHODS) + " |", "|---" * (len(METHODS) + 1) + "|"]
    for name in names:
        summary = summarize_materials([r for r in rows if r["material"] == name])
        lines.append(f"| {name} | " + " | ".join(_cell(summary[m]["mean_deg"]) for m in METHODS) + " |")
    return "\n".join(lines)


def _cell(value: Optional[float]) -> str:
    return "—" if value is None else f"{value:.2f}"


def _training_line(settings: dict) -> str:
    """The training curve at each power of ten of :data:`STRENGTHS` ("" without one)."""
    curve = settings.get("training_mean_deg")
    if curve is None:
        return ""
    decades = [f"{strength:g}: {error:.2f}°" for strength, error in zip(settings["strengths"], curve)
               if np.isclose(np.log10(strength), round(np.log10(strength)))]
    return "Mean image-as-height error over the training renders, by strength: " + ", ".join(decades) + "."


def write_materials(out_dir: os.PathLike | str, rows: Sequence[dict], settings: dict) -> dict:
    """Writes :data:`FILES` into ``out_dir``, each whole or not at all: materials.json (``settings``,
    the rows, the summary), materials.csv (the rows) and materials.md (the command, the tables).
    ``settings`` holds at least "materials" (names) and "strength", and may hold "strengths" with
    "training_mean_deg" (the training curve). Returns name -> path."""
    out_dir = Path(out_dir)
    paths = {name: out_dir / name for name in FILES}
    summary = summarize_materials(rows)
    document = {"settings": settings, "rows": list(rows), "summary": summary}
    write_text(paths["materials.json"], json.dumps(document, indent=1, ensure_ascii=False) + "\n")
    table = io.StringIO()
    writer = csv.DictWriter(table, fieldnames=CSV_COLUMNS, extrasaction="ignore")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: ("" if v is None else v) for k, v in row.items()})
    write_text(paths["materials.csv"], table.getvalue())
    renders_count = len({(r["material"], r["light_azimuth_deg"]) for r in rows})
    lines = ["# Materials: the artist's baselines", "", provenance(), "",
             f"{renders_count} Lambertian renders{' with cast shadows' if settings.get('cast_shadows') else ''} of "
             f"{', '.join(settings['materials'])}; image-as-height "
             f"strength chosen on the training half: {settings['strength']:g}. Mean angular error in degrees "
             "over every pixel.", "", _training_line(settings), "", summary_table(summary), "", "Per material, the mean over its lights:", "",
             material_table(rows), ""]
    write_text(paths["materials.md"], "\n".join(lines))
    return paths


def evaluate_test_half(folder: os.PathLike | str, out_dir: os.PathLike | str, options: Optional[dict] = None,
                       log: Callable[[str], None] = lambda line: None, cast_shadows: bool = False) -> tuple[dict, dict]:
    """eval.py's --materials: the strength chosen on the training half of ``folder``, every row of the
    test half under :func:`default_lights` (``cast_shadows`` as :func:`renders`, both halves), written
    by :func:`write_materials`; (paths, summary)."""
    lights = default_lights()
    curve = training_errors(folder, lights, cast_shadows=cast_shadows)
    strength = training_strength(curve)
    log(f"materials: image-as-height strength {strength:g}, chosen on the training half ({', '.join(TRAINING)})")
    rows = evaluate_materials(folder, TEST, lights, strength, options, log, cast_shadows)
    settings = {"folder": str(Path(folder).resolve()), "materials": list(TEST), "training": list(TRAINING),
                "lights": lights.tolist(), "slant_deg": SLANT_DEGREES, "cast_shadows": cast_shadows, "strength": strength,
                "strengths": STRENGTHS.tolist(), "training_mean_deg": curve.tolist(), "options": dict(options or {})}
    return write_materials(out_dir, rows, settings), summarize_materials(rows)
