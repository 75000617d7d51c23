"""Writing a user's file so that it is either the old file or the whole new one, never half of each.

Every writer of files a user keeps (batch.py's outputs, eval.py's results and figures, the dataset's
samples and manifest) writes through :func:`replacing`: the data goes to a temporary file beside the
target, named uniquely for this process and call, and is renamed over the target only once it is
complete. A full disk, a crash or Ctrl+C leave the previous file as it was, and two runs writing
into one folder never share a temporary file. :func:`check_writable` tries an output folder with
real bytes before any work. No ``bpy`` here.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import shutil
import tempfile
from pathlib import Path
from typing import Iterator


def temporary_name(path: str | os.PathLike) -> Path:
    """A hidden name beside ``path``, unique to this process and call, that keeps its extension
    (the image and mesh writers choose the format by it)."""
    path = Path(path)
    return path.with_name(f".{path.stem}.{os.getpid()}-{secrets.token_hex(4)}.partial{path.suffix}")


def remove_leftovers(path: str | os.PathLike) -> None:
    """Deletes the temporary files (or folders) beside ``path`` that a killed process left: those named
    by :func:`temporary_name` for a process that no longer runs, and the one name every process used
    before (``.<stem>.partial<suffix>``). A running process's temporary file is left alone."""
    path = Path(path)
    pattern = re.compile(re.escape(f".{path.stem}.") + r"(?:(\d+)-[0-9a-f]{8}\.)?partial" + re.escape(path.suffix))
    with contextlib.suppress(OSError):
        for candidate in path.parent.iterdir():
            match = pattern.fullmatch(candidate.name)
            if match and (match.group(1) is None or not _running(int(match.group(1)))):
                if candidate.is_dir() and not candidate.is_symlink():
                    shutil.rmtree(candidate, ignore_errors=True)
                else:
                    with contextlib.suppress(OSError):
                        candidate.unlink()


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: it runs
        return True
    return True


@contextlib.contextmanager
def replacing(path: str | os.PathLike) -> Iterator[Path]:
    """Yields the temporary path to write instead of ``path``; renames it over ``path`` when the block
    ends normally, deletes it when the block raises (the exception goes on)."""
    temporary = temporary_name(path)
    try:
        yield temporary
        os.replace(temporary, path)
    finally:
        with contextlib.suppress(OSError):
            temporary.unlink()


def write_text(path: str | os.PathLike, text: str) -> None:
    """Writes ``text`` (UTF-8) to ``path`` through :func:`replacing`, flushed to the disk before the
    rename so that a crash right after cannot leave an empty file under the name."""
    with replacing(path) as temporary, open(temporary, "w", encoding="utf-8", newline="") as stream:
        stream.write(text)
        stream.flush()
        os.fsync(stream.fileno())


# check_writable's test write: about what one figure or sample file takes.
PROBE_BYTES = 1 << 16


def check_writable(folder: str | os.PathLike) -> Path:
    """Creates ``folder`` (and its parents) and writes real bytes there, flushed to the disk, before any
    work: permissions, read-only mounts and full disks raise OSError here (an empty file is created
    even on a full disk). Returns the folder."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryFile(dir=folder) as probe:
        probe.write(bytes(PROBE_BYTES))
        probe.flush()
        os.fsync(probe.fileno())
    return folder
