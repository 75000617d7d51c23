#!/usr/bin/env bash
# The one test command: installs the dependencies, builds, and runs every test (C++, Python, and the add-on inside Blender).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh
echo "== C++ tests (GoogleTest via ctest)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
echo "== Python tests (pytest, system interpreter)"
PYTHONPATH=addon /usr/bin/python3 -m pytest tests/python -q -p no:cacheprovider
echo "== Blender tests (pytest inside headless Blender)"
blender -b --factory-startup --python-exit-code 1 -P tests/blender/run_pytest.py -- tests/blender -q
echo "== C++ tests and the CLI under AddressSanitizer and UBSan"
bash scripts/sanitize.sh
