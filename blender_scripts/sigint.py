"""Ctrl+C for the headless scripts (make_dataset.py, batch.py): a SIGINT handler for a run
(:func:`handling_sigint`) and the request to stop that it records (:class:`StopRequest`).

Blender in background mode has its own C handler for Ctrl+C, which cancels a render and lets the
script go on; Python's signal module cannot give it back, since it sees no Python handler. So the C
handler is saved with sigaction and restored afterwards.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys


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


class StopRequest:
    """Ctrl+C as a request to stop a script's run, shared by the scripts' handlers.

    While ``deferred`` the handler only records the request (the run stops at its next check) and
    says so once, with ``notice``; otherwise it raises KeyboardInterrupt at once. A script whose
    work can always be stopped at a check (a progress callback) defers throughout; one that cannot
    stop inside a step (a render) defers only in that step (:meth:`deferring`).
    """

    def __init__(self, notice: str, *, always_deferred: bool):
        self.notice = notice
        self.always_deferred = always_deferred
        self.requested = False
        self.deferred = always_deferred

    def handle(self, signum, frame) -> None:
        first = not self.requested
        self.requested = True
        if not self.deferred:
            raise KeyboardInterrupt
        if first:
            print(self.notice, file=sys.stderr, flush=True)

    @contextlib.contextmanager
    def installed(self):
        """The body runs with :meth:`handle` for SIGINT and a fresh request (see handling_sigint)."""
        self.requested, self.deferred = False, self.always_deferred
        with handling_sigint(self.handle):
            yield

    @contextlib.contextmanager
    def deferring(self):
        """Ctrl+C inside is remembered, and raises KeyboardInterrupt on leaving (unless an error does)."""
        outer = self.deferred
        self.deferred = True
        try:
            yield
        finally:
            self.deferred = outer
        if self.requested and not outer:
            raise KeyboardInterrupt
