#!/usr/bin/env bash
# Contract test of `sdfccd haptics`: a short virtual-time session writes ticks.csv and summary.json with the
# required keys; the shrunk peg is stopped by the constraint method with zero penetration; bad input gives a
# one-line error and a non-zero exit, and no output files; the alpha puzzle's test variant runs with both methods.
# Usage: haptics.sh /path/to/sdfccd /path/to/assets
source "$(dirname "$0")/lib.sh"
skip_without haptics "built without the haptics module"

"$tool" haptics "$assets/scenes/haptics/plane-slide.json" --method constraint --seconds 0.2 --virtual-time \
  --out "$work/slide" > "$work/stdout.json" 2> "$work/err.txt" || fail "haptics exited non-zero: $(cat "$work/err.txt")"
[ -f "$work/slide/summary.json" ] || fail "no summary.json"
[ -f "$work/slide/ticks.csv" ] || fail "no ticks.csv"
cmp -s "$work/stdout.json" "$work/slide/summary.json" || fail "stdout differs from summary.json"
for key in method inserted max_penetration_cells tunneled haptic_rate_hz haptic_overruns sim_cycle_p50_ms \
           sim_cycle_p99_ms max_contacts; do
  grep -q "\"$key\":" "$work/slide/summary.json" || fail "summary.json lacks $key"
done
grep -q '"method": "constraint"' "$work/slide/summary.json" || fail "wrong method in summary"
rows=$(($(wc -l < "$work/slide/ticks.csv") - 1))
[ "$rows" -eq 200 ] || fail "expected 200 tick rows, got $rows"
head -1 "$work/slide/ticks.csv" | grep -q '^tick,time,device_x' || fail "bad CSV header"

# The shrunk hole: the constraint method never goes in and never penetrates (virtual time: deterministic).
"$tool" haptics "$assets/scenes/haptics/peg-in-hole-shrunk.json" --method constraint --virtual-time \
  > "$work/shrunk.json" 2> "$work/err.txt" || fail "shrunk run failed: $(cat "$work/err.txt")"
grep -q '"inserted": false' "$work/shrunk.json" || fail "constraint method inserted the peg into the shrunk hole"
grep -q '"max_penetration_cells": 0,' "$work/shrunk.json" || fail "constraint method penetrated"

# The alpha puzzle (test variant): both methods run; the constraint method never penetrates; the field is cached.
for method in constraint penalty; do
  "$tool" haptics "$assets/scenes/haptics/alpha-puzzle-small.json" --method $method --virtual-time --seconds 1.2 \
    --cache "$work/cache" > "$work/alpha-$method.json" 2> "$work/err.txt" || fail "alpha $method failed: $(cat "$work/err.txt")"
  grep -q "\"method\": \"$method\"" "$work/alpha-$method.json" || fail "alpha $method: wrong method"
done
grep -q '"max_penetration_cells": 0,' "$work/alpha-constraint.json" || fail "alpha: constraint method penetrated"
[ "$(ls "$work/cache"/alpha-puzzle-piece-*.sdf | wc -l)" -eq 1 ] || fail "alpha: expected one cached field"

# The benchmark's quick run: the small alpha puzzle and the peg, both methods, one CSV row each.
if "$tool" --help | grep -qE "^ +bench "; then  # builds without the bench command (sanitizers) skip it
  "$tool" bench haptics --quick --assets "$assets" --cache "$work/cache" --out "$work/bench.csv" > "$work/bench.txt" 2> "$work/err.txt" \
    || fail "bench haptics --quick failed: $(cat "$work/err.txt")"
  head -1 "$work/bench.csv" | grep -q '^scene,method,points,sim_cycle_p50_ms,sim_cycle_p99_ms' || fail "bench: bad CSV header"
  [ "$(grep -c '^alpha-puzzle-small,' "$work/bench.csv")" -eq 2 ] || fail "bench: expected 2 alpha rows"
  [ "$(grep -c '^peg-in-hole,' "$work/bench.csv")" -eq 2 ] || fail "bench: expected 2 peg rows"
  grep -q "p99 < 1 ms" "$work/bench.txt" || fail "bench: the paper's target is not printed"
fi

# Errors: one line, non-zero exit, nothing written.
expect_error() {
  local what="$1"; shift
  if "$tool" "$@" > "$work/out.txt" 2> "$work/err.txt"; then fail "$what: exit 0"; fi
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "$what: expected one line on stderr, got: $(cat "$work/err.txt")"
}
expect_error "unknown method" haptics "$assets/scenes/haptics/plane-slide.json" --method springs --out "$work/bad1"
[ ! -e "$work/bad1/summary.json" ] || fail "summary written for a bad method"
expect_error "missing scene" haptics "$work/none.json" --virtual-time
echo '{"obstacle": {"plane": {"normal": [0, 1, 0]}}, "shell": {"shape": "box"}}' > "$work/broken.json"
expect_error "broken scene" haptics "$work/broken.json" --virtual-time --out "$work/bad2"
[ ! -e "$work/bad2/summary.json" ] || fail "summary written for a broken scene"
echo '{"obstacle": ' > "$work/truncated.json"
expect_error "truncated scene" haptics "$work/truncated.json" --virtual-time
echo '{"obstacle": {"mesh": {"procedural": "teapot"}}, "shell": {"shape": "box", "halfExtents": [1, 1, 1]}}' \
  > "$work/teapot.json"
expect_error "unknown procedural mesh" haptics "$work/teapot.json" --virtual-time
expect_error "bad seconds" haptics "$assets/scenes/haptics/plane-slide.json" --seconds -1 --virtual-time
echo '{"obstacle": {"plane": {"normal": [0, 1, 0]}}, "shell": {"shape": "box", "halfExtents": [0.01, 0.01, 0.01],
  "points": 50}, "start": {"position": [0, 0.02, 0]}, "script": [{"t": 0, "position": [0, 0.02, 0]}],
  "guard": {"action": "explode"}}' > "$work/badguard.json"
expect_error "bad guard action" haptics "$work/badguard.json" --virtual-time

# The runaway guard: the sliding box with an absurd penalty stiffness explodes within a few dozen ticks;
# the device renders zero force, the loop stops, one stderr line names the body, exit code 3; the outputs stay.
sed 's/"constraint": {/"penalty": {"stiffness": 1e12}, "constraint": {/' "$assets/scenes/haptics/plane-slide.json" \
  > "$work/exploding.json"
grep -q '"stiffness": 1e12' "$work/exploding.json" || fail "could not make the exploding scene"
for mode in --virtual-time ""; do  # deterministic, then the real-time loop on its own thread
  rc=0
  "$tool" haptics "$work/exploding.json" --method penalty $mode --out "$work/runaway$mode" > "$work/out.txt" \
    2> "$work/err.txt" || rc=$?
  [ "$rc" -eq 3 ] || fail "runaway ($mode): expected exit 3, got $rc: $(cat "$work/err.txt")"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "runaway ($mode): expected one stderr line: $(cat "$work/err.txt")"
  grep -q "body 'simulated object'" "$work/err.txt" || fail "runaway ($mode): the body is not named: $(cat "$work/err.txt")"
  grep -q '"guard_stopped": true' "$work/runaway$mode/summary.json" || fail "runaway ($mode): guard_stopped not set"
  ticks=$(grep -o '"haptic_ticks": [0-9]*' "$work/runaway$mode/summary.json" | grep -o '[0-9]*$')
  [ "$ticks" -lt 1600 ] || fail "runaway ($mode): the loop did not stop ($ticks ticks)"
  # The last tick rendered zero force and torque (columns force_x .. torque_z).
  tail -1 "$work/runaway$mode/ticks.csv" | awk -F, '{ for (i = 17; i <= 22; ++i) if ($i != 0) exit 1 }' \
    || fail "runaway ($mode): the last tick rendered a non-zero wrench: $(tail -1 "$work/runaway$mode/ticks.csv")"
done
# Report instead of stop: the session runs to its end with exit 0 and one line on stderr.
sed 's/"constraint": {/"guard": {"action": "report"}, "constraint": {/' "$work/exploding.json" > "$work/reporting.json"
"$tool" haptics "$work/reporting.json" --method penalty --virtual-time > "$work/out.txt" 2> "$work/err.txt" \
  || fail "report mode exited non-zero: $(cat "$work/err.txt")"
grep -q '"haptic_ticks": 1600,' "$work/out.txt" || fail "report mode: the session did not run to its end"
grep -q "runaway reported" "$work/err.txt" || fail "report mode: no line on stderr"
grep -q '"guard_stopped": false' "$work/out.txt" || fail "report mode: guard_stopped set"
echo "ok"
