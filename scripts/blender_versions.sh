#!/usr/bin/env bash
# Runs the whole Blender suite (tests/blender) in the Blenders of newer Debian releases: for each suite
# named (default: trixie sid), a chroot made once by debootstrap from this machine's Debian archive and
# kept in $SHADECUT_CHROOTS (default /var/cache/shadecut), outside the repository, so later runs reuse
# it. The repository's files are copied in, the modules the suite needs (_core, _imageio, the add-on
# zip) are built there with that release's compilers and Python, and the suite runs in its Blender.
#   sudo bash scripts/blender_versions.sh [trixie] [sid]
# Needs root (debootstrap, chroot, mounts). docs/building_and_testing.md gives the times measured.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
REPO=$PWD
CHROOTS=${SHADECUT_CHROOTS:-/var/cache/shadecut}
# The archive this machine installs from, so that no other source is needed.
MIRROR=${SHADECUT_MIRROR:-$(cat /etc/apt/sources.list /etc/apt/sources.list.d/*.sources 2>/dev/null \
  | grep -oE '^(URIs:|deb) +https?://[^ ]+/debian/?( |$)' | head -n1 | grep -oE 'https?://[^ ]+' || true)}
# What the Blender suite needs inside the chroot: the build of the Python modules and the suite's imports;
# python3-cattr and python3-requests for Blender 5's own extensions add-on, which Debian's package does not
# pull in (without them every start prints its traceback).
PACKAGES=(
  blender xvfb xauth python3-cattr python3-requests
  cmake g++ make pkg-config python3-dev pybind11-dev libeigen3-dev libopenimageio-dev
  python3-numpy python3-pytest python3-openimageio python3-matplotlib python3-scipy
)

# A chroot for one suite, made when missing: debootstrap into a .partial folder, then the packages,
# then renamed, so an interrupted setup is redone rather than reused half made.
ensure_chroot() {
  local suite=$1 root=$CHROOTS/chroot-$1
  if [[ -f $root/.shadecut-ready ]]; then
    echo "blender_versions: reusing $root"
    install_packages "$root"
    return
  fi
  [[ -n $MIRROR ]] || { echo "blender_versions: no Debian archive in /etc/apt; set SHADECUT_MIRROR" >&2; exit 1; }
  command -v debootstrap >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
  mkdir -p "$CHROOTS"
  rm -rf "$root.partial"
  echo "blender_versions: creating $root from $MIRROR (debootstrap $suite)"
  nice debootstrap --variant=minbase "$suite" "$root.partial" "$MIRROR" >"$CHROOTS/debootstrap-$suite.log" 2>&1 \
    || { tail -n 20 "$CHROOTS/debootstrap-$suite.log" >&2; exit 1; }
  install_packages "$root.partial"
  touch "$root.partial/.shadecut-ready"
  mv "$root.partial" "$root"
}

# The packages the chroot lacks (all of them at first; a package added to PACKAGES later), installed.
install_packages() {
  local root=$1 missing=() package
  for package in "${PACKAGES[@]}"; do
    chroot "$root" dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
  done
  ((${#missing[@]})) || return 0
  echo "blender_versions: installing ${missing[*]} in $root"
  # Check-Valid-Until off: sid's Release expires within days, and the archive may be a dated snapshot.
  with_mounts "$root" bash -c "apt-get -o Acquire::Check-Valid-Until=false update -qq && DEBIAN_FRONTEND=noninteractive \
    nice apt-get install -y -qq --no-install-recommends ${missing[*]} >/dev/null"
}

# Mounts a run killed outright left in the chroot (SIGKILL skips with_mounts' trap), released: mounting
# /sys over them fails, and /proc and /dev would stack. Bounded, in case one is busy.
release_mounts() {
  local root=$1 path tries
  for path in dev sys proc; do
    for ((tries = 0; tries < 20; tries++)); do
      mountpoint -q "$root/$path" || break
      umount -R "$root/$path"
    done
  done
}

# Runs a command in the chroot with /proc, /dev and /sys mounted, unmounting them whatever happens.
with_mounts() {
  local root=$1 status=0
  shift
  release_mounts "$root"
  mount -t proc proc "$root/proc"
  mount --rbind /dev "$root/dev" && mount --make-rslave "$root/dev"
  mount -t sysfs sysfs "$root/sys"
  # test.sh's time limit (timeout) ends this with SIGTERM: the mounts go with it.
  trap 'umount -R "$root/dev" "$root/sys" "$root/proc" 2>/dev/null; exit 143' TERM INT
  chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 "$@" || status=$?
  trap - TERM INT
  umount -R "$root/dev" "$root/sys" "$root/proc"
  return $status
}

# The working tree's files (tracked, and new ones not ignored) copied afresh into the chroot, so that
# nothing built there lands in this repository's addon/ folder. The copy's build/ folder is kept and tar
# keeps the files' times, so a later run recompiles only what changed.
copy_repository() {
  local target=$1/work/shadecut
  mkdir -p "$target"
  find "$target" -mindepth 1 -maxdepth 1 ! -name build -exec rm -rf {} +
  git -C "$REPO" ls-files -z --cached --others --exclude-standard \
    | (cd "$REPO" && xargs -0 ls -d 2>/dev/null | tar -cf - -T -) | tar -xf - -C "$target"
}

run_suite() {
  local suite=$1 root=$CHROOTS/chroot-$1 started=$SECONDS
  ensure_chroot "$suite"
  copy_repository "$root"
  echo "== Blender tests in Debian $suite: $(chroot "$root" blender --version 2>/dev/null | head -n1)"
  with_mounts "$root" bash -c 'set -e; cd /work/shadecut
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSHADECUT_BUILD_TESTS=OFF -DSHADECUT_BUILD_BENCHMARKS=OFF >/dev/null
    nice cmake --build build -j2 --target _core _imageio addon_zip >build.log 2>&1 || { tail -n 40 build.log; exit 1; }
    nice blender -b --factory-startup --python-exit-code 1 -P tests/blender/run_pytest.py -- tests/blender -q'
  echo "blender_versions: Debian $suite took $((SECONDS - started)) s"
}

if [[ ${BASH_SOURCE[0]} == "$0" ]]; then  # run, not sourced for its functions
  suites=("$@")
  ((${#suites[@]})) || suites=(trixie sid)
  for suite in "${suites[@]}"; do
    run_suite "$suite"
  done
fi
