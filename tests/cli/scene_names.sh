#!/usr/bin/env bash
# Scene names are data, never paths: without --out, `simulate` writes to out/simulate/<sceneFolderName(name)> under the
# current folder, whatever the scene's "name" holds ("../../x", slashes, a newline, control characters, an empty name),
# and shows control characters as '?'.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"

mkdir -p "$work/a/b"
cd "$work/a/b" || fail "cd"

# run NAME_JSON EXPECTED_FOLDER: runs a tiny scene named NAME_JSON (a JSON string literal) from $work/a/b and
# checks that its run folder is out/simulate/EXPECTED_FOLDER and that nothing else appeared anywhere in $work.
run() {
  cat > "$work/scene.json" <<JSON
{ "name": $1, "timestep": 0.001, "frames": 3,
  "bodies": [ { "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0, "points": 50, "resolution": 8 } ] }
JSON
  "$tool" simulate "$work/scene.json" --cache "" > "$work/out.txt" 2> "$work/err.txt" || fail "name $1 failed: $(cat "$work/err.txt")"
  [ -s "out/simulate/$2/summary.json" ] || fail "name $1: no run folder out/simulate/$2 ($(ls out/simulate))"
  # Exactly one run folder, and nothing outside $work/a/b/out.
  [ "$(ls out/simulate | wc -l)" -eq 1 ] || fail "name $1: more than one run folder: $(ls out/simulate)"
  extra="$(cd "$work" && find . -mindepth 1 -not -path './a' -not -path './a/b' -not -path './a/b/out*' \
           -not -name scene.json -not -name out.txt -not -name err.txt)"
  [ -z "$extra" ] || fail "name $1 wrote outside the run-folder root: $extra"
  # stdout shows the name without control characters: exactly 3 lines (summary, timing, "wrote").
  [ "$(wc -l < "$work/out.txt")" -eq 3 ] || fail "name $1: stdout is not 3 lines: $(cat "$work/out.txt")"
  if [ $# -ge 3 ]; then head -1 "$work/out.txt" | grep -qF "$3:" || fail "name $1 not shown as $3: $(head -1 "$work/out.txt")"; fi
  rm -rf out
}

run '"drop"' 'drop'
run '"../../../x"' '_._.._.._x'
run '"/etc/passwd"' '_etc_passwd'
run '"a\nb"' 'a_b' 'a?b'
run '"a\u001b[31mred"' 'a__31mred' 'a?[31mred'
run '".."' '_.'
run '"."' '_'
run '"spaces and üñí"' 'spaces_and_______'
# An empty name falls back to the file's stem (loadScene), a long one is cut to 64 bytes.
run '""' 'scene'
long="$(printf 'n%.0s' $(seq 1 200))"
run "\"$long\"" "${long:0:64}"

# Errors that quote a name from the file stay one line: control characters are shown as '?'.
cat > "$work/dup.json" <<'JSON'
{ "bodies": [ { "name": "a\nb\u001b[2J", "primitive": { "type": "box" }, "mass": 1.0 },
              { "name": "a\nb\u001b[2J", "primitive": { "type": "box" }, "mass": 1.0 } ] }
JSON
expect_one_line_error simulate "$work/dup.json" --cache ""
grep -qF "repeats 'a?b?[2J'" "$work/err.txt" || fail "duplicate name error: $(cat "$work/err.txt")"
echo "ok"
