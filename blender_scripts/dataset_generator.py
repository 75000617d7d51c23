"""The synthetic dataset generator behind make_dataset.py (its docstring describes the command):
arguments, plan, rendering loop, manifest. A module, so that eval.py generates its default dataset
in-process with :func:`main`; the shapes themselves are the catalogue in shapes.py."""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import math
import os
import re
import sys
import time
from pathlib import Path

import bpy
import numpy as np

REPO = Path(__file__).resolve().parents[1]
for _path in (str(REPO / "addon"), str(Path(__file__).resolve().parent)):  # shadecut; its helper scripts
    if _path not in sys.path:
        sys.path.insert(0, _path)

import shadecut  # noqa: E402  (after the path insert: the repository's package)
from shadecut import dataset  # noqa: E402
from shadecut.atomic_write import check_writable  # noqa: E402
from shadecut.blender import lambertian  # noqa: E402
from sigint import StopRequest  # noqa: E402
from usage import Parser, UsageError  # noqa: E402
from shapes import (  # noqa: E402
    BUILDERS, CATALOGUE, MESH_SUFFIXES, MeshFileError, load_mesh_file, remove_objects, shape_rng,
)

MAX_LIGHTS = 100_000  # per shape
MAX_SAMPLES = 1 << 24  # Cycles samples, as Blender's own limit
MANIFEST_INTERVAL = 10.0  # seconds between manifest refreshes while rendering (and once at the end)
# Planned parameters that a finished sample must share with the plan to be skipped on a re-run.
PLAN_KEYS = ("shape", "light", "albedo", "size", "seed", "noise", "bits", "shadows", "indirect", "samples")


def parse_args(argv: list[str]) -> argparse.Namespace:
    parser = Parser(prog="blender -b -P blender_scripts/make_dataset.py --",
                     description="Renders a synthetic Lambertian dataset with exact ground truth "
                                 "(see the module docstring).")
    parser.add_argument("--out", type=Path, required=True, help="dataset folder (created if missing)")
    parser.add_argument("--shapes", help=f"comma-separated built-in shapes from {', '.join(CATALOGUE)} "
                                         "(default: all of them, or none when --mesh is given)")
    parser.add_argument("--mesh", type=Path, action="append", default=[],
                        help="a mesh file (.obj, .ply, .stl, or .blend: its mesh objects) to render as one more "
                             "shape named after the file; repeatable")
    parser.add_argument("--lights", type=int, default=3, help="lights drawn per shape (default 3)")
    parser.add_argument("--light", action="append", default=[], metavar="X,Y,Z",
                        help="a fixed light direction in the camera frame instead of drawn ones; repeatable")
    parser.add_argument("--slant-min", type=float, default=10.0, help="degrees (default 10)")
    parser.add_argument("--slant-max", type=float, default=60.0, help="degrees, below 90 (default 60)")
    parser.add_argument("--size", type=int, default=256, help="image width and height in pixels (default 256)")
    parser.add_argument("--albedo", type=float, default=0.8, help="uniform albedo in (0, 1] (default 0.8)")
    parser.add_argument("--noise", type=float, default=0.0, help="Gaussian noise sigma, linear intensity (default 0)")
    parser.add_argument("--bits", type=int, choices=(8, 16), help="quantize the image to 8 or 16-bit sRGB codes")
    parser.add_argument("--shadows", action="store_true", help="cast shadows (off: the paper's model)")
    parser.add_argument("--indirect", action="store_true", help="indirect light between surfaces")
    parser.add_argument("--samples", type=int, help="Cycles samples (default: 1 without indirect light, "
                                                    f"{lambertian.INDIRECT_SAMPLES} with it)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the lights, the noise and the bumps (default 0)")
    parser.add_argument("--shard", default="0/1", metavar="I/N", help="render only samples I, I+N, I+2N, ...")
    parser.add_argument("--verbose", action="store_true", help="keep Blender's own output of every render")
    args = parser.parse_args(argv)

    match = re.fullmatch(r"(\d+)/(\d+)", args.shard)
    if not match or not int(match[1]) < int(match[2]):
        raise UsageError(f"--shard must be I/N with 0 <= I < N; got {args.shard!r}")
    args.shard_index, args.shard_count = int(match[1]), int(match[2])
    if args.shapes is None:
        args.shapes = [] if args.mesh else list(CATALOGUE)
    else:
        args.shapes = [name.strip() for name in args.shapes.split(",") if name.strip()]
        unknown = [name for name in args.shapes if name not in CATALOGUE]
        if unknown:
            raise UsageError(f"unknown shape(s) {', '.join(unknown)}; the catalogue is {', '.join(CATALOGUE)}")
    for path in args.mesh:
        if path.suffix.lower() not in MESH_SUFFIXES:
            raise UsageError(f"cannot read mesh {path}: the format must be one of {', '.join(MESH_SUFFIXES)}")
        if not path.is_file():
            raise UsageError(f"cannot read mesh {path}: no such file")
    if not args.shapes and not args.mesh:
        raise UsageError("nothing to render: give --shapes and/or --mesh")
    if not 8 <= args.size <= 16384:
        raise UsageError(f"--size must be 8 to 16384 pixels; got {args.size}")
    if not 0 < args.albedo <= 1:
        raise UsageError(f"--albedo must be in (0, 1]; got {args.albedo}")
    if not (math.isfinite(args.noise) and args.noise >= 0):
        raise UsageError(f"--noise must be a finite number >= 0; got {args.noise}")
    if args.seed < 0:
        raise UsageError(f"--seed must be >= 0; got {args.seed}")
    if args.samples is not None and not 1 <= args.samples <= MAX_SAMPLES:
        raise UsageError(f"--samples must be 1 to {MAX_SAMPLES}; got {args.samples}")
    if not 1 <= args.lights <= MAX_LIGHTS:
        raise UsageError(f"--lights must be 1 to {MAX_LIGHTS}; got {args.lights}")
    args.fixed_lights = [parse_light(text) for text in args.light]
    if not args.fixed_lights:
        if not 0 <= args.slant_min <= args.slant_max < 90:  # False for NaN too
            raise UsageError(f"the slants must satisfy 0 <= --slant-min <= --slant-max < 90 (a light at 90 degrees "
                             f"or more is at or below the horizon); got {args.slant_min} and {args.slant_max}")
    return args


def parse_light(text: str) -> list[float]:
    try:
        vector = np.array([float(v) for v in text.split(",")])
    except ValueError:
        raise UsageError(f"--light must be X,Y,Z; got {text!r}") from None
    if vector.shape != (3,):
        raise UsageError(f"--light must be X,Y,Z; got {text!r}")
    try:
        return shadecut.light_direction(vector).tolist()
    except ValueError as error:
        raise UsageError(f"--light {text}: {error}") from None


def draw_lights(rng: np.random.Generator, count: int, slant_min: float, slant_max: float) -> list[list[float]]:
    """Directions uniform over the solid angle between the two slants (uniform cos slant), any tilt.

    Light k uses the draws 2k and 2k + 1 only, so more --lights extend a dataset without changing the
    lights it has.
    """
    draws = rng.random((count, 2))
    low, high = math.cos(math.radians(slant_max)), math.cos(math.radians(slant_min))
    cos_slant = low + (high - low) * draws[:, 0]
    tilt = 2 * math.pi * draws[:, 1]
    sin_slant = np.sqrt(1 - cos_slant**2)
    return np.stack([sin_slant * np.cos(tilt), sin_slant * np.sin(tilt), cos_slant], axis=1).tolist()


# --- the plan, the renders, the manifest ---

def plan(args: argparse.Namespace) -> list[dict]:
    """Every sample of the dataset, in order, with its parameters (independent of the shard)."""
    shapes = [(name, None) for name in args.shapes]
    used = set(args.shapes)
    for path in args.mesh:
        name = re.sub(r"[^A-Za-z0-9_-]+", "_", path.stem) or "mesh"
        unique, count = name, 2
        while unique in used:
            unique, count = f"{name}{count}", count + 1
        used.add(unique)
        shapes.append((unique, path))
    entries = []
    for shape, path in shapes:
        lights = args.fixed_lights or draw_lights(shape_rng(args.seed, shape, "lights"), args.lights,
                                                  args.slant_min, args.slant_max)
        for k, light in enumerate(lights):
            sample_id = f"{shape}_{k:03d}"
            entry = {
                "id": sample_id,
                "shape": shape,
                "folder": sample_id,
                "light": light,
                "slant_deg": math.degrees(math.acos(min(1.0, light[2]))),
                "tilt_deg": math.degrees(math.atan2(light[1], light[0])) % 360,
                "albedo": args.albedo,
                "size": args.size,
                "seed": int(shape_rng(args.seed, sample_id, "noise").integers(2**31)),
                "noise": args.noise,
                "bits": args.bits,
                "shadows": args.shadows,
                "indirect": args.indirect,
                "samples": args.samples,
            }
            if path is not None:
                entry["mesh_file"] = str(path.resolve())
            entries.append(entry)
    return entries


def check_output(folder: Path) -> None:
    try:
        check_writable(folder)  # real bytes: an empty probe fits on a full disk
    except OSError as error:
        raise UsageError(f"cannot write to the output folder {folder}: {error.strerror or error}") from None


def same_setting(made, planned) -> bool:
    """Whether a sample was made with the planned value: equal, numbers within 1e-9 of each other
    (relative). A drawn light can differ in its last bit between two plans of one Blender process:
    seen after renders had run in it, one bit apart in a component, which is no other setting."""
    if isinstance(planned, list):
        return isinstance(made, list) and len(made) == len(planned) and all(map(same_setting, made, planned))
    if isinstance(planned, float) and isinstance(made, (int, float)) and not isinstance(made, bool):
        return math.isclose(made, planned, rel_tol=1e-9, abs_tol=1e-12)
    return made == planned


def finished(folder: Path, entry: dict) -> bool:
    """True when the sample exists, complete and readable (dataset.check_sample); UsageError when it
    exists with other parameters than planned. A damaged sample is reported and is not finished."""
    sample = folder / entry["folder"]
    if not dataset.is_sample(sample):
        return False
    try:
        meta = dataset.load_sample_meta(sample)
    except (OSError, ValueError):
        meta = None  # damaged: check_sample says how
    if isinstance(meta, dict):
        made = meta.get("dataset_entry")
        made = made if isinstance(made, dict) else {}
        different = [key for key in PLAN_KEYS if not same_setting(made.get(key), entry[key])]
        if different:
            raise UsageError(f"{sample} was made with other settings ({', '.join(different)}); "
                             "use another --out folder, or delete it")
    problem = dataset.check_sample(sample)
    if problem is not None:
        print(f"make_dataset: {entry['id']} is incomplete or damaged, so not done: {problem}", file=sys.stderr,
              flush=True)
        return False
    return True


# Ctrl+C stops the whole run, instead of Blender's own handling of it, which cancels the render under
# way (Python sees a render that returned early) and carries on with the next sample. Outside a sample
# it raises KeyboardInterrupt at once; inside one (STOP.deferring()) the sample is finished first,
# since a KeyboardInterrupt raised inside Blender's render would land in Python code that Blender
# calls (Cycles' engine.render), where Blender prints and swallows it. KeyboardInterrupt unwinds the
# loop (a half-written sample is removed by dataset.write_sample; the manifest is refreshed) and
# main() reports it.
STOP = StopRequest("make_dataset: Ctrl+C: stopping after the sample under way", always_deferred=False)


@contextlib.contextmanager
def quiet_stdout(enabled: bool):
    """Sends file descriptor 1 to /dev/null, silencing Blender's per-render lines ("Fra:", "Saved:")."""
    if not enabled:
        yield
        return
    libc = ctypes.CDLL(None) if os.name == "posix" else None
    sys.stdout.flush()
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        yield
    finally:
        if libc is not None:
            libc.fflush(None)  # C-level output buffered during the render must go to /dev/null too
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)


def render_sample(entry: dict, objects: list, args: argparse.Namespace, folder: Path) -> None:
    with quiet_stdout(not args.verbose):
        render = lambertian.render_lambertian(
            objects, light=entry["light"], resolution=(entry["size"], entry["size"]), albedo=entry["albedo"],
            shadows=entry["shadows"], indirect=entry["indirect"], noise=entry["noise"], bits=entry["bits"],
            seed=entry["seed"], samples=entry["samples"])
    render.meta.update(shape=entry["shape"], dataset_entry=entry)
    render.write(folder / entry["folder"])


def describe(seconds: float) -> str:
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def write_manifest(folder: Path, entries: list[dict], done: set, args: argparse.Namespace) -> None:
    info = {"generator": "blender_scripts/make_dataset.py", "blender_version": bpy.app.version_string,
            "shapes": sorted({entry["shape"] for entry in entries}), "samples_planned": len(entries),
            "seed": args.seed, "size": args.size, "lights_per_shape": len(args.fixed_lights) or args.lights,
            "slant_range_deg": [args.slant_min, args.slant_max], "albedo": args.albedo, "noise": args.noise,
            "bits": args.bits, "shadows": args.shadows, "indirect": args.indirect}
    dataset.write_manifest(folder, [entry for entry in entries if entry["id"] in done], info)


def generate(args: argparse.Namespace) -> int:
    folder = args.out
    check_output(folder)
    for path in args.mesh:  # an unreadable file is reported before anything is rendered
        remove_objects(load_mesh_file(path))
    entries = plan(args)
    mine = [entry for index, entry in enumerate(entries) if index % args.shard_count == args.shard_index]
    done = {entry["id"] for entry in entries if finished(folder, entry)}
    todo = [entry for entry in mine if entry["id"] not in done]
    print(f"make_dataset: {len(entries)} samples planned, {len(mine)} in shard {args.shard}, "
          f"{len(mine) - len(todo)} already done, {len(todo)} to render into {folder}", flush=True)

    failures = 0
    rendered_seconds = []
    last_manifest = time.monotonic()
    shape_objects: dict[str, list] = {}
    try:
        for position, entry in enumerate(todo, 1):
            shape = entry["shape"]
            with STOP.deferring():  # Ctrl+C: this sample is finished, then the run stops
                if shape not in shape_objects:
                    # Objects of the previous shape go first: only one shape's meshes are alive at a time.
                    for objects in shape_objects.values():
                        remove_objects(objects)
                    shape_objects = {shape: (load_mesh_file(Path(entry["mesh_file"])) if "mesh_file" in entry
                                             else BUILDERS[shape](args.seed))}
                start = time.monotonic()
                try:
                    render_sample(entry, shape_objects[shape], args, folder)
                except (RuntimeError, OSError, ValueError) as error:
                    failures += 1
                    print(f"make_dataset: {entry['id']} failed: {error}", file=sys.stderr, flush=True)
                    continue
                rendered_seconds.append(time.monotonic() - start)
                done.add(entry["id"])
                left = len(todo) - position
                eta = np.mean(rendered_seconds) * left
                print(f"[{position}/{len(todo)}] {entry['id']} slant {entry['slant_deg']:.1f} tilt "
                      f"{entry['tilt_deg']:.1f}: {rendered_seconds[-1]:.2f} s; {left} left, about {describe(eta)} "
                      "to go", flush=True)
            if time.monotonic() - last_manifest > MANIFEST_INTERVAL:
                write_manifest(folder, entries, done, args)
                last_manifest = time.monotonic()
    finally:
        for objects in shape_objects.values():
            remove_objects(objects)
        # Other shards may have finished samples meanwhile: list what is on disk now.
        done |= {entry["id"] for entry in entries if entry["id"] not in done
                 and dataset.is_sample(folder / entry["folder"])
                 and dataset.check_sample(folder / entry["folder"]) is None}
        write_manifest(folder, entries, done, args)
    print(f"make_dataset: {len(done)} of {len(entries)} samples done in {folder}"
          + (f"; {failures} failed" if failures else ""), flush=True)
    return 1 if failures else 0


def main(argv: list[str]) -> int:
    """Runs the generator with the arguments that follow "--" on Blender's command line."""
    try:
        args = parse_args(argv)
        with STOP.installed():
            return generate(args)
    except (UsageError, MeshFileError) as error:
        print(f"make_dataset: error: {error}", file=sys.stderr, flush=True)
        return 2
    except SystemExit as exit_:  # --help
        return int(exit_.code or 0)
    except KeyboardInterrupt:
        print("make_dataset: interrupted (Ctrl+C): the run is stopped; the finished samples and the manifest are "
              "kept, re-run the same command to continue", file=sys.stderr, flush=True)
        return 130

