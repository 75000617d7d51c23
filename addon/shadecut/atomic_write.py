"""Writing a user's file so that it is either the old file or the whole new one, never half of each.

Every writer of files a user keeps (batch.py's outputs, eval.py's results and figures, the dataset's
samples and manifest) writes through :func:`replacing`: the data goes to a temporary file beside the
target, named uniquely for this process and call, and is renamed over the target only once it is
complete. A full disk, a crash or Ctrl+C leave the previous file as it was, and two runs writing
into one folder never share a temporary file. No ``bpy`` here.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path
from typing import Iterator


def temporary_name(path: str | os.PathLike) -> Path:
    """A hidden name beside ``path``, unique to this process and call, that keeps its extension
    (the image and mesh writers choose the format by it)."""
    path = Path(path)
    return path.with_name(f".{path.stem}.{os.getpid()}-{secrets.token_hex(4)}.partial{path.suffix}")


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
