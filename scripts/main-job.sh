#!/usr/bin/env bash
# The main job (README): installs dependencies, builds, and runs the headless demo.
# Usage (as root, from the repository root): bash scripts/main-job.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
mkdir -p out
# Paper Fig. 10a: 20 bunnies dropped onto the ground, headless (fields and shells cached in out/cache).
./build/demos/sdfccd simulate assets/scenes/drop-bunnies.json --out out/drop-bunnies
