#!/usr/bin/env bash
# sdfccd simulate: a run folder with frames.csv, summary.json and scene.json; the plate scene stops the bunny
# with the continuous model and lets it tunnel with the discrete one; bad scenes fail with one line.
set -euo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"
value() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

cat > "$work/drop.json" <<'JSON'
{ "timestep": 0.001, "frames": 150, "effects": ["gravity", "ground", "damping"],
  "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 4.0 },
  "bodies": [ { "name": "box", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "mass": 1.0,
                "position": [0, 0.06, 0], "points": 200, "resolution": 12 } ] }
JSON
"$tool" simulate "$work/drop.json" --out "$work/run" --cache "" > "$work/out.txt"
for f in frames.csv summary.json scene.json; do [ -s "$work/run/$f" ] || fail "missing $f"; done
[ "$(value "$work/run/summary.json" frames)" = 150 ] || fail "frames"
[ "$(value "$work/run/summary.json" nan_detected)" = False ] || fail "nan"
[ "$(value "$work/run/summary.json" tunneled_bodies)" = 0 ] || fail "tunnelled"
for key in wall_seconds ccd_seconds max_penetration_cells final_kinetic_energy active_effects; do
  value "$work/run/summary.json" "$key" > /dev/null || fail "summary lacks $key"
done
[ "$(wc -l < "$work/run/frames.csv")" = 151 ] || fail "frames.csv rows"
head -1 "$work/run/frames.csv" | grep -q "box.py" || fail "frames.csv header"
"$tool" simulate "$work/drop.json" --frames 20 --out "$work/run20" --cache "" > /dev/null
[ "$(value "$work/run20/summary.json" frames)" = 20 ] || fail "--frames"

# Fast bunny at a thin plate: continuous stops it, discrete tunnels.
"$tool" simulate "$assets/scenes/bunny-vs-plate.json" --out "$work/plate" --cache "$work/cache" > /dev/null
[ "$(value "$work/plate/summary.json" tunneled_bodies)" = 0 ] || fail "continuous model tunnelled"
"$tool" simulate "$assets/scenes/bunny-vs-plate.json" --model discrete --out "$work/plate-d" --cache "$work/cache" > /dev/null
[ "$(value "$work/plate-d/summary.json" tunneled_bodies)" = 1 ] || fail "discrete model did not tunnel"

# Bad scenes: non-zero exit, one line on stderr, no run folder left behind.
bad() {
  echo "$1" > "$work/bad.json"
  if "$tool" simulate "$work/bad.json" --out "$work/bad-run" --cache "" > /dev/null 2> "$work/err.txt"; then
    fail "accepted: $1"
  fi
  [ "$(wc -l < "$work/err.txt")" = 1 ] || fail "error is not one line: $(cat "$work/err.txt")"
  grep -q "$2" "$work/err.txt" || fail "error does not name $2: $(cat "$work/err.txt")"
  [ ! -e "$work/bad-run/summary.json" ] || fail "summary written for a bad scene"
}
bad '{ "bodies": [ { "primitive": { "type": "box" }, "mass": -1 } ] }' "mass"
bad '{ "bodies": [ { "mesh": "nowhere.off", "mass": 1 } ] }' "missing file"
bad '{ "bodies": [ { "primitive": { "type": "box" }, "mass": 1, "orientation": [2, 0, 0, 0] } ] }' "quaternion"
bad '{ "frames": 10, "wind": 3, "bodies": [] }' "wind"
bad '{ "frames": ' "JSON"
if "$tool" simulate "$work/missing.json" 2> "$work/err.txt"; then fail "missing scene accepted"; fi
echo "ok"
