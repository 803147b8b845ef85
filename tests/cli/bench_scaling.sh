#!/usr/bin/env bash
# `sdfccd simulate --threads N` gives the same motion for every N (the parallel narrowphase hands its results to Bullet
# in pair order); a bad value fails with one line; `bench bullet --part scaling --quick` writes its rows (time per body,
# CCD queries, speedups) and its plot, each row the median of --repeat runs.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"
cat > "$work/pile.json" <<'JSON'
{ "timestep": 0.001, "frames": 300, "effects": ["gravity", "ground", "damping", "rotation", "friction"],
  "contact": { "mode": "penalty" },
  "bodies": [
    { "name": "a", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "mass": 1.0,
      "position": [0, 0.06, 0], "points": 200, "resolution": 12 },
    { "name": "b", "primitive": { "type": "box", "half_extents": [0.05, 0.05, 0.05] }, "mass": 1.0,
      "position": [0.02, 0.2, 0], "orientation": [0.95976, 0.19995, 0.099975, 0.169958], "points": 200, "resolution": 12 },
    { "name": "c", "primitive": { "type": "box", "half_extents": [0.05, 0.05, 0.05] }, "mass": 1.0,
      "position": [-0.03, 0.35, 0.01], "orientation": [0.901398, 0.100155, 0.400621, 0.130202], "points": 200, "resolution": 12 } ] }
JSON
for n in 1 2 4; do
  "$tool" simulate "$work/pile.json" --threads "$n" --out "$work/run$n" --cache "" > /dev/null 2> "$work/err$n.txt" ||
    fail "--threads $n failed: $(cat "$work/err$n.txt")"
done
# The motion columns (everything before the timing columns) must match bit for bit.
motion() { python3 -c "
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [i for i, name in enumerate(rows[0]) if name not in ('ccd_seconds', 'step_seconds')]
print('\n'.join(','.join(r[i] for i in keep) for r in rows))" "$1"; }
motion "$work/run1/frames.csv" > "$work/m1.txt"
for n in 2 4; do
  motion "$work/run$n/frames.csv" > "$work/m$n.txt"
  cmp -s "$work/m1.txt" "$work/m$n.txt" || fail "--threads $n moved the bodies differently from --threads 1"
done
grep -q "^300," "$work/m1.txt" || fail "the run did not reach frame 300"
for bad in -1 100000; do  # below 0, and more threads than a pool takes (the thread limit would end the process)
  out=$("$tool" simulate "$work/pile.json" --threads "$bad" --out "$work/bad" --cache "" 2>&1) &&
    fail "--threads $bad accepted"
  [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && printf '%s' "$out" | grep -q -- "--threads" || fail "bad --threads: $out"
done

"$tool" --help | grep -qE "^ +bench " || { echo "ok (bench command not built)"; exit 0; }
"$tool" bench bullet --quick --part scaling --scaling-bodies 3 --repeat 2 --scenes "$assets/scenes" --cache "$work/cache" \
  --out "$work/s.csv" --scaling-plot "$work/s.png" > "$work/bench.txt" 2> "$work/bench_err.txt" ||
  fail "bench failed: $(cat "$work/bench_err.txt")"
for key in wall_ms_per_step_and_body ccd_queries_per_step real_time_factor thread_cpu_seconds batch_share_of_wall; do
  grep -q "^scaling,penalty 1 ms, 2 threads / 3,$key," "$work/s.csv" || fail "scaling CSV lacks $key"
done
grep -q "^scaling,convex hulls 1/240 s (Bullet) / 3,wall_seconds," "$work/s.csv" || fail "no convex-hull row"
grep -q "^scaling,speedup / 3,penalty," "$work/s.csv" || fail "no speedup row"
grep -q "load average" "$work/bench.txt" || fail "the bench does not report the machine's load"
[ -s "$work/s.png" ] || grep -q "no plot" "$work/bench.txt" || fail "no plot and no reason"
"$tool" bench bullet --part scaling --scaling-bodies 0 --out "" > /dev/null 2>&1 && fail "--scaling-bodies 0 accepted"
# --repeat: every world twice, in turns, each row the median run; progress on stderr; 0 is refused in one line.
grep -q "median of 2 runs" "$work/bench.txt" || fail "the bench does not say its rows are medians of 2 runs"
grep -q "^scaling,3 bunnies,runs_per_row,2$" "$work/s.csv" || fail "scaling CSV lacks runs_per_row"
grep -q "round 2 of 2" "$work/bench_err.txt" || fail "no progress of the repeats on stderr"
out=$("$tool" bench bullet --part scaling --repeat 0 --out "" 2>&1) && fail "--repeat 0 accepted"
[ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && printf '%s' "$out" | grep -q -- "--repeat" || fail "bad --repeat: $out"
echo "ok"
