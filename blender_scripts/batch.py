"""Headless batch: every image of a folder reconstructed, its height, normal map and mesh written.

    blender -b -P blender_scripts/batch.py -- IN_DIR OUT_DIR [--scene auto|object|relief] [--max-size N]
                                              [--max-vertices N | --full-mesh]
    python3 blender_scripts/batch.py IN_DIR OUT_DIR [...]       (works without Blender too)

Every file of IN_DIR (not its subfolders) with an image extension (.png .jpg .jpeg .tif .tiff .exr
.hdr .bmp .tga, any case) is read by ``shadecut.load_image`` (its alpha, if any, is the mask),
reconstructed by ``shadecut.reconstruct`` with the light and albedo estimated from the image and the
library's default options, and written to OUT_DIR (created if missing) as

    <stem>_height.exr   the depth in pixel units, larger = closer: a grey float image (channel Y, alpha
                        A = mask) that Blender loads as the heights (shadecut.save_depth)
    <stem>_normal.png   a tangent-space normal map, 0.5 n + 0.5 as RGB (16-bit, Non-Color data),
                        the add-on's rule (shadecut.imaging.normal_colors)
    <stem>.ply          the height field as a triangle mesh (shadecut.save_mesh), pixel units, within
                        the add-on's Vertex limit (shadecut.MAX_VERTICES, 250,000): one vertex every
                        shadecut.vertex_step pixels; --max-vertices N sets another budget, --full-mesh
                        gives every pixel a vertex

The subject (the add-on's Subject) is, by default (--scene auto), chosen for each image from its
alpha: an image whose alpha leaves part of it transparent is an object cut out from its background
(Object); one without alpha, or opaque everywhere, fills the frame and is read as a relief (a wall,
a coin, bark, a texture: Relief, which keeps its carrier flat). An object photographed on a plain
background without alpha needs --scene object; --scene relief or object sets every image's subject.
--max-size N shrinks a larger image by a whole factor until neither side exceeds N pixels, as the
add-on's Max size does (0 = full size, the default here). Each file's three outputs are written
under temporary names of this run's own and then renamed, so a file named like an output is always
complete, and two runs into one OUT_DIR never take each other's temporary files.

One progress line per image (index/total, name, seconds, the subject and why, the light found,
the mesh's density); a file that cannot be
read or reconstructed gets an error line naming it, and the others are still done. Files without an
image extension are listed as skipped.

Exit code: 0 when every image was done; 1 when an image failed (each named, and listed again at the
end); 2 for bad arguments (IN_DIR missing or not a folder, no image file in it, OUT_DIR not
creatable, a negative --max-size, an output that would replace a file of IN_DIR, as OUT_DIR = IN_DIR
does for x.png beside x_normal.png or x.ply), with a message and no traceback: nothing is written. Ctrl+C (SIGINT) stops the run:
the image under way is abandoned (nothing of it is written), the finished ones are kept, exit code 130.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
for _path in (str(REPO / "addon"), str(Path(__file__).resolve().parent)):  # shadecut; sigint.py, usage.py
    if _path not in sys.path:
        sys.path.insert(0, _path)

import OpenImageIO as oiio  # noqa: E402  (shadecut.dataset's writer too; in Debian's Blender and python3)
import shadecut  # noqa: E402  (after the path insert: the repository's package)
from shadecut import imaging  # noqa: E402
from shadecut.atomic_write import replacing  # noqa: E402
from sigint import StopRequest  # noqa: E402
from usage import Parser, UsageError  # noqa: E402

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr", ".hdr", ".bmp", ".tga")
PROG = "batch.py"
AUTO = "auto"


def parse_args(argv: list[str]) -> argparse.Namespace:
    parser = Parser(prog="blender -b -P blender_scripts/batch.py --",
                     description="Reconstructs every image of IN_DIR into OUT_DIR: <stem>_height.exr (the heights "
                                 "in pixel units as a grey float image, alpha = mask, which Blender opens as a "
                                 "height image), <stem>_normal.png (a tangent-space normal map) and <stem>.ply "
                                 "(the mesh). More in the script's docstring and docs/blender_addon.md.")
    parser.add_argument("in_dir", type=Path, metavar="IN_DIR", help="folder of images")
    parser.add_argument("out_dir", type=Path, metavar="OUT_DIR", help="output folder (created if missing)")
    parser.add_argument("--scene", choices=[AUTO, *shadecut.SceneKind.__members__], default=AUTO,
                        help="what the images show (default auto: relief for an image without transparent "
                             "pixels, which fills the frame, object for one whose alpha cuts it out; give "
                             "--scene object for objects photographed on a background without alpha)")
    parser.add_argument("--max-size", type=int, default=0, metavar="N",
                        help="shrink larger images by a whole factor to at most N px a side (default 0 = full size)")
    mesh = parser.add_mutually_exclusive_group()
    mesh.add_argument("--max-vertices", type=int, default=shadecut.MAX_VERTICES, metavar="N",
                      help=f"the mesh's vertex budget: one vertex every few pixels so that at most N remain "
                           f"(default {shadecut.MAX_VERTICES:,}, the add-on's Vertex limit)")
    mesh.add_argument("--full-mesh", action="store_true", help="every masked pixel a vertex of the mesh")
    args = parser.parse_args(argv)
    if args.max_size < 0:
        raise UsageError(f"--max-size must be 0 (full size) or more, not {args.max_size}")
    if args.max_vertices < 4:
        raise UsageError(f"--max-vertices must be at least 4 (one quad), not {args.max_vertices}")
    return args


def list_inputs(in_dir: Path) -> tuple[list[Path], list[Path]]:
    """The image files of ``in_dir`` (sorted by name) and the other visible files (skipped)."""
    if not in_dir.exists():
        raise UsageError(f"IN_DIR {in_dir} does not exist")
    if not in_dir.is_dir():
        raise UsageError(f"IN_DIR {in_dir} is not a folder")
    try:
        files = sorted((path for path in in_dir.iterdir() if path.is_file()), key=lambda path: path.name)
    except OSError as error:
        raise UsageError(f"cannot list IN_DIR {in_dir}: {error.strerror or error}") from error
    images = [path for path in files if path.suffix.lower() in IMAGE_EXTENSIONS]
    skipped = [path for path in files if path not in images and not path.name.startswith(".")]
    if not images:
        raise UsageError(f"IN_DIR {in_dir} holds no image file ({' '.join(IMAGE_EXTENSIONS)})")
    return images, skipped


def prepare_output(out_dir: Path) -> None:
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise UsageError(f"cannot create OUT_DIR {out_dir}: {error.strerror or error}") from error
    if not os.access(out_dir, os.W_OK | os.X_OK):
        raise UsageError(f"OUT_DIR {out_dir} is not writable")


def output_paths(out_dir: Path, stem: str) -> dict[str, Path]:
    return {"height": out_dir / f"{stem}_height.exr", "normal": out_dir / f"{stem}_normal.png",
            "mesh": out_dir / f"{stem}.ply"}


def check_inputs_kept(inputs: list[Path], out_dir: Path) -> None:
    """UsageError when an output of an image would replace a file of IN_DIR (``inputs``: its images
    and the files skipped; OUT_DIR = IN_DIR, x.png beside x_normal.png or beside x.ply): an image would
    be overwritten before it is read and the overwritten image reconstructed, any other file lost."""
    kept = {path.resolve(): path for path in inputs}
    for image in (path for path in inputs if path.suffix.lower() in IMAGE_EXTENSIONS):
        replaced = [kept[resolved].name for resolved in (path.resolve() for path in
                                                         output_paths(out_dir, image.stem).values())
                    if resolved in kept]
        if replaced:
            raise UsageError(f"the outputs of {image.name} would replace {', '.join(replaced)} in {out_dir}: "
                             "choose another OUT_DIR, or rename the input")


def save_normal_map(path: Path, normals: np.ndarray, mask: np.ndarray) -> None:
    """The normals as a 16-bit RGB PNG of the add-on's normal-map colours (imaging.normal_colors)."""
    colors = imaging.normal_colors(normals, mask)
    height, width = mask.shape
    out = oiio.ImageOutput.create(str(path))
    if out is None or not out.open(str(path), oiio.ImageSpec(width, height, 3, oiio.UINT16)):
        raise OSError(f"cannot write {path}: {oiio.geterror()}")
    written = out.write_image(np.round(np.clip(colors, 0.0, 1.0) * 65535).astype(np.uint16))
    out.close()
    if not written:
        raise OSError(f"cannot write {path}: {oiio.geterror()}")


def write_outputs(paths: dict[str, Path], result, mesh_step: int) -> None:
    """The three files of one reconstruction, each written under a temporary name of its own (two runs
    into one folder never share one) and renamed over its name only when all three are complete; the
    mesh samples every ``mesh_step`` pixels."""
    with contextlib.ExitStack() as stack:
        partial = {key: stack.enter_context(replacing(path)) for key, path in paths.items()}
        shadecut.save_depth(partial["height"], result.depth, result.mask)
        save_normal_map(partial["normal"], result.normals, result.mask)
        shadecut.save_mesh(partial["mesh"], result.depth, result.mask, mesh_step)


STOP = StopRequest(f"{PROG}: Ctrl+C: stopping (the image under way is abandoned)", always_deferred=True)


def _progress(fraction: float, stage: str) -> bool:
    return not STOP.requested  # False: the core stops with shadecut.Cancelled


def subject(loaded, scene: str) -> tuple[str, str]:
    """The subject (a SceneKind name) of a loaded image for --scene ``scene``, and why, for the log."""
    if scene != AUTO:
        return scene, "--scene"
    if loaded.has_alpha and not loaded.mask.all():
        return "object", "auto: its alpha cuts it out"
    return "relief", "auto: " + ("opaque everywhere" if loaded.has_alpha else "no alpha") + ", it fills the frame"


def reconstruct_file(path: Path, args: argparse.Namespace) -> tuple[object, str, str]:
    """The reconstruction of one image file, a note on its subject and one on its working size ("" at
    full size)."""
    loaded = shadecut.load_image(path)
    image, mask = loaded.image, loaded.mask
    scene, reason = subject(loaded, args.scene)
    note = ""
    if args.max_size:
        height, width = mask.shape
        try:
            image, mask, factor = imaging.downsample(image, mask, args.max_size)
        except ValueError as error:
            raise ValueError(f"--max-size {args.max_size}: {error}") from error
        if factor > 1:
            note = f" (shrunk by {factor} from {width} x {height})"
    return shadecut.reconstruct(image, mask=mask, progress=_progress, scene=scene), f"subject {scene} ({reason})", note


def run(args: argparse.Namespace) -> int:
    images, skipped = list_inputs(args.in_dir)
    check_inputs_kept(images + skipped, args.out_dir)
    prepare_output(args.out_dir)
    scenes = list(shadecut.SceneKind.__members__) if args.scene == AUTO else [args.scene]
    lights = "/".join(shadecut.ReconstructOptions(scene=scene).light_method_used().name for scene in scenes)
    print(f"{PROG}: {len(images)} image(s) in {args.in_dir} -> {args.out_dir}; scene {args.scene}"
          f"{' (relief without transparent pixels, else object)' if args.scene == AUTO else ''}, "
          f"method {shadecut.ReconstructOptions().method.name}, light estimated ({lights}), "
          f"max size {args.max_size or 'full'}, mesh "
          f"{'every pixel' if args.full_mesh else f'at most {args.max_vertices:,} vertices'}", flush=True)
    for path in skipped:
        print(f"{PROG}: skipped {path.name}: not an image file ({path.suffix or 'no extension'})", flush=True)

    failed: list[tuple[str, str]] = []
    stems: dict[str, str] = {}
    total, start = len(images), time.perf_counter()
    for index, path in enumerate(images, 1):
        if STOP.requested:
            raise KeyboardInterrupt
        began = time.perf_counter()
        label = f"[{index}/{total}] {path.name}"
        try:
            if path.stem in stems:
                raise ValueError(f"its outputs would overwrite those of {stems[path.stem]} (same name "
                                 f"'{path.stem}'): rename one of them")
            result, chosen, note = reconstruct_file(path, args)
            step = 1 if args.full_mesh else shadecut.vertex_step(result.mask, args.max_vertices)
            write_outputs(output_paths(args.out_dir, path.stem), result, step)
        except shadecut.Cancelled:
            raise KeyboardInterrupt from None
        except Exception as error:  # noqa: BLE001  (one bad file must not stop the others)
            kind = "" if isinstance(error, (OSError, ValueError)) else f"{type(error).__name__}: "
            message = "; ".join(line.strip() for line in str(error).removeprefix("shadecut: ").splitlines()
                                if line.strip()) or "no message"
            failed.append((path.name, f"{kind}{message}"))
            print(f"{label}: error: {kind}{message}", file=sys.stderr, flush=True)
            continue
        stems[path.stem] = path.name
        light = ", ".join(f"{value:.3f}" for value in result.light)
        height, width = result.mask.shape
        vertices = np.count_nonzero(result.mask[::step, ::step])
        print(f"{label}: {time.perf_counter() - began:.1f} s, {chosen}, light found ({light}), albedo "
              f"{result.albedo:.3f}, {width} x {height}{note} -> {path.stem}_height.exr, {path.stem}_normal.png, "
              f"{path.stem}.ply ({vertices:,} vertices, one every {step} px)", flush=True)

    done = total - len(failed)
    print(f"{PROG}: {done} of {total} image(s) done in {time.perf_counter() - start:.1f} s"
          + (f"; {len(failed)} failed:" if failed else ""), flush=True)
    for name, message in failed:
        print(f"  {name}: {message}", file=sys.stderr, flush=True)
    return 1 if failed else 0


def main(argv: list[str]) -> int:
    """Runs the batch with the arguments that follow "--" on Blender's command line."""
    try:
        args = parse_args(argv)
        with STOP.installed():  # Ctrl+C is seen by the reconstruction's progress callback
            return run(args)
    except UsageError as error:
        print(f"{PROG}: error: {error}", file=sys.stderr, flush=True)
        return 2
    except SystemExit as exit_:  # --help
        return int(exit_.code or 0)
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted (Ctrl+C): the run is stopped; the images done so far are written in full",
              file=sys.stderr, flush=True)
        return 130


if __name__ == "__main__":
    if "--" in sys.argv:
        arguments = sys.argv[sys.argv.index("--") + 1:]
    elif "bpy" in sys.modules:  # blender -P batch.py without "--": no arguments of ours
        arguments = []
    else:  # python3 batch.py IN_DIR OUT_DIR
        arguments = sys.argv[1:]
    sys.exit(main(arguments))
