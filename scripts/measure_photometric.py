"""Photometric stereo on DiLiGenT (issue 45): the C++ core's photometric_stereo + choose_candidates
against plain least squares, with four, eight and two of the benchmark's photographs.

Run: /usr/bin/python3 scripts/measure_photometric.py [BUILD_DIR] [DILIGENT_FOLDER]
(BUILD_DIR defaults to build/, DILIGENT_FOLDER to ../shared/data/diligent). The measured normals
(Normal_gt.mat, zlib-compressed MATLAB, read with scipy) are written as raw float32 copies to a
temporary folder, outside the repository, for tests/cpp/photometric/test_diligent_photometric.cpp,
which this script then runs; its table rows are printed as they come. Nothing is tuned here: the
thresholds are PhotometricStereoParams' defaults.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy.io

REPO = Path(__file__).resolve().parents[1]
OBJECTS = ("ball", "cat", "reading")


def write_raw_normals(diligent: Path, folder: Path) -> None:
    """<object>.f32: int32 rows, int32 cols, then rows x cols x 3 float32 (x, y, z), row-major."""
    for name in OBJECTS:
        normals = scipy.io.loadmat(diligent / f"{name}PNG" / "Normal_gt.mat")["Normal_gt"].astype(np.float32)
        with open(folder / f"{name}.f32", "wb") as file:
            np.array(normals.shape[:2], dtype=np.int32).tofile(file)
            np.ascontiguousarray(normals).tofile(file)


def main() -> int:
    build = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "build"
    diligent = Path(sys.argv[2]) if len(sys.argv) > 2 else REPO.parent / "shared" / "data" / "diligent"
    tests = build / "tests" / "shadecut_tests"
    with tempfile.TemporaryDirectory() as folder:
        write_raw_normals(diligent, Path(folder))
        env = dict(os.environ, SHADECUT_DILIGENT=str(diligent), SHADECUT_DILIGENT_NORMALS=folder)
        print("| object  | photographs                      | plain | ours  | >= 3 lit | 2 lit |")
        return subprocess.run([str(tests), "--gtest_filter=DiLiGenTPhotometric.*"], env=env).returncode


if __name__ == "__main__":
    sys.exit(main())
