#!/usr/bin/env bash
# Installs the Debian 12 packages sdfccd needs. Idempotent: packages already present are skipped.
# Usage (as root): bash scripts/install-deps.sh
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git  # ninja: the generator of scripts/test.sh's builds
  libeigen3-dev        # core linear algebra (double)
  libassimp-dev        # mesh loading: OBJ, OFF, PLY, STL, glTF, ...
  libbullet-dev        # Bullet Physics 3.24, single precision (found through bullet.pc)
  libosmesa6-dev       # offscreen rendering without a display or GPU
  libgtest-dev         # unit tests
  libbenchmark-dev     # micro benchmarks
  libcli11-dev         # command-line parsing
  nlohmann-json3-dev   # scene files and summaries
  libpng-dev           # frame output
  gnuplot-nox          # run plots (sdfccd plot), headless pngcairo terminal
  libtbb-dev           # parallel loops in the SDF builder and tree traversal
  libopenvdb-dev libboost-dev  # optional peer of `sdfccd bench segments` (OpenVDB LevelSetRayIntersector)
  clang libclang-rt-14-dev     # libFuzzer targets of the loaders (tests/fuzz; scripts/test.sh fuzz stage)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present" >&2
  exit 0
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
