#!/usr/bin/env bash
# cli.bench_queries: `sdfccd bench queries` writes the CSV contract query,shape,seconds_per_query,hits,queries for
# rayTest and the two sweeps, ours (sdfccd) beside Bullet's btBvhTriangleMeshShape (bvh) of the same mesh, with the same
# hits for rays; bad options fail with one line. Timings are printed, never asserted.
source "$(dirname "$0")/lib.sh"
skip_without bench "built without the bench command"
"$tool" bench --help | grep -q "queries" || { echo "cli.bench_queries: skipped (built without the Bullet plugin)"; exit 0; }

"$tool" bench queries --mesh "$assets/meshes/bunny.off" --resolution 32 --rays 300 --sweeps 10 --repeats 1 \
  --cache "$work/cache" --out "$work/q.csv" > "$work/out.txt" 2> "$work/err.txt" \
  || fail "bench queries failed: $(tail -3 "$work/err.txt")"
head -1 "$work/q.csv" | grep -q "^query,shape,seconds_per_query,hits,queries$" || fail "CSV header: $(head -1 "$work/q.csv")"
[ "$(tail -n +2 "$work/q.csv" | wc -l)" -eq 6 ] || fail "expected 6 rows: $(cat "$work/q.csv")"
awk -F, 'NR > 1 && !($3 > 0 && $4 >= 0) { bad = 1 } END { exit bad }' "$work/q.csv" \
  || fail "a row has a non-positive time: $(cat "$work/q.csv")"
ours=$(awk -F, '$1 == "rayTest" && $2 == "sdfccd" { print $4 }' "$work/q.csv")
bvh=$(awk -F, '$1 == "rayTest" && $2 == "bvh" { print $4 }' "$work/q.csv")
[ -n "$ours" ] && [ "$ours" = "$bvh" ] || fail "ray hits differ: ours $ours, bvh $bvh"
[ "$ours" -gt 50 ] || fail "too few ray hits to mean anything: $ours"
grep -q "ratio" "$work/out.txt" || fail "the table does not print the ratio"

for bad in "--rays 0" "--repeats 0" "--sweeps -1" "--resolution 3"; do
  # shellcheck disable=SC2086
  if "$tool" bench queries --mesh "$assets/meshes/bunny.off" $bad --out "$work/bad.csv" > /dev/null 2> "$work/err.txt"; then
    fail "bench queries $bad succeeded"
  fi
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "bench queries $bad: not one line: $(cat "$work/err.txt")"
  [ ! -e "$work/bad.csv" ] || fail "bench queries $bad left a CSV"
done
echo "cli.bench_queries: ok"
