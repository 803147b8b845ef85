#!/usr/bin/env bash
# Fuzz-style robustness of two readers: the segments file of `sdfccd query` and the haptic scene of `sdfccd haptics`,
# fed truncations, seeded random bytes, byte flips, huge lines and /dev/zero. Every input must end in exit 0 or 1 with
# at most one line on stderr (exactly one on failure) within the time limit: never a crash (a signal), a hang, or memory
# filled.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

# check_run LABEL ARGS...: runs the tool under a 20 s limit and checks the contract above.
cases=0
check_run() {
  local label="$1"
  shift
  timeout 20 "$tool" "$@" > "$work/out.txt" 2> "$work/err.txt"
  local code=$?
  cases=$((cases + 1))
  [ "$code" -eq 0 ] || [ "$code" -eq 1 ] || fail "$label: exit code $code ($(head -c 300 "$work/err.txt"))"
  local lines
  lines="$(wc -l < "$work/err.txt")"
  [ "$lines" -le 1 ] || fail "$label: $lines lines on stderr ($(head -c 300 "$work/err.txt"))"
  [ "$code" -eq 0 ] || [ "$lines" -eq 1 ] || fail "$label: failed without a message"
}

# mutate SRC PREFIX SEEDS: damaged copies PREFIX-<mode>-<seed> of SRC for seeds 1..SEEDS and the modes
# truncate, flip (1-7 random bytes), random (random bytes) and splice (two pieces swapped); one python3 call,
# seeded, so every run tries the same inputs.
mutate() {
  python3 - "$1" "$2" "$3" <<'PY'
import random, sys
src, prefix, seeds = sys.argv[1], sys.argv[2], int(sys.argv[3])
good = open(src, "rb").read()
for seed in range(1, seeds + 1):
    rnd = random.Random(seed)
    versions = {"truncate": good[: rnd.randrange(0, len(good))]}
    data = bytearray(good)
    for _ in range(rnd.randrange(1, 8)):
        data[rnd.randrange(len(data))] = rnd.randrange(256)
    versions["flip"] = bytes(data)
    versions["random"] = bytes(rnd.randrange(256) for _ in range(rnd.randrange(1, 4000)))
    i, j = sorted(rnd.randrange(len(good)) for _ in range(2))
    versions["splice"] = good[:i] + good[j:] + good[i:j]
    for mode, bytes_ in versions.items():
        open("%s-%s-%d" % (prefix, mode, seed), "wb").write(bytes_)
PY
}

# --- segments files -----------------------------------------------------------------------------------------
{
  echo "5 3 3"; echo "0 0 0"; echo "0.5"
  for _ in $(seq 45); do echo "-0.25"; done
} > "$work/field.sdfgen"
cat > "$work/segments.txt" <<'SEG'
# x0,y0,z0,x1,y1,z1[,sigma]
2,0.5,0.5,0,0.5,0.5
0,0,0,2,1,1,0.5
  0.5 , 0.2 , 0.3 , 1.5 , 0.8 , 0.9
1e300,0,0,-1e300,0,0
SEG
check_run "segments: the intact file" query "$work/field.sdfgen" --segments "$work/segments.txt"
mutate "$work/segments.txt" "$work/fuzz-seg" 15
for input in "$work"/fuzz-seg-*; do
  check_run "segments ${input##*/}" query "$work/field.sdfgen" --segments "$input"
done
# Size limits: a 1 MB line, a NUL byte, and /dev/zero (no newline ever) are one-line errors, at once.
head -c 1000000 /dev/zero | tr '\0' '1' > "$work/long.txt"
check_run "segments: 1 MB line" query "$work/field.sdfgen" --segments "$work/long.txt"
grep -q "longer than 4096 bytes" "$work/err.txt" || fail "long line: $(cat "$work/err.txt")"
printf '0,0,0,1,1,1\n0,0\0,0,1,1,1\n' > "$work/nul.txt"
check_run "segments: NUL byte" query "$work/field.sdfgen" --segments "$work/nul.txt"
grep -q "NUL byte" "$work/err.txt" || fail "NUL byte: $(cat "$work/err.txt")"
check_run "segments: /dev/zero" query "$work/field.sdfgen" --segments /dev/zero
grep -q "longer than 4096 bytes" "$work/err.txt" || fail "/dev/zero: $(cat "$work/err.txt")"

# --- haptic scenes ------------------------------------------------------------------------------------------
if "$tool" --help | grep -qE "^ +haptics "; then
  # The plane scene builds nothing, so each case costs only the scene read and a 10 ms virtual session.
  sed -e 's/"points": 1000/"points": 60/' "$assets/scenes/haptics/plane-slide.json" > "$work/haptic.json"
  haptic() { check_run "$1" haptics "$2" --seconds 0.01 --virtual-time --cache ""; }
  haptic "haptic: the intact scene" "$work/haptic.json"
  [ "$(wc -l < "$work/err.txt")" -eq 0 ] || fail "the intact haptic scene failed: $(cat "$work/err.txt")"
  mutate "$work/haptic.json" "$work/fuzz-haptic" 10
  for input in "$work"/fuzz-haptic-*; do
    haptic "haptic ${input##*/}" "$input"
  done
  haptic "haptic: /dev/zero" /dev/zero
  # Absurd values each give one line naming the key.
  bad_haptic() {
    python3 - "$work/haptic.json" "$work/bad.json" "$1" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(scene, open(sys.argv[2], "w"))
PY
    haptic "haptic: $1" "$work/bad.json"
    grep -qF "$2" "$work/err.txt" || fail "haptic $1: error does not name $2: $(cat "$work/err.txt")"
  }
  bad_haptic 'scene["secnds"] = 1' "secnds"
  bad_haptic 'scene["shell"]["pionts"] = 10' "shell.pionts"
  bad_haptic 'scene["shell"]["points"] = 1e12' "shell.points"
  bad_haptic 'scene["shell"]["points"] = 10**20' "shell.points"
  bad_haptic 'scene["shell"]["iterations"] = -3' "shell.iterations"
  bad_haptic 'scene["checks"]["insert"]["axis"] = [0, 0, 0]' "checks.insert.axis must be non-zero"
  bad_haptic 'scene["obstacle"]["plane"]["normal"] = [0, 0, 0]' "obstacle.plane.normal"
  bad_haptic 'scene["seconds"] = 1e9' "seconds"
  bad_haptic 'scene["script"][1]["t"] = -1' "script[1].t"
  bad_haptic 'scene["script"][2]["t"] = 0.1' "script"
  bad_haptic 'scene["obstacle"] = {"spacing": 1e-300, "solids": [{"box": {"center": [0,0,0], "halfExtents": [1,1,1]}}]}' "grid too large"
  bad_haptic 'scene["obstacle"] = {"spacing": 0.1, "paddingCells": 1e12, "solids": [{"box": {"center": [0,0,0], "halfExtents": [1,1,1]}}]}' "obstacle.paddingCells"
  expect_one_line_error haptics "$work/haptic.json" --seconds nan --virtual-time --cache ""
  grep -q -- "--seconds" "$work/err.txt" || fail "--seconds nan: $(cat "$work/err.txt")"
fi
echo "ok ($cases inputs)"
