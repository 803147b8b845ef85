#!/usr/bin/env bash
# `sdfccd render` and `sdfccd plot` on a hand-made run folder (long CSV layout, docs/cli.md, run folders):
# frames, contact sheet and plots are written with the right sizes; bad runs fail with one clear line.
# Usage: bash render_plot.sh /path/to/sdfccd /path/to/assets
set -uo pipefail
source "$(dirname "$0")/lib.sh"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

make_run() {  # make_run DIR MESH_PATH [REST_HEIGHT]
  mkdir -p "$1"
  cat > "$1/scene.json" <<JSON
{ "timestep": 0.01, "frames": 30, "gravity": [0, -9.81, 0], "effects": ["gravity", "ground"],
  "ground": { "height": 0.0 },
  "camera": { "eye": [1.5, 1.2, 2.5], "target": [0, 0.3, 0], "fov": 40 },
  "bodies": [ { "name": "bunny0", "mesh": "$2", "scale": 0.5, "mass": 1.0, "position": [0, 1, 0] },
              { "name": "bunny1", "mesh": "$2", "scale": 0.4, "mass": 1.0, "position": [0.6, 1, 0] } ] }
JSON
  awk -v rest="${3:-0.25}" 'BEGIN { print "frame,time,body,px,py,pz,qw,qx,qy,qz,contacts,penetration,kinetic_energy,ccd_seconds";
    for (f = 0; f < 30; f++) { t = f * 0.02; y = 1 - 4.9 * t * t; if (y < rest) y = rest;
      printf "%d,%.3f,bunny0,0,%.5f,0,1,0,0,0,%d,%.4f,%.4f,%.6f\n", f, t, y, (y <= rest) ? 4 : 0, (y <= rest) ? 0.001 : 0, 0.5 * (9.8 * t) ^ 2, 0.0002;
      printf "%d,%.3f,bunny1,0.6,%.5f,0,0.7071,0,0.7071,0,%d,%.4f,%.4f,%.6f\n", f, t, y, 0, 0, 0.4 * (9.8 * t) ^ 2, 0.0001 } }' \
    > "$1/frames.csv"
}

# Mesh found through the original scene's folder named in summary.json (assets/scenes -> assets/meshes).
run="$work/run"
make_run "$run" "meshes/bunny.off"
echo "{\"frames\": 30, \"scene\": \"$assets/scenes/hand_made.json\"}" > "$run/summary.json"

render_out="$("$tool" render "$run" --size 160x90 --every 10 --sheet-cells 4 --thumb-width 80 2>&1)"
render_status=$?
if echo "$render_out" | grep -q "built without the renderer"; then
  echo "renderer not built: render checks skipped" >&2
else
  [ "$render_status" -eq 0 ] || fail "render exited $render_status: $render_out"
  for f in 00000 00010 00020; do
    [ -f "$run/frames/frame_$f.png" ] || fail "frame_$f.png missing"
    [ "$(png_size "$run/frames/frame_$f.png" 2>/dev/null)" = "160x90" ] || fail "frame_$f.png is not 160x90"
  done
  [ "$(ls "$run/frames" | grep -c '^frame_.*\.png$')" -eq 3 ] || fail "expected 3 frames: $(ls "$run/frames")"
  # 4 cells of 80x45: 2x2 grid with 4 px padding: 2*84+4 = 172 by 2*49+4 = 102.
  [ "$(png_size "$run/contact_sheet.png" 2>/dev/null)" = "172x102" ] || fail "contact sheet size $(png_size "$run/contact_sheet.png")"
  # Same input, same frames (byte for byte: the renderer is deterministic).
  cp "$run/frames/frame_00010.png" "$work/before.png"
  "$tool" render "$run" --size 160x90 --every 10 --sheet-cells 0 --no-video >/dev/null 2>&1 || fail "second render failed"
  cmp -s "$work/before.png" "$run/frames/frame_00010.png" || fail "re-rendering changed frame 10"
  ls "$run/frames" | grep -q tmp && fail "temporary files left in frames/"

  # Bodies sunk into the ground: --ground-contacts marks the vertices below it, so the last frame changes.
  sunk="$work/sunk"
  make_run "$sunk" "$assets/meshes/bunny.off" 0.02
  "$tool" render "$sunk" --size 160x90 --every 29 --sheet-cells 0 --no-video --out "$sunk/plain" >/dev/null 2>&1 ||
    fail "render of the sunk run failed"
  "$tool" render "$sunk" --size 160x90 --every 29 --sheet-cells 0 --no-video --ground-contacts --out "$sunk/marked" \
    >/dev/null 2>&1 || fail "render --ground-contacts failed"
  cmp -s "$sunk/plain/frame_00000.png" "$sunk/marked/frame_00000.png" || fail "contacts marked while in the air"
  cmp -s "$sunk/plain/frame_00029.png" "$sunk/marked/frame_00029.png" && fail "no contacts marked on the sunk bodies"

  # Missing mesh: one clear error line, non-zero exit.
  bad="$work/missing_mesh"
  make_run "$bad" "no/such/mesh.off"
  out="$("$tool" render "$bad" --size 64x64 2>&1)" && fail "missing mesh accepted"
  echo "$out" | grep -q "bodies\[0\].mesh names a missing file 'no/such/mesh.off'" || fail "missing mesh message: $out"
  [ "$(echo "$out" | wc -l)" -eq 1 ] || fail "missing mesh: more than one line: $out"
  # Unwritable output folder (a path below a regular file fails even for root).
  touch "$work/plain_file"
  out="$("$tool" render "$run" --size 64x64 --out "$work/plain_file/frames" 2>&1)" && fail "unwritable folder accepted"
  echo "$out" | grep -q "plain_file" || fail "unwritable folder message: $out"
  # Truncated CSV.
  trunc="$work/truncated"
  make_run "$trunc" "$assets/meshes/bunny.off"
  head -c 300 "$run/frames.csv" > "$trunc/frames.csv"
  out="$("$tool" render "$trunc" --size 64x64 2>&1)" && fail "truncated CSV accepted"
  echo "$out" | grep -q "frames.csv" || fail "truncated CSV message: $out"
  out="$("$tool" render "$run" --size 64 2>&1)" && fail "bad --size accepted"
  echo "$out" | grep -q "WIDTHxHEIGHT" || fail "bad size message: $out"
fi

# Plots: with gnuplot, four series and an overview; without it, a clear error.
if command -v gnuplot >/dev/null 2>&1; then
  out="$("$tool" plot "$run" --size 320x200 2>&1)" || fail "plot failed: $out"
  for p in penetration kinetic_energy contacts ccd_time; do
    [ "$(png_size "$run/plots/$p.png" 2>/dev/null)" = "320x200" ] || fail "plots/$p.png missing or wrong size"
  done
  [ -f "$run/plots/overview.png" ] || fail "plots/overview.png missing"
  # series.dat: one row per frame.
  [ "$(grep -vc '^#' "$run/plots/series.dat")" -eq 30 ] || fail "series.dat does not have 30 rows"
  # Last frame, bunny0 resting: penetration is the deepest body's (0.001), contacts add up (4 + 0), CCD time
  # adds up (0.2 + 0.1 ms). Columns: frame time penetration kinetic_energy contacts ccd_seconds(ms).
  tail -1 "$run/plots/series.dat" | awk '{ d = $6 - 0.3; exit !($1 == 29 && $3 == 0.001 && $5 == 4 && d * d < 1e-12) }' ||
    fail "per-frame aggregation: $(tail -1 "$run/plots/series.dat")"
else
  out="$(PATH=/nonexistent "$tool" plot "$run" 2>&1)" && fail "plot without gnuplot succeeded"
fi
out="$(PATH=/nonexistent "$tool" plot "$run" 2>&1)" && fail "plot without gnuplot succeeded"
echo "$out" | grep -q "gnuplot is not installed" || fail "no-gnuplot message: $out"

if [ "$failures" -ne 0 ]; then
  echo "render_plot: $failures failure(s)" >&2
  exit 1
fi
echo "render_plot: all checks passed"
