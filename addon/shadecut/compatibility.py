"""Whether this Python can load the compiled module ``_core`` shipped beside this file, asked without
importing it: a module built for another Python or platform fails on import with a message about
symbols or DLLs that an artist cannot act on. The add-on shows :func:`core_problem`'s sentence in
a report and in its panel instead.
"""

from __future__ import annotations

import importlib.machinery
import platform
import re
import sys
from pathlib import Path
from typing import Optional, Sequence

PACKAGE_DIR = Path(__file__).resolve().parent

# The oldest glibc a Linux zip's _core loads on, whichever Debian built it (Ubuntu 22.04's; the
# symbols it pins: native/python/glibc_compat.cpp, docs/portable_addon.md).
OLDEST_GLIBC = (2, 35)

_PLATFORM_NAMES = (("linux", "Linux"), ("darwin", "macOS"), ("win", "Windows"))


def describe_build(file_name: str) -> str:
    """Who a compiled module is for, read from its name: "_core.cpython-311-x86_64-linux-gnu.so" is
    "Python 3.11 on Linux x86_64"; "_core.cp311-win_amd64.pyd" is "Python 3.11 on Windows amd64"."""
    match = re.match(r"_core\.(?:cpython-|cp)(\d)(\d+)[-_]?(.*)\.(?:so|pyd)$", file_name)
    if not match:
        return file_name
    major, minor, tag = match.groups()
    system = next((name for prefix, name in _PLATFORM_NAMES if prefix in tag), "")
    machine = re.sub(r"-?(linux-gnu|darwin|linux|win)[-_]?", "", tag)
    where = " ".join(part for part in (system, machine) if part)
    return f"Python {major}.{minor}" + (f" on {where}" if where else "")


def addon_zip_name(version: str) -> str:
    """The name of the add-on zip for this Python and platform, as the build names it
    (native/python/CMakeLists.txt): "shadecut-addon-0.1.0-linux-x64-cp311.zip"."""
    system = {"Darwin": "macos"}.get(platform.system(), platform.system().lower())
    machine = "arm64" if platform.machine().lower() in ("aarch64", "arm64") else "x64"
    return f"shadecut-addon-{version}-{system}-{machine}-cp{sys.version_info.major}{sys.version_info.minor}.zip"


def describe_running() -> str:
    """This interpreter in the words of describe_build: "Python 3.12 on Windows AMD64"."""
    return f"Python {sys.version_info.major}.{sys.version_info.minor} on {platform.system()} {platform.machine()}"


def core_problem(package_dir: Path = PACKAGE_DIR,
                 suffixes: Sequence[str] = tuple(importlib.machinery.EXTENSION_SUFFIXES),
                 running: Optional[str] = None) -> Optional[str]:
    """None when ``package_dir`` holds a ``_core`` this interpreter loads (one whose name ends in one
    of its extension ``suffixes``); otherwise one sentence saying what is wrong and what to do."""
    cores = sorted(path.name for path in package_dir.glob("_core.*") if path.suffix in (".so", ".pyd"))
    if any(name == "_core" + suffix for name in cores for suffix in suffixes):
        return None
    if not cores:
        return ("ShadeCut's compiled module _core is missing: build it first (README.md, "
                "'cmake -S . -B build && cmake --build build'), which places it in addon/shadecut/.")
    return (f"This ShadeCut was built for {describe_build(cores[0])}, but this Blender runs "
            f"{running or describe_running()}: install the ShadeCut zip built for it "
            f"({addon_zip_name('<version>')}; docs/portable_addon.md says how to build one).")
