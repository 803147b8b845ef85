#!/usr/bin/env bash
# A run folder whose last frame went non-finite (simulate stops there with exit code 3) can still be plotted and
# rendered: the frames before the NaN row are used, one warning line says where the run stopped. A NaN in the first
# frame is still an error.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"
cat > "$work/scene.json" <<'JSON'
{ "timestep": 0.001, "frames": 20, "effects": ["gravity", "ground"],
  "bodies": [ { "name": "box", "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0,
                "position": [0, 0.3, 0], "points": 50, "resolution": 8 } ] }
JSON
"$tool" simulate "$work/scene.json" --out "$work/run" --cache "" > /dev/null 2>&1 || fail "simulate"
# The run as simulate leaves it after a NaN: one more row, its state non-finite.
tail -1 "$work/run/frames.csv" | awk -F, 'BEGIN { OFS = "," } { $1 = $1 + 1; $3 = "nan"; $4 = "-nan"; print }' \
  >> "$work/run/frames.csv"
[ "$(wc -l < "$work/run/frames.csv")" -eq 22 ] || fail "frames.csv rows"

"$tool" plot "$work/run" --size 320x200 --out "$work/plots" > /dev/null 2> "$work/err.txt"
code=$?
if grep -q "gnuplot" "$work/err.txt" && [ "$code" -ne 0 ]; then
  echo "gnuplot not installed: plot check skipped"
else
  [ "$code" -eq 0 ] || fail "plot of a NaN run failed: $(cat "$work/err.txt")"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "not one warning line: $(cat "$work/err.txt")"
  grep -q "line 22: a non-finite state; the 20 frames before it are used" "$work/err.txt" ||
    fail "warning: $(cat "$work/err.txt")"
  ls "$work/plots"/*.png > /dev/null 2>&1 || fail "no plots written"
fi
"$tool" render "$work/run" --size 64x48 --every 10 --sheet-cells 0 --no-video --out "$work/frames" > /dev/null \
  2> "$work/err.txt"
code=$?
if grep -q "built without the renderer" "$work/err.txt"; then
  echo "renderer not built: render check skipped"
else
  [ "$code" -eq 0 ] || fail "render of a NaN run failed: $(cat "$work/err.txt")"
  grep -q "non-finite state" "$work/err.txt" || fail "render: no warning: $(cat "$work/err.txt")"
  [ -f "$work/frames/frame_00010.png" ] || fail "render: frame 10 missing"
fi

# NaN already in the first frame: nothing to show, one error line naming the file.
head -1 "$work/run/frames.csv" > "$work/first.csv"
tail -1 "$work/run/frames.csv" >> "$work/first.csv"
cp "$work/first.csv" "$work/run/frames.csv"
expect_one_line_error plot "$work/run" --out "$work/plots2"
grep -q "frames.csv" "$work/err.txt" || fail "first-frame NaN: $(cat "$work/err.txt")"
echo "ok"
