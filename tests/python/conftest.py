from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
MOZART_PATH = REPO / "data" / "mozart" / "moz256.depth"


@pytest.fixture(scope="session")
def mozart_path() -> Path:
    return MOZART_PATH


def limit_file_size(limit: int):
    """A preexec_fn for subprocess: files in the child cannot grow past `limit` bytes, and a write
    beyond it fails with EFBIG instead of killing the child (SIGXFSZ ignored): a disk that fills
    part-way through a file, in a child process, without a small file system."""
    def apply():
        import resource
        import signal
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    return apply


@pytest.fixture
def file_size_limit():
    return limit_file_size
