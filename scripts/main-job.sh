#!/usr/bin/env bash
# The main job (README): installs dependencies, builds, runs the headless demo and shows what it did: the run's
# summary, a contact sheet of the drop (OSMesa, offscreen) and its plots (gnuplot), with where each file is.
# Usage (as root, from the repository root): bash scripts/main-job.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# The tool only (its libraries with it), in the test command's tree and settings (the release preset): the test
# command reuses what this compiled and builds only the suites on top.
cmake --preset release >/dev/null
cmake --build --preset release -j"$(nproc)" --target sdfccd
mkdir -p out
run=out/drop-bunnies
# Paper Fig. 10a: 20 bunnies dropped onto the ground, headless (fields and shells cached in the model cache).
./build/demos/sdfccd simulate assets/scenes/drop-bunnies.json --out "$run"
# The contact sheet only (12 frames re-rendered from the run's CSV, no frame folder, no video): seconds.
./build/demos/sdfccd render "$run" --no-frames --no-video
# Penetration, kinetic energy, contacts and CCD time per frame, and an overview.
./build/demos/sdfccd plot "$run"
for file in "$run/summary.json" "$run/contact_sheet.png" "$run/plots/overview.png"; do
  [[ -f "$file" ]] || { echo "main job: $file was not written" >&2; exit 1; }
done
echo
echo "What the main job made:"
echo "  summary:        $run/summary.json (per frame: $run/frames.csv)"
echo "  contact sheet:  $run/contact_sheet.png"
echo "  plots:          $run/plots/overview.png and the single plots beside it in $run/plots/"
