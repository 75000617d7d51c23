#!/usr/bin/env bash
# The demo: installs the dependencies, builds, renders the Mozart depth map under light (1, 0, 1),
# reconstructs it with graphcut and lee_rosenfeld, prints both errors and writes out/demo/.
# The build shows one line per finished part (CMake's "Built target" and "Linking" steps with their
# percentage), so that its minutes are not silent; its compiler errors, on stderr, show in full.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh | grep --line-buffered -E '^(== build.sh|\[ *[0-9]+%\] (Built target|Linking))'
PYTHONPATH=addon /usr/bin/python3 scripts/demo.py "$@"
