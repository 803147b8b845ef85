#!/usr/bin/env bash
# Contract test of `sdfccd haptics`: a short virtual-time session writes ticks.csv and summary.json with the
# required keys; the shrunk peg is stopped by the constraint method with zero penetration; bad input gives a
# one-line error and a non-zero exit, and no output files; the alpha puzzle's test variant runs with both methods.
# Usage: haptics.sh /path/to/sdfccd /path/to/assets
set -u
SDFCCD="$1"
ASSETS="$2"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
if ! "$SDFCCD" --help | grep -qE "^ +haptics "; then echo "skipped: built without the haptics module"; exit 0; fi

"$SDFCCD" haptics "$ASSETS/scenes/haptics/plane-slide.json" --method constraint --seconds 0.2 --virtual-time \
  --out "$WORK/slide" > "$WORK/stdout.json" 2> "$WORK/err.txt" || fail "haptics exited non-zero: $(cat "$WORK/err.txt")"
[ -f "$WORK/slide/summary.json" ] || fail "no summary.json"
[ -f "$WORK/slide/ticks.csv" ] || fail "no ticks.csv"
cmp -s "$WORK/stdout.json" "$WORK/slide/summary.json" || fail "stdout differs from summary.json"
for key in method inserted max_penetration_cells tunneled haptic_rate_hz haptic_overruns sim_cycle_p50_ms \
           sim_cycle_p99_ms max_contacts; do
  grep -q "\"$key\":" "$WORK/slide/summary.json" || fail "summary.json lacks $key"
done
grep -q '"method": "constraint"' "$WORK/slide/summary.json" || fail "wrong method in summary"
rows=$(($(wc -l < "$WORK/slide/ticks.csv") - 1))
[ "$rows" -eq 200 ] || fail "expected 200 tick rows, got $rows"
head -1 "$WORK/slide/ticks.csv" | grep -q '^tick,time,device_x' || fail "bad CSV header"

# The shrunk hole: the constraint method never goes in and never penetrates (virtual time: deterministic).
"$SDFCCD" haptics "$ASSETS/scenes/haptics/peg-in-hole-shrunk.json" --method constraint --virtual-time \
  > "$WORK/shrunk.json" 2> "$WORK/err.txt" || fail "shrunk run failed: $(cat "$WORK/err.txt")"
grep -q '"inserted": false' "$WORK/shrunk.json" || fail "constraint method inserted the peg into the shrunk hole"
grep -q '"max_penetration_cells": 0,' "$WORK/shrunk.json" || fail "constraint method penetrated"

# The alpha puzzle (test variant): both methods run; the constraint method never penetrates; the field is cached.
for method in constraint penalty; do
  "$SDFCCD" haptics "$ASSETS/scenes/haptics/alpha-puzzle-small.json" --method $method --virtual-time --seconds 1.2 \
    --cache "$WORK/cache" > "$WORK/alpha-$method.json" 2> "$WORK/err.txt" || fail "alpha $method failed: $(cat "$WORK/err.txt")"
  grep -q "\"method\": \"$method\"" "$WORK/alpha-$method.json" || fail "alpha $method: wrong method"
done
grep -q '"max_penetration_cells": 0,' "$WORK/alpha-constraint.json" || fail "alpha: constraint method penetrated"
[ "$(ls "$WORK/cache"/alpha-puzzle-piece-*.sdf | wc -l)" -eq 1 ] || fail "alpha: expected one cached field"

# The benchmark's quick run: the small alpha puzzle and the peg, both methods, one CSV row each.
"$SDFCCD" bench haptics --quick --cache "$WORK/cache" --out "$WORK/bench.csv" > "$WORK/bench.txt" 2> "$WORK/err.txt" \
  || fail "bench haptics --quick failed: $(cat "$WORK/err.txt")"
head -1 "$WORK/bench.csv" | grep -q '^scene,method,points,sim_cycle_p50_ms,sim_cycle_p99_ms' || fail "bench: bad CSV header"
[ "$(grep -c '^alpha-puzzle-small,' "$WORK/bench.csv")" -eq 2 ] || fail "bench: expected 2 alpha rows"
[ "$(grep -c '^peg-in-hole,' "$WORK/bench.csv")" -eq 2 ] || fail "bench: expected 2 peg rows"
grep -q "p99 < 1 ms" "$WORK/bench.txt" || fail "bench: the paper's target is not printed"

# Errors: one line, non-zero exit, nothing written.
expect_error() {
  local what="$1"; shift
  if "$SDFCCD" "$@" > "$WORK/out.txt" 2> "$WORK/err.txt"; then fail "$what: exit 0"; fi
  [ "$(wc -l < "$WORK/err.txt")" -eq 1 ] || fail "$what: expected one line on stderr, got: $(cat "$WORK/err.txt")"
}
expect_error "unknown method" haptics "$ASSETS/scenes/haptics/plane-slide.json" --method springs --out "$WORK/bad1"
[ ! -e "$WORK/bad1/summary.json" ] || fail "summary written for a bad method"
expect_error "missing scene" haptics "$WORK/none.json" --virtual-time
echo '{"obstacle": {"plane": {"normal": [0, 1, 0]}}, "shell": {"shape": "box"}}' > "$WORK/broken.json"
expect_error "broken scene" haptics "$WORK/broken.json" --virtual-time --out "$WORK/bad2"
[ ! -e "$WORK/bad2/summary.json" ] || fail "summary written for a broken scene"
echo '{"obstacle": ' > "$WORK/truncated.json"
expect_error "truncated scene" haptics "$WORK/truncated.json" --virtual-time
echo '{"obstacle": {"mesh": {"procedural": "teapot"}}, "shell": {"shape": "box", "halfExtents": [1, 1, 1]}}' \
  > "$WORK/teapot.json"
expect_error "unknown procedural mesh" haptics "$WORK/teapot.json" --virtual-time
expect_error "bad seconds" haptics "$ASSETS/scenes/haptics/plane-slide.json" --seconds -1 --virtual-time
echo "ok"
