"""The helper modules of blender_scripts/ that run without Blender: Ctrl+C handling (sigint.py)."""

import os
import signal
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "blender_scripts"))
from sigint import StopRequest  # noqa: E402


def _deliver_sigint():
    os.kill(os.getpid(), signal.SIGINT)
    for _ in range(1000):  # the handler runs between bytecodes
        sum(range(100))


def test_a_deferred_request_is_recorded_and_said_once(capsys):
    before = signal.getsignal(signal.SIGINT)
    stop = StopRequest("script: Ctrl+C: stopping", always_deferred=True)
    with stop.installed():
        _deliver_sigint()
        _deliver_sigint()
        assert stop.requested
    assert capsys.readouterr().err.count("script: Ctrl+C: stopping") == 1
    assert signal.getsignal(signal.SIGINT) == before
    with stop.installed():  # a new run starts without the old request
        assert not stop.requested


def test_an_undeferred_request_stops_at_once_and_a_deferred_step_finishes_first():
    stop = StopRequest("script: Ctrl+C", always_deferred=False)
    with pytest.raises(KeyboardInterrupt), stop.installed():
        _deliver_sigint()
    finished = []
    with pytest.raises(KeyboardInterrupt), stop.installed(), stop.deferring():
        _deliver_sigint()
        finished.append(True)
    assert finished == [True]
