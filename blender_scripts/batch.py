"""Headless batch: every image of a folder reconstructed, its height, normal map and mesh written.

    blender -b -P blender_scripts/batch.py -- IN_DIR OUT_DIR [--scene auto|object|relief] [--max-size N]
                                              [--max-vertices N | --full-mesh]
    python3 blender_scripts/batch.py IN_DIR OUT_DIR [...]       (works without Blender too)

Every file of IN_DIR with an image extension (.png .jpg .jpeg .tif .tiff .exr .hdr .bmp .tga, any
case) is read by ``shadecut.load_image`` (its alpha, if any, is the mask),
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

A subfolder of IN_DIR is a set of photographs of one subject (a camera on a tripod, one lamp moved
around it): its images, in name order, are reconstructed together by ``shadecut.reconstruct``, one
light per photograph, into <folder>_height.exr, <folder>_normal.png, <folder>.ply and
<folder>_albedo.png (the de-lit colour, result.albedo_colour, or the grey albedo_map when a
photograph is grey: a 16-bit sRGB PNG, alpha = mask, shadecut.save_image). The mask is where every
photograph is opaque. The lights come from the folder's lights.txt, one line per photograph, its
file name then x y z (toward the light, camera frame, any length) or a side of the image
(shadecut.LIGHT_SIDES, at the library's guessed slant, which scales the depth); blank lines and
lines starting with # are left out:

    rug/lights.txt:   rug_1.jpg above
                      rug_2.jpg 0.7 0 0.7

else from each file name's last _-separated word when it is such a side (rug/rug_above.jpg,
rug/rug_left.jpg, ...); a set of four or more photographs that names none has them estimated from
the photographs (lit from around the subject at one slant, the library's default hint). A set with
some lights given and others not, or with fewer than four and none given, or with one photograph,
gets an error line saying what is missing. Subfolders without an image, hidden ones and
OUT_DIR are skipped; a set's own subfolders are not entered.

The subject (the add-on's Subject) is, by default (--scene auto), chosen for each image from its
alpha: an image whose alpha leaves part of it transparent is an object cut out from its background
(Object); one without alpha, or opaque everywhere, fills the frame and is read as a relief (a wall,
a coin, bark, a texture: Relief, which keeps its carrier flat). An object photographed on a plain
background without alpha needs --scene object; --scene relief or object sets every image's subject.
A set is judged alike by its photographs' alphas. --max-size N shrinks a larger image by a whole
factor until neither side exceeds N pixels, as the add-on's Max size does (0 = full size, the
default here). Each image's (or set's) outputs are written under temporary names of this run's own
and then renamed, so a file named like an output is always complete, and two runs into one OUT_DIR
never take each other's temporary files.

One progress line per image or set, counted together (index/total, name, seconds, the subject and
why, the light found or where the lights came from, the mesh's density); a file or set that cannot
be read or reconstructed gets an error line naming it, and the others are still done. Files without
an image extension are listed as skipped.

Exit code: 0 when every image and set was done; 1 when one failed (each named, and listed again at
the end); 2 for bad arguments (IN_DIR missing or not a folder, no image file in it nor in a
subfolder, a folder that cannot be listed, OUT_DIR not creatable, a negative --max-size, an output
that would replace a file of IN_DIR or of a set, as OUT_DIR = IN_DIR does for x.png beside
x_normal.png or x.ply), with a message and no traceback: nothing is written. Ctrl+C (SIGINT) stops
the run: the image or set under way is abandoned (nothing of it is written), the finished ones are
kept, exit code 130.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import sys
import time
from dataclasses import dataclass
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
LIGHTS_FILE = "lights.txt"  # a set's lights, when its file names do not give them
SIDES = ", ".join(shadecut.LIGHT_SIDES)
PROG = "batch.py"
AUTO = "auto"


def parse_args(argv: list[str]) -> argparse.Namespace:
    parser = Parser(prog="blender -b -P blender_scripts/batch.py --",
                     description="Reconstructs every image of IN_DIR into OUT_DIR: <stem>_height.exr (the heights "
                                 "in pixel units as a grey float image, alpha = mask, which Blender opens as a "
                                 "height image), <stem>_normal.png (a tangent-space normal map) and <stem>.ply "
                                 "(the mesh); a subfolder's photographs of one subject, each under its own light, "
                                 "give one set of these and <folder>_albedo.png. More in the script's docstring "
                                 "and docs/blender_addon.md.")
    parser.add_argument("in_dir", type=Path, metavar="IN_DIR",
                        help="folder of images (a subfolder: the photographs of one subject, each under its own light)")
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


@dataclass
class PhotographSet:
    """A subfolder of IN_DIR: the photographs of one subject (sorted by name), named like an image by
    ``name`` (its progress line) and ``stem`` (its outputs)."""

    folder: Path
    photographs: list[Path]

    @property
    def name(self) -> str:
        return f"{self.folder.name}/"

    @property
    def stem(self) -> str:
        return self.folder.name


def is_image(path: Path) -> bool:
    return path.suffix.lower() in IMAGE_EXTENSIONS


def _files(folder: Path, what: str) -> list[Path]:
    """The files of ``folder`` sorted by name (hidden ones too: the caller decides)."""
    try:
        return sorted((path for path in folder.iterdir() if path.is_file()), key=lambda path: path.name)
    except OSError as error:
        raise UsageError(f"cannot list {what} {folder}: {error.strerror or error}") from error


def _folders(in_dir: Path) -> list[Path]:
    """The subfolders of ``in_dir`` sorted by name, hidden ones left out."""
    try:
        return sorted((path for path in in_dir.iterdir() if path.is_dir() and not path.name.startswith(".")),
                      key=lambda path: path.name)
    except OSError as error:
        raise UsageError(f"cannot list IN_DIR {in_dir}: {error.strerror or error}") from error


def list_inputs(in_dir: Path, out_dir: Path) -> tuple[list, list[str], list[Path]]:
    """What to reconstruct, sorted by name: the image files of ``in_dir`` and its subfolders that hold
    images (each a PhotographSet); what is skipped, each with why; and every file found (their
    outputs must not replace any)."""
    if not in_dir.exists():
        raise UsageError(f"IN_DIR {in_dir} does not exist")
    if not in_dir.is_dir():
        raise UsageError(f"IN_DIR {in_dir} is not a folder")
    files = _files(in_dir, "IN_DIR")
    items: list = [path for path in files if is_image(path)]
    skipped = [f"{path.name}: not an image file ({path.suffix or 'no extension'})"
               for path in files if not is_image(path) and not path.name.startswith(".")]
    for folder in _folders(in_dir):
        if folder.resolve() == out_dir.resolve():
            skipped.append(f"{folder.name}/: it is OUT_DIR")
            continue
        found = [path for path in _files(folder, "the folder") if not path.name.startswith(".")]
        photographs = [path for path in found if is_image(path)]
        files += found
        skipped += [f"{folder.name}/{path.name}: not an image file ({path.suffix or 'no extension'})"
                    for path in found if not is_image(path) and path.name != LIGHTS_FILE]
        if photographs:
            items.append(PhotographSet(folder, photographs))
        else:
            skipped.append(f"{folder.name}/: no image file in it")
    if not items:
        raise UsageError(f"IN_DIR {in_dir} holds no image file ({' '.join(IMAGE_EXTENSIONS)}) nor a subfolder of them")
    return sorted(items, key=lambda item: item.name), skipped, files


def prepare_output(out_dir: Path) -> None:
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise UsageError(f"cannot create OUT_DIR {out_dir}: {error.strerror or error}") from error
    if not os.access(out_dir, os.W_OK | os.X_OK):
        raise UsageError(f"OUT_DIR {out_dir} is not writable")


def output_paths(out_dir: Path, stem: str, albedo: bool = False) -> dict[str, Path]:
    """The files of one image, or with ``albedo`` of one set (the mesh last, as its line names them)."""
    paths = {"height": out_dir / f"{stem}_height.exr", "normal": out_dir / f"{stem}_normal.png"}
    if albedo:
        paths["albedo"] = out_dir / f"{stem}_albedo.png"
    return paths | {"mesh": out_dir / f"{stem}.ply"}


def item_outputs(out_dir: Path, item) -> dict[str, Path]:
    return output_paths(out_dir, item.stem, albedo=isinstance(item, PhotographSet))


def check_inputs_kept(files: list[Path], items: list, in_dir: Path, out_dir: Path) -> None:
    """UsageError when an output of an image or set would replace a file of IN_DIR or of a set (``files``;
    OUT_DIR = IN_DIR, x.png beside x_normal.png or beside x.ply): an image would be overwritten before
    it is read and the overwritten image reconstructed, any other file lost."""
    kept = {path.resolve(): path.relative_to(in_dir).as_posix() for path in files}
    for item in items:
        replaced = [kept[resolved] for resolved in (path.resolve() for path in item_outputs(out_dir, item).values())
                    if resolved in kept]
        if replaced:
            raise UsageError(f"the outputs of {item.name} would replace {', '.join(replaced)} in {out_dir}: "
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
    """The files of one reconstruction, each written under a temporary name of its own (two runs into
    one folder never share one) and renamed over its name only when all are complete; the mesh
    samples every ``mesh_step`` pixels; a set's de-lit colour (albedo) as a 16-bit sRGB PNG, alpha =
    mask (shadecut.save_image)."""
    with contextlib.ExitStack() as stack:
        partial = {key: stack.enter_context(replacing(path)) for key, path in paths.items()}
        shadecut.save_depth(partial["height"], result.depth, result.mask)
        save_normal_map(partial["normal"], result.normals, result.mask)
        if "albedo" in partial:
            albedo = result.albedo_map if result.albedo_colour is None else result.albedo_colour
            shadecut.save_image(partial["albedo"], albedo, result.mask)
        shadecut.save_mesh(partial["mesh"], result.depth, result.mask, mesh_step)


STOP = StopRequest(f"{PROG}: Ctrl+C: stopping (the image or set under way is abandoned)", always_deferred=True)


def _progress(fraction: float, stage: str) -> bool:
    return not STOP.requested  # False: the core stops with shadecut.Cancelled


def subject(has_alpha: bool, mask: np.ndarray, scene: str) -> tuple[str, str]:
    """The subject (a SceneKind name) of an image (or set) with its alpha's ``mask`` for --scene
    ``scene``, and why, for the log."""
    if scene != AUTO:
        return scene, "--scene"
    if has_alpha and not mask.all():
        return "object", "auto: its alpha cuts it out"
    return "relief", "auto: " + ("opaque everywhere" if has_alpha else "no alpha") + ", it fills the frame"


def working_pixels(pixels: np.ndarray, mask: np.ndarray, max_size: int) -> tuple[np.ndarray, np.ndarray, int]:
    """(H, W) intensity or (H, W, 3) colour and its mask shrunk for --max-size as the add-on's Max
    size does (imaging.shrink_factor, imaging.shrink), with the factor."""
    try:
        factor = imaging.shrink_factor(*mask.shape, max_size)
    except ValueError as error:
        raise ValueError(f"--max-size {max_size}: {error}") from error
    if pixels.ndim == 2:
        return (*imaging.shrink(pixels, mask, factor), factor)
    channels = [imaging.shrink(np.ascontiguousarray(pixels[..., k]), mask, factor) for k in range(3)]
    return np.dstack([channel for channel, _ in channels]), channels[0][1], factor


def shrunk_note(factor: int, mask: np.ndarray) -> str:
    """What the log says of the working size: nothing at full size."""
    height, width = mask.shape
    return f" (shrunk by {factor} from {width} x {height})" if factor > 1 else ""


def reconstruct_file(path: Path, args: argparse.Namespace) -> tuple[object, str, str]:
    """The reconstruction of one image file, what its line says of it (subject, light, albedo) and a
    note on its working size ("" at full size)."""
    loaded = shadecut.load_image(path)
    scene, reason = subject(loaded.has_alpha, loaded.mask, args.scene)
    image, mask, factor = working_pixels(loaded.image, loaded.mask, args.max_size)
    result = shadecut.reconstruct(image, mask=mask, progress=_progress, scene=scene)
    light = ", ".join(f"{value:.3f}" for value in result.light)
    return (result, f"subject {scene} ({reason}), light found ({light}), albedo {result.albedo:.3f}",
            shrunk_note(factor, loaded.mask))


def side_in_name(path: Path) -> str | None:
    """The side of the image (shadecut.LIGHT_SIDES) the file name's last _-separated word names:
    rug_above.jpg -> "above"; None for another word."""
    word = path.stem.rsplit("_", 1)[-1].lower()
    return word if word in shadecut.LIGHT_SIDES else None


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def listed_light(line: str) -> tuple[str, np.ndarray]:
    """A line of lights.txt: a file name, then its light as x y z (toward the light, camera frame:
    x right, y up, z toward the viewer) or a side of the image."""
    words = line.rsplit(None, 3)
    if len(words) == 4 and all(_is_number(word) for word in words[1:]):
        return words[0], shadecut.light_direction([float(word) for word in words[1:]])
    words = line.rsplit(None, 1)
    if len(words) == 2 and words[1].lower() in shadecut.LIGHT_SIDES:
        return words[0], shadecut.light_from_side(words[1].lower())
    raise ValueError(f"'{line}' is neither 'file x y z' nor 'file side' (a side: {SIDES})")


def listed_lights(path: Path) -> dict[str, np.ndarray]:
    """The lights of a lights.txt by file name, one line each (listed_light); blank lines and lines
    that start with # are left out."""
    lights: dict[str, np.ndarray] = {}
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            name, light = listed_light(line.strip())
        except ValueError as error:
            raise ValueError(f"{LIGHTS_FILE} line {number}: {str(error).removeprefix('shadecut: ')}") from error
        if name in lights:
            raise ValueError(f"{LIGHTS_FILE} line {number}: {name} is listed twice")
        lights[name] = light
    return lights


def set_lights(photo_set: PhotographSet) -> tuple[list[np.ndarray] | None, str]:
    """One light per photograph of the set, in order, and where they come from: its lights.txt, else
    the side each file name ends with, else (none named) None: estimated from the photographs.
    ValueError saying what is missing."""
    names = [path.name for path in photo_set.photographs]
    listed = photo_set.folder / LIGHTS_FILE
    if listed.is_file():
        lights = listed_lights(listed)
        strangers = [name for name in lights if name not in names]
        if strangers:
            raise ValueError(f"{LIGHTS_FILE} lists {', '.join(strangers)}, not an image of the folder")
        missing = [name for name in names if name not in lights]
        if missing:
            raise ValueError(f"no light for {', '.join(missing)} in {LIGHTS_FILE}: add a line "
                             f"'{missing[0]} x y z' or '{missing[0]} <side>' (a side: {SIDES})")
        return [lights[name] for name in names], LIGHTS_FILE
    sides = [side_in_name(path) for path in photo_set.photographs]
    missing = [path for path, side in zip(photo_set.photographs, sides) if side is None]
    if len(missing) == len(names):
        return None, "the photographs (estimated)"  # the library refuses fewer than it can read them from
    if missing:
        raise ValueError(f"no light for {', '.join(path.name for path in missing)}: name it "
                         f"{missing[0].stem}_<side>{missing[0].suffix} (a side: {SIDES}) or list it in {LIGHTS_FILE}")
    return [shadecut.light_from_side(side) for side in sides], "the names"


@contextlib.contextmanager
def photographs_named(photographs: list[Path]):
    """The library's ValueErrors with each "photograph N" they speak of followed by its file's name:
    it counts the photographs of the list it was given, here the set's in name order."""
    def named(match: re.Match) -> str:
        number = int(match.group(1))
        if not 0 < number <= len(photographs):
            return match.group(0)
        return f"{match.group(0)} ({photographs[number - 1].name})"

    try:
        yield
    except ValueError as error:
        raise ValueError(re.sub(r"\bphotograph (\d+)\b", named, str(error))) from error


def reconstruct_set(photo_set: PhotographSet, args: argparse.Namespace) -> tuple[object, str, str]:
    """The reconstruction of a set's photographs under their lights (set_lights), the mask opaque in
    every one, in colour when all are; what its line says of it and a note on its working size."""
    count = len(photo_set.photographs)
    if count < 2:
        raise ValueError(f"one photograph ({photo_set.photographs[0].name}): a set needs two or more of one "
                         "view, each under another light (a single image goes in IN_DIR itself)")
    lights, origin = set_lights(photo_set)
    loaded = [shadecut.load_image(path) for path in photo_set.photographs]
    with photographs_named(photo_set.photographs):
        if len({photograph.mask.shape for photograph in loaded}) > 1:  # reconstruct() refuses them, saying which
            shadecut.reconstruct([photograph.image for photograph in loaded], lights)
        mask = np.logical_and.reduce([photograph.mask for photograph in loaded])
        scene, reason = subject(any(photograph.has_alpha for photograph in loaded), mask, args.scene)
        in_colour = all(photograph.colour is not None for photograph in loaded)
        working = [working_pixels(photograph.colour if in_colour else photograph.image, mask, args.max_size)
                   for photograph in loaded]
        result = shadecut.reconstruct([pixels for pixels, _, _ in working], lights, working[0][1],
                                      progress=_progress, scene=scene)
    return (result, f"{count} photographs, subject {scene} ({reason}), lights from {origin}, "
                    f"albedo {result.albedo:.3f}", shrunk_note(working[0][2], mask))


def process(item, args: argparse.Namespace, stems: dict[str, str]) -> str:
    """Reconstructs one image file or set and writes its files; what its progress line says after its name."""
    began = time.perf_counter()
    if item.stem in stems:
        raise ValueError(f"its outputs would overwrite those of {stems[item.stem]} (same name '{item.stem}'): "
                         "rename one of them")
    reconstruct = reconstruct_set if isinstance(item, PhotographSet) else reconstruct_file
    result, said, note = reconstruct(item, args)
    step = 1 if args.full_mesh else shadecut.vertex_step(result.mask, args.max_vertices)
    paths = item_outputs(args.out_dir, item)
    write_outputs(paths, result, step)
    stems[item.stem] = item.name
    height, width = result.mask.shape
    vertices = np.count_nonzero(result.mask[::step, ::step])
    return (f"{time.perf_counter() - began:.1f} s, {said}, {width} x {height}{note} -> "
            f"{', '.join(path.name for path in paths.values())} ({vertices:,} vertices, one every {step} px)")


def error_text(error: Exception) -> str:
    """An error as one line: its type named unless it is bad input or a file's problem."""
    kind = "" if isinstance(error, (OSError, ValueError)) else f"{type(error).__name__}: "
    message = "; ".join(line.strip() for line in str(error).removeprefix("shadecut: ").splitlines()
                        if line.strip()) or "no message"
    return f"{kind}{message}"


def announce(args: argparse.Namespace, items: list, skipped: list[str]) -> str:
    """Prints what the run will do and what it skips; returns what it counts ("image(s)" [and sets])."""
    sets = sum(isinstance(item, PhotographSet) for item in items)
    counted = "image(s)" + (" and set(s)" if sets else "")
    scenes = list(shadecut.SceneKind.__members__) if args.scene == AUTO else [args.scene]
    lights = "/".join(shadecut.ReconstructOptions(scene=scene).light_method_used().name for scene in scenes)
    print(f"{PROG}: {len(items) - sets} image(s){f' and {sets} set(s) of photographs' if sets else ''} in "
          f"{args.in_dir} -> {args.out_dir}; scene {args.scene}"
          f"{' (relief without transparent pixels, else object)' if args.scene == AUTO else ''}, "
          f"method {shadecut.ReconstructOptions().method.name}, light estimated ({lights})"
          f"{'; a set: its lights given' if sets else ''}, max size {args.max_size or 'full'}, mesh "
          f"{'every pixel' if args.full_mesh else f'at most {args.max_vertices:,} vertices'}", flush=True)
    for line in skipped:
        print(f"{PROG}: skipped {line}", flush=True)
    return counted


def run(args: argparse.Namespace) -> int:
    items, skipped, files = list_inputs(args.in_dir, args.out_dir)
    check_inputs_kept(files, items, args.in_dir, args.out_dir)
    prepare_output(args.out_dir)
    counted = announce(args, items, skipped)
    failed: list[tuple[str, str]] = []
    stems: dict[str, str] = {}
    total, start = len(items), time.perf_counter()
    for index, item in enumerate(items, 1):
        if STOP.requested:
            raise KeyboardInterrupt
        label = f"[{index}/{total}] {item.name}"
        try:
            line = process(item, args, stems)
        except shadecut.Cancelled:
            raise KeyboardInterrupt from None
        except Exception as error:  # noqa: BLE001  (one bad file or set must not stop the others)
            failed.append((item.name, error_text(error)))
            print(f"{label}: error: {failed[-1][1]}", file=sys.stderr, flush=True)
            continue
        print(f"{label}: {line}", flush=True)

    done = total - len(failed)
    print(f"{PROG}: {done} of {total} {counted} done in {time.perf_counter() - start:.1f} s"
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
        print(f"{PROG}: interrupted (Ctrl+C): the run is stopped; the images and sets done so far are written in full",
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
