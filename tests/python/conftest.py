from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
MOZART_PATH = REPO / "data" / "mozart" / "moz256.depth"


@pytest.fixture(scope="session")
def mozart_path() -> Path:
    return MOZART_PATH
