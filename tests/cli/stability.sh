#!/usr/bin/env bash
# sdfccd simulate on scene files with NaN/inf, zero or negative masses and timesteps, and on bodies whose precomputed
# field or shell holds NaN: each is one line on stderr naming what is wrong, a non-zero exit, and no output file in the
# run folder (frames.csv, summary.json, scene.json are never half-written).
set -euo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"

box='"primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "points": 0, "resolution": 8'
n=0
rejected() {  # rejected SCENE_JSON EXPECTED_WORDS
  n=$((n + 1))
  echo "$1" > "$work/bad$n.json"
  if "$tool" simulate "$work/bad$n.json" --out "$work/run$n" --cache "" > /dev/null 2> "$work/err$n.txt"; then
    fail "accepted: $1"
  fi
  [ "$(wc -l < "$work/err$n.txt")" = 1 ] || fail "error is not one line: $(cat "$work/err$n.txt")"
  grep -q "$2" "$work/err$n.txt" || fail "error does not name '$2': $(cat "$work/err$n.txt")"
  if [ -d "$work/run$n" ] && [ -n "$(find "$work/run$n" -type f)" ]; then
    fail "files left in the run folder for a bad scene: $(find "$work/run$n" -type f)"
  fi
}

# Non-finite numbers: JSON has no NaN or Infinity, and 1e999 overflows a double.
rejected "{ \"timestep\": NaN, \"bodies\": [ { $box, \"mass\": 1 } ] }" "JSON"
rejected "{ \"timestep\": 1e999, \"bodies\": [ { $box, \"mass\": 1 } ] }" "JSON"
rejected "{ \"bodies\": [ { $box, \"mass\": 1, \"position\": [0, Infinity, 0] } ] }" "JSON"
rejected "{ \"bodies\": [ { $box, \"mass\": 1, \"velocity\": [0, -1e400, 0] } ] }" "JSON"
rejected "{ \"bodies\": [ { $box, \"mass\": 1, \"orientation\": [NaN, 0, 0, 0] } ] }" "JSON"
rejected "{ \"gravity\": [0, -Infinity, 0], \"bodies\": [ { $box, \"mass\": 1 } ] }" "JSON"
# Zero and negative masses and timesteps.
rejected "{ \"bodies\": [ { $box, \"mass\": 0 } ] }" "bodies\[0\].mass"
rejected "{ \"bodies\": [ { $box, \"mass\": -2.5 } ] }" "bodies\[0\].mass"
rejected "{ \"bodies\": [ { $box, \"mass\": 1 }, { \"name\": \"light\", $box, \"mass\": -1e-9 } ] }" "bodies\[1\].mass"
rejected "{ \"timestep\": 0, \"bodies\": [ { $box, \"mass\": 1 } ] }" "timestep"
rejected "{ \"timestep\": -0.001, \"bodies\": [ { $box, \"mass\": 1 } ] }" "timestep"
rejected "{ \"contact\": { \"stiffness\": 0 }, \"bodies\": [ { $box, \"mass\": 1 } ] }" "contact.stiffness"
rejected "{ \"contact\": { \"direction\": \"sideways\" }, \"bodies\": [ { $box, \"mass\": 1 } ] }" "shell_normal or field_gradient"

# A body whose precomputed shell or field holds NaN: the loader names the file.
"$tool" build-sdf "$assets/meshes/bunny.off" -o "$work/bunny.sdfgen" -r 8 -p 2 -t 1 > /dev/null 2>&1
"$tool" sample "$assets/meshes/bunny.off" -o "$work/bunny.ply" -n 50 -t 1 > /dev/null 2>&1
sed '12s/^[^ ]*/nan/' "$work/bunny.ply" > "$work/nan.ply"
sed '5s/^[^ ]*/nan/' "$work/bunny.sdfgen" > "$work/nan.sdfgen"
mesh="\"mesh\": \"$assets/meshes/bunny.off\", \"mass\": 1"
rejected "{ \"bodies\": [ { $mesh, \"sdf\": \"$work/bunny.sdfgen\", \"shell\": \"$work/nan.ply\" } ] }" "nan.ply"
rejected "{ \"bodies\": [ { $mesh, \"sdf\": \"$work/nan.sdfgen\", \"shell\": \"$work/bunny.ply\" } ] }" "nan.sdfgen"
# The same files without the NaN are accepted (the cases above fail for the NaN, not for the setup).
echo "{ \"frames\": 3, \"bodies\": [ { $mesh, \"sdf\": \"$work/bunny.sdfgen\", \"shell\": \"$work/bunny.ply\" } ] }" \
  > "$work/good.json"
"$tool" simulate "$work/good.json" --out "$work/good" --cache "" > /dev/null 2> "$work/good-err.txt" ||
  fail "the clean files were rejected: $(cat "$work/good-err.txt")"
[ -s "$work/good/summary.json" ] || fail "no summary for the clean scene"
cat "$work"/err*.txt >&2  # the messages, for the log
echo "ok"
