"""Headless evaluation: every ShadeCut method measured against ground truth, and the paper's experiment.

    blender -b -P blender_scripts/eval.py -- [--dataset DIR] [--methods graphcut,lee_rosenfeld,...]
        [--out DIR] [--size N] [--estimate-light [ESTIMATOR]] [--shapes a,b] [--lights N] [--seed S]
        [--no-paper] [--diligent DIR] [--materials DIR] [--fit-shading]

Without --dataset, the default dataset (make_dataset.py's built-in shapes, three seeded lights each,
256 x 256; --size, --shapes, --lights and --seed change it) is generated once into
$XDG_CACHE_HOME/shadecut/datasets/<hash of the settings> (~/.cache by default) and reused. Writes
results.json, results.csv, report.md and figures/ (a strip per sample, the paper's experiment as
normal maps and as Blender renders of the surfaces) to --out (default out/eval in the repository).

--diligent DIR evaluates real photographs: DIR is a DiLiGenT object folder (ballPNG/, in the
benchmark's own layout) or a folder of them. Each object is imported into <out>/diligent/<object>/
(once: a later run reuses it) and every method runs on every photograph with the calibrated light
and with the light estimated as reconstruct(light=None) does, the albedo always estimated; the
report gets a "Real photographs" section (a table per object, with the flat plane's row, and a
strip per object). Each object is also reconstructed from several of its photographs at once
(shadecut.evaluation.PHOTOGRAPH_SETS: two, four, eight, all) with their calibrated lights, beside
plain least squares over the same photographs, and with the lights estimated from the photographs
(reconstruct(photographs, None, mask), the default hint; the median angle to the calibrated lights
reported); a set of fewer than shadecut.FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS photographs, which the
library does not estimate lights from, is run with the calibrated lights only. --diligent alone
runs only that part; with --dataset DIR the synthetic dataset (and the paper's experiment, unless
--no-paper) is evaluated too.

--materials DIR evaluates one photograph of each scanned material of the test half
(shadecut.materials.TEST; DIR is ../shared/data/materials or a folder in its layout) under four lights
at slant 40 degrees, beside the artist's baselines: flat, the image as height (its strength chosen on
the training half, and the best strength knowing the truth) and ShadeCut (scene "relief", true and
estimated light). Writes materials.json, materials.csv and materials.md to --out
(shadecut.evaluation.materials). With --cast-shadows the renders are black where the relief hides the
light (both halves). Alone (or with --diligent only), no synthetic dataset is evaluated,
and without --diligent results.json, results.csv and report.md are not written.

Exit code: 0 when every method was evaluated on every sample (and material render); 1 when a method failed on a sample
(recorded in the results) or a result could not be written (a full disk: named, and every file is
either whole or its previous version, never cut short); 2 for bad input (unknown method, missing or malformed dataset, a
--diligent folder missing or not in DiLiGenT's layout, a --materials folder without the ten materials'
maps, unwritable output folder), with a message
and no traceback.

The metrics, tables and strips live in shadecut.evaluation (no bpy); this script parses the
arguments, generates the dataset and renders the 3-D surfaces with Blender.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import hashlib
import json
import os
import sys
import time
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "addon"))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # dataset_generator.py and shapes.py

import dataset_generator  # noqa: E402  (after the path inserts: the repository's scripts and package)
import shadecut  # noqa: E402
import shapes  # noqa: E402
from shadecut import evaluation  # noqa: E402
from shadecut import materials  # noqa: E402
from shadecut.evaluation import materials as material_baselines  # noqa: E402
from shadecut.blender import lambertian, lambertian_passes, lambertian_scene  # noqa: E402
from shadecut.atomic_write import replacing, write_text  # noqa: E402
from shadecut.blender.mesh import depth_mesh  # noqa: E402

# The sources of the generated dataset: a change to any of them gives a new dataset.
GENERATOR_SOURCES = tuple(Path(module.__file__) for module in (dataset_generator, shapes, lambertian,
                                                                lambertian_scene, lambertian_passes))
GENERATED_DEFAULTS = {"size": 256, "lights": 3, "seed": 0}


def parse_args(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="blender -b -P blender_scripts/eval.py --",
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--dataset", type=Path, metavar="DIR",
                        help="a dataset folder (make_dataset.py); default: generate one")
    parser.add_argument("--methods", metavar="A,B", help="comma-separated method names (default: all)")
    parser.add_argument("--out", type=Path, default=REPO / "out" / "eval", metavar="DIR",
                        help="output folder (default out/eval)")
    parser.add_argument("--estimate-light", nargs="?", const="lee_rosenfeld", choices=shadecut.LIGHT_METHODS,
                        metavar="ESTIMATOR", help="give the methods the light and albedo estimated from each image "
                        "instead of the true ones, by ESTIMATOR (default lee_rosenfeld, as the paper; or "
                        f"{', '.join(m for m in shadecut.LIGHT_METHODS if m != 'lee_rosenfeld')})")
    parser.add_argument("--no-paper", action="store_true",
                        help="skip the paper's experiment (Mozart, light (1,0,1))")
    parser.add_argument("--diligent", type=Path, metavar="DIR",
                        help="real photographs: a DiLiGenT object folder or a folder of them (alone: only these)")
    parser.add_argument("--materials", type=Path, metavar="DIR",
                        help="scanned materials (../shared/data/materials): one photograph of each of the test "
                             "half beside flat and the image as height (alone: only these)")
    parser.add_argument("--cast-shadows", action="store_true",
                        help="with --materials: render the materials with cast shadows")
    parser.add_argument("--fit-shading", action=argparse.BooleanOptionalAction,
                        help="graphcut's fit_shading (the depth fitted to the image) on or off "
                             f"(default: {'on' if shadecut.ReconstructOptions().fit_shading else 'off'})")
    generated = parser.add_argument_group("generated dataset (without --dataset)")
    generated.add_argument("--size", type=int, metavar="N",
                           help=f"image size in pixels (default {GENERATED_DEFAULTS['size']})")
    generated.add_argument("--shapes", metavar="A,B",
                           help="comma-separated built-in shapes (default: make_dataset.py's catalogue)")
    generated.add_argument("--lights", type=int, metavar="N",
                           help=f"lights per shape (default {GENERATED_DEFAULTS['lights']})")
    generated.add_argument("--seed", type=int, metavar="S",
                           help=f"make_dataset.py's seed: lights, bump layout (default {GENERATED_DEFAULTS['seed']})")
    return parser.parse_args(argv)


def cache_folder() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "shadecut" / "datasets"


def generated_dataset(args: argparse.Namespace) -> Path:
    """The default dataset for these settings, generated by make_dataset.py on first use.

    The folder is named by a hash of the settings and of the sources of the generator, its catalogue
    and its renderer, so a changed catalogue or renderer gives a new dataset instead of stale files. A marker
    written after the generator succeeded says the folder is complete; an interrupted generation is
    resumed (the generator skips the samples it finished). The generator checks the settings itself
    and prints what is wrong.
    """
    settings = {key: getattr(args, key) if getattr(args, key) is not None else default
                for key, default in GENERATED_DEFAULTS.items()}
    settings["shapes"] = args.shapes
    settings["generator"] = hashlib.sha256(b"".join(path.read_bytes() for path in GENERATOR_SOURCES)).hexdigest()[:16]
    key = hashlib.sha256(json.dumps(settings, sort_keys=True).encode()).hexdigest()[:12]
    folder = cache_folder() / key
    complete = folder / ".complete"
    if complete.is_file():
        print(f"reusing the generated dataset {folder}", flush=True)
        return folder

    print(f"generating the dataset {folder} ({json.dumps(settings)})", flush=True)
    argv = ["--out", str(folder), "--size", str(settings["size"]), "--lights", str(settings["lights"]),
            "--seed", str(settings["seed"])] + (["--shapes", args.shapes] if args.shapes else [])
    code = dataset_generator.main(argv)
    if code != 0:
        raise evaluation.EvaluationError(f"make_dataset.py {' '.join(argv)} failed (exit code {code})")
    write_text(complete, json.dumps(settings) + "\n")
    return folder


def _look_at(obj: bpy.types.Object, target: Vector) -> None:
    obj.rotation_euler = (target - obj.location).to_track_quat("-Z", "Y").to_euler()


def render_surfaces(surfaces: dict, folder: Path, resolution: int = 240) -> dict:
    """Renders each height field alone, same camera and light, to ``folder/<name>.png``.

    ``surfaces``: name -> (depth in pixel units, mask). Each surface is shifted so that its masked
    mean depth is 0: the depth of a reconstruction is known only up to a constant, and the view
    should compare shapes, not offsets. Cycles on the CPU (works headless without a GPU), few samples
    and no denoising (this Blender has no OpenImageDenoise). Returns name -> PNG path.
    """
    scene = bpy.data.scenes.new("shadecut_eval_surfaces")
    try:
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = 24
        scene.cycles.use_denoising = False
        scene.render.resolution_x = scene.render.resolution_y = resolution
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGBA"
        scene.render.film_transparent = True  # the figure's white shows around the surface
        scene.world = bpy.data.worlds.new("shadecut_eval_world")
        scene.world.color = (0.12, 0.12, 0.13)

        # Each surface spans [-1, 1] in x and y (depth_mesh's default size) and faces +z. The camera
        # aims at the centre of the first surface's mask from the front, a little from the right and
        # below, so relief shows as in the paper's 3-D plots; the same camera serves every surface.
        first_mask = np.asarray(next(iter(surfaces.values()))[1], dtype=bool)
        rows, cols = np.nonzero(first_mask)
        height, width = first_mask.shape
        unit = 2.0 / width
        target = Vector(((cols.mean() - (width - 1) / 2) * unit, ((height - 1) / 2 - rows.mean()) * unit, 0.0))
        camera = bpy.data.objects.new("shadecut_eval_camera", bpy.data.cameras.new("shadecut_eval_camera"))
        camera.location = target + Vector((0.9, -1.6, 2.4))
        _look_at(camera, target)
        camera.data.lens = 40
        sun = bpy.data.objects.new("shadecut_eval_sun", bpy.data.lights.new("shadecut_eval_sun", "SUN"))
        sun.data.energy = 3.0
        sun.location = (-2.0, 1.5, 1.6)  # raking from the upper left: relief casts clear shading
        _look_at(sun, Vector((0.0, 0.0, 0.0)))
        for helper in (camera, sun):
            scene.collection.objects.link(helper)
        scene.camera = camera

        paths = {}
        for name, (depth, mask) in surfaces.items():
            mask = np.asarray(mask, dtype=bool)
            centred = np.where(mask, depth - float(np.mean(depth[mask])), 0.0)
            mesh = depth_mesh(f"shadecut_eval_{name}", centred, mask)
            obj = bpy.data.objects.new(mesh.name, mesh)
            scene.collection.objects.link(obj)
            paths[name] = folder / f"{name}.png"
            with replacing(paths[name]) as temporary:  # a full disk leaves no truncated render under the name
                scene.render.filepath = str(temporary)
                bpy.ops.render.render(write_still=True, scene=scene.name)
                if not temporary.is_file():  # Blender reports a failed write on its console only
                    raise OSError(errno.EIO, "Blender could not write the render", str(paths[name]))
            bpy.data.objects.remove(obj)
            bpy.data.meshes.remove(mesh)
        return paths
    finally:
        for obj in list(scene.collection.objects):
            data = obj.data
            bpy.data.objects.remove(obj)
            if isinstance(data, bpy.types.Camera):
                bpy.data.cameras.remove(data)
            elif isinstance(data, bpy.types.Light):
                bpy.data.lights.remove(data)
        if scene.world is not None:
            bpy.data.worlds.remove(scene.world)
        bpy.data.scenes.remove(scene)


def save_surface_figure(path: Path, renders: dict, titles: dict) -> None:
    """The renders side by side in one PNG, each under its title (matplotlib's Agg canvas)."""
    import matplotlib.image
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(2.3 * len(titles), 2.6))
    FigureCanvasAgg(figure)
    axes = np.atleast_1d(figure.subplots(1, len(titles)))
    for axis, (name, title) in zip(axes, titles.items()):
        if name in renders:
            axis.imshow(matplotlib.image.imread(renders[name]))
        else:
            axis.text(0.5, 0.5, "failed", ha="center", va="center", transform=axis.transAxes)
        axis.set_title(title, fontsize=9)
        axis.set_axis_off()
    figure.suptitle("Mozart, light (1, 0, 1): surfaces reconstructed by each method", fontsize=10)
    figure.tight_layout()
    with replacing(path) as temporary:
        figure.savefig(temporary, dpi=80)


def paper_figures(figures: Path, result: evaluation.SampleResult) -> Path:
    """Blender renders of the true and every reconstructed Mozart surface, composed into one PNG."""
    truth = result.truth
    surfaces = {"truth": (truth.depth, truth.mask)}
    surfaces.update({method: (r.depth, r.mask) for method, r in result.reconstructions.items()})
    renders_folder = figures / "mozart_surfaces"
    renders_folder.mkdir(exist_ok=True)
    renders = render_surfaces(surfaces, renders_folder)
    titles = {"truth": "true surface"}
    for record in result.records:
        ok = record["status"] == "ok"
        titles[record["method"]] = f"{record['method']}, {record['mean_deg']:.1f}°" if ok else record["method"]
    path = figures / "mozart_paper_3d.png"
    save_surface_figure(path, renders, titles)
    return path


def check_materials(folder: Path | None) -> None:
    """EvaluationError unless ``folder`` (None: not asked) holds every material of both halves, readable."""
    if folder is not None:
        try:
            material_baselines.load_half(folder, materials.TRAINING + materials.TEST)
        except ValueError as error:
            raise evaluation.EvaluationError(str(error).removeprefix("shadecut: ")) from None


def main(argv: list[str]) -> int:
    args = parse_args(argv)
    start = time.monotonic()
    log = lambda line: print(line, flush=True)  # noqa: E731  (progress shows while Blender runs)
    out = args.out.resolve()
    new_out = not out.exists()
    try:
        methods = evaluation.check_methods(args.methods.split(",") if args.methods is not None else None)
        generated_only = [f"--{k}" for k in ("size", "shapes", "lights", "seed") if getattr(args, k) is not None]
        if args.dataset is not None and generated_only:
            raise evaluation.EvaluationError(f"{', '.join(generated_only)} apply to the generated dataset, "
                                             "not to one given with --dataset")
        # --diligent or --materials alone: those photographs only
        run_dataset = (args.diligent is None and args.materials is None) or args.dataset is not None
        if not run_dataset and (generated_only or args.estimate_light):
            given = generated_only + (["--estimate-light"] if args.estimate_light else [])
            raise evaluation.EvaluationError(f"{', '.join(given)} apply to a synthetic dataset, which --diligent "
                                             "or --materials alone does not evaluate (add --dataset DIR)")
        if args.cast_shadows and args.materials is None:
            raise evaluation.EvaluationError("--cast-shadows renders the scanned materials: give --materials DIR")
        objects = evaluation.find_objects(args.diligent) if args.diligent is not None else []
        check_materials(args.materials)
        evaluation.prepare_output(out)
        dataset = None
        if run_dataset:
            dataset = args.dataset if args.dataset is not None else generated_dataset(args)
            evaluation.read_manifest(dataset)
        imported = evaluation.import_objects(objects, out / "diligent", log=log) if objects else {}
        figures = evaluation.prepare_output(out / "figures")
    except evaluation.EvaluationError as error:
        if new_out:  # a run refused before any work leaves no empty folder of its own
            with contextlib.suppress(OSError):
                out.rmdir()
        print(f"eval.py: error: {error}", file=sys.stderr)
        return 2
    try:
        return evaluate_and_report(args, methods, dataset, imported, out, figures, log, start)
    except OSError as error:  # a full disk, a folder removed: every file written is whole or the old one
        name = f" {error.filename}" if error.filename else ""
        print(f"eval.py: error: cannot write{name}: {error.strerror or error}; the files already written are "
              "whole and those not yet replaced keep their previous contents", file=sys.stderr)
        return 1


def evaluate_and_report(args: argparse.Namespace, methods: tuple, dataset: Path | None, imported: dict, out: Path,
                        figures: Path, log, start: float) -> int:
    """Evaluates what the checked arguments ask and writes the report; the exit code (1: a method failed)."""
    run_dataset = dataset is not None
    options = {} if args.fit_shading is None else {"fit_shading": args.fit_shading}
    shown = []
    if run_dataset:
        light = (f"light and albedo estimated by {args.estimate_light}" if args.estimate_light
                 else "true light and albedo")
        log(f"evaluating {len(methods)} methods ({', '.join(methods)}) on {dataset}; {light}")
        run = evaluation.evaluate_dataset(dataset, methods, light_method=args.estimate_light, options=options,
                                          figures_dir=figures, log=log)
        shown = [f"figures/{s['id']}.png" for s in run.samples if (figures / f"{s['id']}.png").is_file()]
    else:
        run = evaluation.Evaluation({"dataset": None, "methods": list(methods), "light_method": None,
                                     "options": options, "erode_pixels": evaluation.ERODE_PIXELS}, [], [])
    if run_dataset and not args.no_paper:
        log("the paper's experiment: Mozart, light (1, 0, 1)")
        run.paper, result = evaluation.paper_experiment(shapes.MOZART, methods, options=options, figures_dir=figures,
                                                        log=log)
        shown = ["figures/mozart_paper.png", paper_figures(figures, result).relative_to(out).as_posix()] + shown
    if imported:
        log(f"evaluating {len(methods)} methods ({', '.join(methods)}) on the real photographs of "
            f"{', '.join(imported)}; calibrated, then estimated light; albedo estimated")
        run.real = evaluation.evaluate_real(imported, methods, options=options, figures_dir=figures, log=log)
    material_failures = 0
    if args.materials is not None:
        log(f"one photograph of each material of the test half ({', '.join(materials.TEST)}) beside the artist's "
            "baselines")
        material_paths, material_summary = material_baselines.evaluate_test_half(args.materials, out, options, log,
                                                                                 args.cast_shadows)
        log("\nMaterials, test half:\n" + material_baselines.summary_table(material_summary))
        log(f"written to {out}: {', '.join(material_paths)}")
        material_failures = sum(part["failed"] for part in material_summary.values())
    if not (run_dataset or imported):
        return 1 if material_failures else 0
    paths = evaluation.write_results(out, run, shown)

    summary = run.summary
    if run_dataset:
        log("\n" + evaluation.method_table(summary) + "\n\n" + evaluation.shape_table(summary))
    if run.paper:
        log("\nThe paper's experiment, Mozart, light (1, 0, 1):\n" + evaluation.method_table(run.paper["summary"]))
    for name, part in (run.real or {}).get("objects", {}).items():
        log(f"\nReal photographs, {name}:\n" + evaluation.real_table(part))
        if part.get("photographs"):
            log(f"\nSeveral photographs, {name}, calibrated and estimated lights:\n"
                + evaluation.photographs_table(part))
    failed = run.failed
    if failed:
        log(f"\n{len(failed)} evaluation(s) failed:")
        for record in failed:
            log(f"  {record['sample']} / {record['method']}: {record['error']}")
    log(f"\nreport written to {out}: {paths['report'].name}, {paths['json'].name}, {paths['csv'].name}, figures/ "
        f"({time.monotonic() - start:.0f} s in all)")
    return 1 if failed or material_failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []))
