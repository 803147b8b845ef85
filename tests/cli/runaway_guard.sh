#!/usr/bin/env bash
# The physical sanity guard. Absurd settings that blow a run up (a resting box with stiffness, damping or friction 1e12,
# mass 1e-30 or 1e30) are refused up front with one line naming the key; a scene inside the key ranges that still
# explodes stops with exit code 3 and one line on stderr naming the body; "guard": {"action": "report"} lets it run and
# records the violation; a sound scene is left alone.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"
value() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

# box_scene CONTACT BODY_EXTRA TOP_EXTRA [FRAMES] [MASS]: a box resting on the ground.
box_scene() {
  cat > "$work/scene.json" <<JSON
{ "timestep": 0.001, "frames": ${4:-300}, "effects": ["gravity", "ground", "damping", "friction"] $3,
  "contact": { "mode": "penalty"${1:+, $1} },
  "bodies": [ { "name": "box", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] },
                "position": [0, 0.05, 0], "mass": ${5:-1.0}, "points": 0, "resolution": 12 $2 } ] }
JSON
}

# refused KEY CONTACT BODY_EXTRA [MASS]: the scene fails before any run, one line on stderr naming KEY.
refused() {
  box_scene "$2" "$3" "" 300 "${4:-1.0}"
  "$tool" simulate "$work/scene.json" --out "$work/run" --cache "" > /dev/null 2> "$work/err.txt" &&
    fail "accepted: contact {$2} body {$3}"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "not one line for $1: $(cat "$work/err.txt")"
  grep -qF "$1" "$work/err.txt" || fail "error does not name $1: $(cat "$work/err.txt")"
  [ ! -e "$work/run" ] || fail "run folder left for $1"
}
refused "contact.stiffness" '"stiffness": 1e12' ''
refused "contact.damping" '"stiffness": 2000, "damping": 1e12' ''
refused "contact.friction" '"friction": 1e12' ''
refused "bodies[0].mass" '"stiffness": 2000' '' 1e-30
refused "bodies[0].mass" '"stiffness": 2000' '' 1e30
refused "bodies[0].friction" '"stiffness": 2000' ', "friction": 1e12'

# Inside every range, still unstable: 1e9 N/m per point on a 1 g box at 1 ms (k dt^2 / m = 1e6).
box_scene '"stiffness": 1e9, "damping": 0' '' "" 300 0.001
"$tool" simulate "$work/scene.json" --out "$work/boom" --cache "" > "$work/out.txt" 2> "$work/err.txt"
code=$?
[ "$code" -eq 3 ] || fail "exploding run exited $code, not 3 ($(cat "$work/err.txt"))"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "not one line: $(cat "$work/err.txt")"
grep -q "runaway" "$work/err.txt" || fail "no runaway message: $(cat "$work/err.txt")"
grep -qF "body 'box'" "$work/err.txt" || fail "the message does not name the body: $(cat "$work/err.txt")"
[ "$(value "$work/boom/summary.json" guard_stopped)" = True ] || fail "summary: guard_stopped"
frames="$(value "$work/boom/summary.json" frames)"
[ "$frames" -lt 300 ] || fail "the run was not stopped ($frames frames)"
energy="$(value "$work/boom/summary.json" final_kinetic_energy)"
python3 -c "import sys; sys.exit(0 if float('$energy') < 1e9 else 1)" || fail "stopped too late: $energy J"

# The same scene with "action": "report" runs to the end (exit 0) and keeps the first violation.
box_scene '"stiffness": 1e9, "damping": 0' '' ', "guard": { "action": "report" }' 50 0.001
"$tool" simulate "$work/scene.json" --out "$work/report" --cache "" > /dev/null 2> "$work/err.txt" ||
  fail "report mode failed: $(cat "$work/err.txt")"
[ "$(value "$work/report/summary.json" runaway_detected)" = True ] || fail "report: runaway not recorded"
[ "$(value "$work/report/summary.json" frames)" = 50 ] || fail "report: the run stopped"
value "$work/report/summary.json" runaway | grep -qF "body 'box'" || fail "report: no body named"

# Guard keys are validated too.
box_scene '"stiffness": 2000' '' ', "guard": { "energy_factor": 0.5 }'
expect_one_line_error simulate "$work/scene.json" --out "$work/bad" --cache ""
grep -q "guard.energy_factor" "$work/err.txt" || fail "guard.energy_factor not named"
box_scene '"stiffness": 2000' '' ', "guard": { "action": "ignore" }'
expect_one_line_error simulate "$work/scene.json" --out "$work/bad" --cache ""
grep -q "guard.action" "$work/err.txt" || fail "guard.action not named"

# A sound resting box (the default contact) is left alone: exit 0, nothing recorded.
box_scene '"stiffness": 2000, "damping": 5' '' ''
"$tool" simulate "$work/scene.json" --out "$work/rest" --cache "" > /dev/null 2> "$work/err.txt" ||
  fail "resting box stopped: $(cat "$work/err.txt")"
[ "$(value "$work/rest/summary.json" runaway_detected)" = False ] || fail "resting box flagged"

# Command-line overrides get the scene keys' ranges.
expect_one_line_error simulate "$work/scene.json" --timestep 5 --out "$work/bad" --cache ""
grep -q -- "--timestep" "$work/err.txt" || fail "--timestep 5 accepted"
expect_one_line_error simulate "$work/scene.json" --stiffness 1e12 --out "$work/bad" --cache ""
grep -q -- "--stiffness" "$work/err.txt" || fail "--stiffness 1e12 accepted"
expect_one_line_error simulate "$work/scene.json" --timestep nan --out "$work/bad" --cache ""
grep -q -- "--timestep" "$work/err.txt" || fail "--timestep nan accepted"
expect_one_line_error simulate "$work/scene.json" --stiffness nan --out "$work/bad" --cache ""
grep -q -- "--stiffness" "$work/err.txt" || fail "--stiffness nan accepted"
echo "ok"
