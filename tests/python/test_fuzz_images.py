"""Mutated image files never crash load_image or the command-line tool: each is read in a process of
its own, which must end with success or a clean error (OSError / ValueError, exit 2), never a signal
or another exception. The mutations are drawn from a fixed seed, so every run reads the same files."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import shadecut

REPO = Path(__file__).resolve().parents[2]
CLI = REPO / "build" / "native" / "shadecut"
MUTANTS_PER_FORMAT = 12
READ_IN_PYTHON = """
import sys
import shadecut
try:
    shadecut.load_image(sys.argv[1])
except (OSError, ValueError) as error:
    print(error)
    sys.exit(3)
"""


def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    """Flipped bytes, a cut, or a repeated run: what a damaged download or a bad disk gives."""
    data = bytearray(data)
    kind = rng.integers(3)
    if kind == 0:
        for position in rng.integers(0, len(data), size=rng.integers(1, 9)):
            data[position] = int(rng.integers(256))
    elif kind == 1:
        data = data[: int(rng.integers(1, len(data)))]
    else:
        start = int(rng.integers(0, len(data) - 1))
        run = data[start:start + int(rng.integers(1, 64))]
        data[start:start] = run * int(rng.integers(1, 50))
    return bytes(data)


@pytest.fixture(scope="module")
def seeds(tmp_path_factory):
    folder = tmp_path_factory.mktemp("seeds")
    image = np.linspace(0, 1, 24 * 20, dtype=np.float32).reshape(20, 24)
    mask = image > 0.1
    for name in ("seed.png", "seed.exr", "seed.tif"):
        shadecut.save_image(folder / name, image, mask)
    shadecut.save_normals(folder / "seed8.png", shadecut.normals_from_depth(image * 5), mask)
    import OpenImageIO as oiio  # a JPEG, which save_image does not write
    out = oiio.ImageOutput.create(str(folder / "seed.jpg"))
    out.open(str(folder / "seed.jpg"), oiio.ImageSpec(24, 20, 3, oiio.UINT8))
    out.write_image((np.dstack([image] * 3) * 255).astype(np.uint8))
    out.close()
    return sorted(folder.iterdir())


@pytest.mark.parametrize("format_index", range(5))
def test_mutated_files_end_cleanly_in_python_and_in_the_cli(seeds, tmp_path, format_index):
    seed = seeds[format_index]
    rng = np.random.default_rng(1000 + format_index)
    for index in range(MUTANTS_PER_FORMAT):
        path = tmp_path / f"mutant{index}{seed.suffix}"
        path.write_bytes(mutate(seed.read_bytes(), rng))
        python = subprocess.run([sys.executable, "-c", READ_IN_PYTHON, str(path)], capture_output=True, text=True,
                                timeout=60, env={"PYTHONPATH": str(REPO / "addon")})
        assert python.returncode in (0, 3), f"{seed.name} mutant {index}: {python.returncode} {python.stderr[-800:]}"
        cli = subprocess.run([str(CLI), str(path), "--light", "1,0,1", "--quiet", "--out", str(tmp_path / "out")],
                             capture_output=True, text=True, timeout=60)
        assert cli.returncode in (0, 2), f"{seed.name} mutant {index}: CLI {cli.returncode} {cli.stderr[-800:]}"
        if cli.returncode == 2:
            assert "shadecut:" in cli.stderr, cli.stderr  # the library (libpng) may speak first
