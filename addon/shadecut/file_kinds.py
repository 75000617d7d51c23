"""What kind of file a path names, for the readers that must refuse anything but a regular file.

A named pipe blocks a reader forever (until something writes to it) and a device such as /dev/zero
feeds it bytes without end: neither is an image. Used by the add-on's file path, which Blender reads,
and by every Python reader of a user's file (a dataset's images and texts, DiLiGenT's files) through
:func:`refuse_special_file`; ``shadecut.load_image`` and the command line read through the C++
``load_image``, which refuses the same paths in the same words. No ``bpy`` here.
"""

from __future__ import annotations

import os
import stat
from typing import Optional

_KINDS = ((stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def special_file_kind(path: str | os.PathLike) -> Optional[str]:
    """What ``path`` is when it exists and is neither a regular file nor a folder ("a named pipe
    (FIFO)", "a character device", ...), else None: a missing file or a folder is the reader's to
    name, as it always did."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):  # missing, unreachable or an impossible name: the reader says which
        return None
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return None
    return next((kind for is_kind, kind in _KINDS if is_kind(mode)), "not a regular file")


def refuse_special_file(path: str | os.PathLike) -> None:
    """OSError, in the C++ reader's words, when ``path`` is a named pipe, a device or a socket: every
    reader of a user's file in Python calls this before opening it (a pipe would block it forever)."""
    kind = special_file_kind(path)
    if kind is not None:
        raise OSError(f'shadecut: cannot read "{os.fspath(path)}": it is {kind}, not a regular file')


def read_text(path: str | os.PathLike) -> str:
    """A text file's contents (UTF-8) through :func:`refuse_special_file`."""
    refuse_special_file(path)
    with open(path, encoding="utf-8") as stream:
        return stream.read()
