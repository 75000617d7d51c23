#!/usr/bin/env bash
# The C++ tests and the command-line tool under AddressSanitizer and UndefinedBehaviorSanitizer: any
# report fails the run. Builds into build-sanitize/ (no Python module, no benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHADECUT_BUILD_PYTHON=OFF -DSHADECUT_BUILD_BENCHMARKS=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-sanitize -j"$(nproc)" --target shadecut_tests shadecut_cli
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
PYTHONPATH=addon /usr/bin/python3 -c "
import sys, shadecut
from shadecut import synthetic
scene = synthetic.sphere((1, 0, 1), size=96)
shadecut.save_image(sys.argv[1], scene.image, scene.mask)" "$work/sphere.png"
build-sanitize/native/shadecut "$work/sphere.png" --out "$work/out" --quiet
build-sanitize/native/shadecut "$work/sphere.png" --scene relief --light 1,0,1 --out "$work/relief" --quiet
echo "sanitizers: clean"
