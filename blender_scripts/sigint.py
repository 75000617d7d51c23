"""One SIGINT handler for a script's run, for the headless scripts (make_dataset.py, batch.py).

Blender in background mode has its own C handler for Ctrl+C, which cancels a render and lets the
script go on; Python's signal module cannot give it back, since it sees no Python handler. So the C
handler is saved with sigaction and restored afterwards.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal


@contextlib.contextmanager
def handling_sigint(handler):
    """Runs the body with ``handler`` for SIGINT, and restores the previous one, Python's or C's.
    Where no handler can be set (not the main thread, no sigaction), the body runs as it is."""
    try:
        libc = ctypes.CDLL(None) if os.name == "posix" else None
        saved = ctypes.create_string_buffer(512)  # a struct sigaction, opaque: smaller than this everywhere
        if libc is not None and libc.sigaction(signal.SIGINT, None, saved) != 0:
            libc = None
        previous = signal.signal(signal.SIGINT, handler)
    except (ValueError, OSError, AttributeError):  # not the main thread, or no sigaction
        yield
        return
    try:
        yield
    finally:
        if previous is not None:  # a handler set from Python
            signal.signal(signal.SIGINT, previous)
        else:  # one set in C (Blender's): back to it, as it was
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            if libc is not None:
                libc.sigaction(signal.SIGINT, saved, None)
