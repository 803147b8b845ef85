#!/usr/bin/env bash
# The whole headless pipeline on a tiny primitive scene: `sdfccd simulate` writes a run folder, `sdfccd render`
# re-renders it (frames named by frame number, contact sheet) and `sdfccd plot` plots it from the same CSV.
# Skipped when the tool has no simulate command (Bullet not built) or no renderer.
# Usage: bash simulate_render.sh /path/to/sdfccd /path/to/assets
set -uo pipefail
source "$(dirname "$0")/lib.sh"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

skip_without simulate "no simulate command"
cat > "$work/scene.json" <<'JSON'
{ "name": "render-smoke", "timestep": 0.002, "frames": 60, "gravity": [0, -9.81, 0],
  "effects": ["gravity", "ground", "damping", "rotation"], "ground": { "height": 0.0 },
  "contact": { "mode": "penalty", "model": "continuous", "stiffness": 2000.0, "damping": 5.0, "subintervals": 5 },
  "bodies": [ { "name": "ball", "primitive": { "type": "sphere", "radius": 0.1, "subdivisions": 2 }, "mass": 1.0,
                "position": [0, 0.3, 0], "points": 200, "resolution": 24 },
              { "name": "crate", "primitive": { "type": "box", "half_extents": [0.08, 0.05, 0.08] }, "mass": 1.0,
                "position": [0.3, 0.2, 0.1], "orientation": [0.9659258, 0, 0.2588190, 0], "points": 200,
                "resolution": 24 } ] }
JSON
out="$("$tool" simulate "$work/scene.json" --out "$work/run" --cache "" 2>&1)" || fail "simulate failed: $out"
[ -f "$work/run/frames.csv" ] || fail "simulate wrote no frames.csv"

render_out="$("$tool" render "$work/run" --size 120x80 --every 20 --sheet-cells 3 --thumb-width 60 --no-video 2>&1)"
if echo "$render_out" | grep -q "built without the renderer"; then
  echo "renderer not built: render checks skipped" >&2
else
  echo "$render_out" | grep -q "frames: 3 PNG" || fail "render: $render_out"
  count=0
  for f in "$work/run/frames"/frame_*.png; do
    [ "$(png_size "$f")" = "120x80" ] || fail "$f is not 120x80"
    count=$((count + 1))
  done
  [ "$count" -eq 3 ] || fail "expected 3 frames, found $count"
  # 3 cells of 60x40 on 2 columns: 2*64+4 = 132 by 2*44+4 = 92.
  [ "$(png_size "$work/run/contact_sheet.png")" = "132x92" ] || fail "contact sheet size $(png_size "$work/run/contact_sheet.png")"
fi

# simulate --render writes frames while simulating: frame 0 (the start) and every K-th frame after it, with the
# scene's own camera; a camera with a bad field of view is rejected by the scene loader before anything runs.
if ! echo "$render_out" | grep -q "built without the renderer"; then
  sed 's/"name": "render-smoke",/"name": "render-smoke", "camera": { "eye": [1.2, 0.8, 1.2], "target": [0, 0.1, 0], "fov": 40 },/' \
    "$work/scene.json" > "$work/camera.json"
  out="$("$tool" simulate "$work/camera.json" --out "$work/run2" --cache "" --render "$work/live" --every 20 --size 120x80 2>&1)" ||
    fail "simulate --render failed: $out"
  for n in 00000 00020 00040 00060; do
    [ "$(png_size "$work/live/frame_$n.png")" = "120x80" ] || fail "simulate --render: frame_$n.png missing or not 120x80"
  done
  [ "$(ls "$work/live" | wc -l)" -eq 4 ] || fail "simulate --render wrote $(ls "$work/live" | wc -l) files, expected 4"
  sed 's/"fov": 40/"fov": 400/' "$work/camera.json" > "$work/badcamera.json"
  err="$("$tool" simulate "$work/badcamera.json" --out "$work/run3" --cache "" 2>&1)" && fail "a 400 degree fov was accepted"
  [ "$(echo "$err" | wc -l)" -eq 1 ] && echo "$err" | grep -q "fov" || fail "bad camera error is not one line naming fov: $err"
fi

if command -v gnuplot >/dev/null 2>&1; then
  out="$("$tool" plot "$work/run" 2>&1)" || fail "plot failed: $out"
  for p in penetration kinetic_energy contacts ccd_time overview; do
    [ -s "$work/run/plots/$p.png" ] || fail "plots/$p.png missing"
  done
  # The kinetic energy computed from the CSV's velocities ends where the summary says it does.
  final_csv="$(grep -v '^#' "$work/run/plots/series.dat" | tail -1 | awk '{print $4}')"
  final_summary="$(awk -F': ' '/"final_kinetic_energy"/ { gsub(/[ ,]/, "", $2); print $2 }' "$work/run/summary.json")"
  awk -v a="$final_csv" -v b="$final_summary" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-6 + 1e-5 * (b < 0 ? -b : b)) }' ||
    fail "kinetic energy from the CSV ($final_csv) differs from summary.json ($final_summary)"
fi

if [ "$failures" -ne 0 ]; then
  echo "simulate_render: $failures failure(s)" >&2
  exit 1
fi
echo "simulate_render: all checks passed"
