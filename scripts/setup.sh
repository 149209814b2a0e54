#!/usr/bin/env bash
# Installs the Debian 12 packages grip needs, only those that are missing. Run as root.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git clang libclang-rt-14-dev
  libeigen3-dev libccd-dev            # runtime: math and convex collision
  libcgal-dev libopenvdb-dev          # offline mesh preprocessing (voxel/)
  libcgal-demo                        # third-party test meshes (elephant, bunny, ...)
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libcli11-dev     # scene files and the command line
  libbullet-dev libode-dev            # peers for side-by-side comparisons
  chromium fonts-dejavu-core          # the viewer's browser tests and screenshots (docs/viewer.md)
)
# The viewer is built with Node.js and npm (web/): Debian's, unless a node is already there.
command -v node >/dev/null || packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
