#!/usr/bin/env bash
# The one test command: installs the dependencies, builds, and runs every test (C++, Python, and the add-on inside
# Blender: Debian 12's, and in chroots Debian 13's and sid's, scripts/blender_versions.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage says when it starts; the run ends with one line, whether every stage passed or which one
# failed, and the time it took (a busy machine can take far longer than docs/building_and_testing.md's figures).
started=$SECONDS
stage="installing the dependencies"
elapsed() { echo "$(( (SECONDS - started) / 60 )) min $(( (SECONDS - started) % 60 )) s"; }
next() { stage=$1; echo "== $1 (at $(elapsed))"; }
trap 'code=$?; if ((code == 0)); then echo "== test.sh: every stage passed in $(elapsed)";
      else echo "== test.sh: FAILED in the stage \"$stage\" (exit code $code) after $(elapsed)"; fi' EXIT
bash scripts/install_dependencies.sh
next "Build (scripts/build.sh)"
bash scripts/build.sh
next "C++ tests (GoogleTest via ctest)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
next "Python tests (pytest, system interpreter)"
PYTHONPATH=addon /usr/bin/python3 -m pytest tests/python -q -p no:cacheprovider
next "Blender tests (pytest inside headless Blender)"
blender -b --factory-startup --python-exit-code 1 -P tests/blender/run_pytest.py -- tests/blender -q
next "C++ tests and the CLI under AddressSanitizer and UBSan"
bash scripts/sanitize.sh
# The other Blenders last, in chroots (scripts/blender_versions.sh): each takes about a quarter of CI's
# 90 minutes (docs/building_and_testing.md), so each runs only while the time left allows it, and says
# so when it does not. A failure in either decides the run.
budget=${SHADECUT_TEST_SECONDS:-5100}
other_blender() {
  local suite=$1 left=$((budget - (SECONDS - started))) code=0
  if ((left < 1800)); then
    echo "== SKIPPED the Blender suite in $suite's Blender: $((left / 60)) of the run's $((budget / 60)) minutes left, it needs about 30"
    return 0
  fi
  next "Blender tests in $suite's Blender (chroot made once, then reused)"
  timeout "$left" bash scripts/blender_versions.sh "$suite" || code=$?
  if ((code == 124)); then
    echo "== STOPPED the Blender suite in $suite's Blender: the run's $((budget / 60)) minutes ran out"
  elif ((code != 0)); then
    return "$code"
  fi
}
other_blender trixie
other_blender sid
