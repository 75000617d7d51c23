#!/usr/bin/env bash
# The demo: installs the dependencies, builds, renders the Mozart depth map under light (1, 0, 1),
# reconstructs it with graphcut and lee_rosenfeld, prints both errors and writes out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh >/dev/null
PYTHONPATH=addon /usr/bin/python3 scripts/demo.py "$@"
