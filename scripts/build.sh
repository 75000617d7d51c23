#!/usr/bin/env bash
# Configures and builds everything (Release) into build/; the Python extension lands in addon/shadecut/.
# Says what it does before it starts and how long it took: a first build compiles for minutes, and each
# "[ NN%]" line of CMake's is a step of it.
set -euo pipefail
cd "$(dirname "$0")/.."
started=$SECONDS
echo "== build.sh: building ShadeCut (Release) into build/ with $(nproc) parallel jobs; a first build takes minutes," \
     "a later one only what changed"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
echo "== build.sh: built in $(( (SECONDS - started) / 60 )) min $(( (SECONDS - started) % 60 )) s"
