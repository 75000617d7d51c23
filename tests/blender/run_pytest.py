"""Runs pytest inside Blender, so the add-on is tested against the real bpy.

    blender -b --factory-startup --python-exit-code 1 -P tests/blender/run_pytest.py -- [pytest args]

Blender's own exit code is pytest's: --python-exit-code only catches uncaught exceptions, so the
result is passed on with sys.exit.
"""

import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "addon"))

args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else [str(Path(__file__).parent)]
sys.exit(int(pytest.main(["-p", "no:cacheprovider", *args])))
