#!/usr/bin/env bash
# The C++ tests and the command-line tool under AddressSanitizer and UndefinedBehaviorSanitizer: any
# report fails the run. Builds into build-sanitize/ (no Python module, no benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."
started=$SECONDS
echo "== sanitize.sh: building the C++ tests and the CLI with AddressSanitizer and UBSan into build-sanitize/" \
     "(a first build compiles the core again: minutes), then running them"
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHADECUT_BUILD_PYTHON=OFF -DSHADECUT_BUILD_BENCHMARKS=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-sanitize -j"$(nproc)" --target shadecut_tests shadecut_cli
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
echo "== sanitize.sh: built after $((SECONDS - started)) s; the C++ tests under the sanitizers"
ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)"
echo "== sanitize.sh: the command-line tool under the sanitizers"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
PYTHONPATH=addon /usr/bin/python3 -c "
import sys, shadecut
from shadecut import synthetic
scene = synthetic.sphere((1, 0, 1), size=96)
shadecut.save_image(sys.argv[1], scene.image, scene.mask)" "$work/sphere.png"
build-sanitize/native/shadecut "$work/sphere.png" --out "$work/out" --quiet
build-sanitize/native/shadecut "$work/sphere.png" --scene relief --light 1,0,1 --out "$work/relief" --quiet
echo "== sanitize.sh: clean (no sanitizer report) in $(( (SECONDS - started) / 60 )) min $(( (SECONDS - started) % 60 )) s"
