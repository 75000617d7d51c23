"""What kind of file a path names, for the readers that must refuse anything but a regular file.

A named pipe blocks a reader forever (until something writes to it) and a device such as /dev/zero
feeds it bytes without end: neither is an image. Used by ``shadecut.load_image`` and by the add-on's
file path (which Blender would read), so both refuse the same paths. No ``bpy`` here.
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
