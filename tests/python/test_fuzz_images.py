"""Mutated image files never crash load_image or the command-line tool: each is read in a process of
its own, which must end with success or a clean error (OSError / ValueError, exit 2), never a signal
or another exception. The mutations are drawn from a fixed seed, so every run reads the same files.
Truncated files, which the decoders used to fill with grey or black rows, and paths that are not
regular files are refused by name."""

import os
import struct
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


def strip_tiff(pixels: np.ndarray, rows_per_strip: int) -> bytes:
    """An uncompressed 8-bit grey TIFF with its directory before its strips, as many writers lay it
    out: cut in its last strip, its header still reads whole and only the pixels are missing."""
    height, width = pixels.shape
    strips = -(-height // rows_per_strip)
    entries = 9
    arrays = 8 + 2 + entries * 12 + 4
    first_strip = arrays + 8 * strips
    sizes = [min(rows_per_strip, height - k * rows_per_strip) * width for k in range(strips)]
    offsets = [first_strip + k * rows_per_strip * width for k in range(strips)]
    long, short = 4, 3
    tags = [(256, long, 1, width), (257, long, 1, height), (258, short, 1, 8), (259, short, 1, 1),
            (262, short, 1, 1), (273, long, strips, arrays), (277, short, 1, 1), (278, long, 1, rows_per_strip),
            (279, long, strips, arrays + 4 * strips)]
    header = b"II*\0" + struct.pack("<I", 8) + struct.pack("<H", entries)
    header += b"".join(struct.pack("<HHII", *tag) for tag in tags) + struct.pack("<I", 0)
    header += struct.pack(f"<{strips}I", *offsets) + struct.pack(f"<{strips}I", *sizes)
    return header + pixels.astype(np.uint8).tobytes()


@pytest.fixture(scope="module")
def truncated_files(tmp_path_factory):
    """A 128 x 96 textured image in each format, cut: JPEG, PNG and EXR at 60 %, the TIFF in its last
    strip."""
    folder = tmp_path_factory.mktemp("truncated")
    image = np.random.default_rng(7).random((96, 128), dtype=np.float32) * 0.5 + 0.25
    import OpenImageIO as oiio  # a JPEG, which save_image does not write
    out = oiio.ImageOutput.create(str(folder / "whole.jpg"))
    out.open(str(folder / "whole.jpg"), oiio.ImageSpec(128, 96, 3, oiio.UINT8))
    out.write_image((np.dstack([image] * 3) * 255).astype(np.uint8))
    out.close()
    shadecut.save_image(folder / "whole.png", image)
    shadecut.save_image(folder / "whole.exr", image)
    tiff = strip_tiff(image * 255, rows_per_strip=8)
    (folder / "whole.tif").write_bytes(tiff)
    cut = {}
    for suffix in (".jpg", ".png", ".exr", ".tif"):
        whole = (folder / f"whole{suffix}").read_bytes()
        shadecut.load_image(folder / f"whole{suffix}")  # each reads whole before it is cut
        length = len(whole) - 4 * 128 if suffix == ".tif" else int(len(whole) * 0.6)
        cut[suffix] = folder / f"cut{suffix}"
        cut[suffix].write_bytes(whole[:length])
    return cut


@pytest.mark.parametrize("suffix", [".jpg", ".tif", ".png", ".exr"])
def test_a_truncated_file_is_refused_by_name_in_python_and_in_the_cli(truncated_files, tmp_path, suffix):
    path = truncated_files[suffix]
    with pytest.raises(OSError, match=f'cannot read image "{path}"'):
        shadecut.load_image(path)
    cli = subprocess.run([str(CLI), str(path), "--light", "1,0,1", "--quiet", "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, timeout=60)
    assert cli.returncode == 2 and f'shadecut: cannot read image "{path}"' in cli.stderr, cli.stderr
    assert not (tmp_path / "out").exists()


def test_a_named_pipe_or_a_device_is_refused_by_the_cli_without_reading_it(tmp_path):
    """The tool blocked forever on a FIFO and spun on /dev/zero."""
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    for path, kind in ((fifo, "a named pipe (FIFO)"), ("/dev/zero", "a character device")):
        cli = subprocess.run([str(CLI), str(path), "--light", "1,0,1", "--quiet", "--out", str(tmp_path / "out")],
                             capture_output=True, text=True, timeout=30)
        assert cli.returncode == 2, cli.stderr
        assert f'cannot read image "{path}": it is {kind}, not a regular file' in cli.stderr
