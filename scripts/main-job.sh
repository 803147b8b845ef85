#!/usr/bin/env bash
# The main job (README): installs dependencies, builds, and runs the headless demo.
# Usage (as root, from the repository root): bash scripts/main-job.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
mkdir -p out
./build/demos/sdfccd build-sdf assets/meshes/bunny.off --resolution 128 --padding 4 -o out/bunny-128.sdf
./build/demos/sdfccd info out/bunny-128.sdf
