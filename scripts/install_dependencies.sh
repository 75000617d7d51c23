#!/usr/bin/env bash
# Installs ShadeCut's build and test dependencies from Debian 12's archive (run as root).
# Packages already present are not fetched again, so repeated runs cost a second.
set -euo pipefail

PACKAGES=(
  cmake g++ make pkg-config
  libeigen3-dev libopencv-dev libopenimageio-dev libboost-dev pybind11-dev libsuitesparse-dev
  python3 python3-dev python3-numpy python3-pytest python3-openimageio python3-matplotlib python3-scipy python3-pyelftools python3-skimage
  googletest libgtest-dev libbenchmark-dev
  blender xvfb xauth
)

missing=()
for package in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if ((${#missing[@]})); then
  if [[ $(id -u) -ne 0 ]]; then
    echo "install_dependencies: missing ${missing[*]}; run this script as root (apt-get)" >&2
    exit 1
  fi
  echo "install_dependencies: installing ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
