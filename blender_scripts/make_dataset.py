"""Synthetic Lambertian dataset generator: Cycles renders of a catalogue of shapes with exact ground truth.

    blender -b -P blender_scripts/make_dataset.py -- --out DIR [--shapes sphere,torus,...] [--mesh FILE ...]
        [--lights N | --light X,Y,Z ...] [--slant-min 10] [--slant-max 60] [--size 256] [--albedo 0.8]
        [--noise SIGMA] [--bits 8|16] [--shadows] [--indirect] [--samples N] [--seed S] [--shard I/N]

Every shape gets ``--lights`` lights drawn with the seed, uniformly over the directions whose slant
(angle from the viewing direction) lies between --slant-min and --slant-max degrees, every tilt; or
the --light directions given (camera frame, x right, y up, z toward the viewer). Each sample is a
folder ``<shape>_<light index>`` in the format of ``shadecut.dataset``; ``manifest.json`` and
``manifest.csv`` list the finished samples. The lights and the noise depend only on --seed and the
shape's name, so the same seed gives the same dataset whatever the shard or the other shapes.

Re-running skips the finished samples (an interrupted sample leaves no folder: samples are written
atomically); a sample counts as finished only when every file it lists reads back whole with the
planned resolution and channels, so one damaged later (truncated by a full disk, a copy cut short)
is rendered again. ``--shard I/N`` (I from 0 to N-1) renders only the samples whose index modulo N is I,
so that processes, machines or a batch scheduler's array jobs share a dataset folder; each shard
refreshes the manifest with what is on disk, and a last run without --shard (everything skipped)
writes the complete one.

Exit code 0 on success, 1 when a render failed, 2 for bad input (unknown shape, unreadable mesh,
light at or below the horizon, a negative seed, a NaN or negative noise, unwritable output folder...),
with a message and no traceback. Ctrl+C (SIGINT) stops the whole run after the render under way: the
finished samples and a manifest listing them are kept, and the exit code is 130.
``dataset_generator.main(argv)`` runs the generator in-process (argv = the arguments after "--") and returns the code.

This file is the command; the generator is dataset_generator.py (also run by eval.py), the shapes,
built-in and read from mesh files, are the catalogue in shapes.py.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # dataset_generator.py

from dataset_generator import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []))
