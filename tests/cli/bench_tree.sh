#!/usr/bin/env bash
# cli.bench_tree: `sdfccd bench tree --quick` (a small version of the paper's Table 3) writes the CSV contract
# model,points,configs,linear_s,tree_s,speedup (+ query, linear_cut_s, the paper's times) with the tree's answers
# checked against the linear ones inside the benchmark (it exits non-zero when they differ); bad options fail
# with one line. Timings are printed, never asserted.
source "$(dirname "$0")/lib.sh"
skip_without bench "built without the bench command"

"$tool" bench tree --quick --models bunny,bowl --configs 20 --assets "$assets" --out "$work/t3.csv" \
  > "$work/out.txt" 2> "$work/err.txt" || fail "bench tree --quick failed: $(tail -3 "$work/err.txt")"
head -1 "$work/t3.csv" | grep -q "^model,points,configs,linear_s,tree_s,speedup," || fail "CSV header: $(head -1 "$work/t3.csv")"
# Two models x two queries (all, earliest-one), each with positive times and 20 configurations.
[ "$(tail -n +2 "$work/t3.csv" | wc -l)" -eq 4 ] || fail "expected 4 rows: $(cat "$work/t3.csv")"
awk -F, 'NR > 1 && !($3 == 20 && $4 > 0 && $5 > 0 && $6 > 0) { bad = 1 } END { exit bad }' "$work/t3.csv" \
  || fail "a row has a non-positive time or the wrong count: $(cat "$work/t3.csv")"
grep -q "^bunny,777,20,.*,all," "$work/t3.csv" || fail "no bunny 'all' row"
grep -q "^bowl,2072,20,.*,earliest-one," "$work/t3.csv" || fail "no bowl 'earliest-one' row"
grep -q "paper" "$work/out.txt" || fail "the table does not show the paper's figures"

# Bad options: one line on stderr, non-zero exit, no CSV.
for bad in "--query sideways" "--resolution 3" "--models teapot" "--cull-lipschitz -1"; do
  # shellcheck disable=SC2086
  if "$tool" bench tree --quick --configs 2 --assets "$assets" $bad --out "$work/bad.csv" > /dev/null 2> "$work/err.txt"; then
    fail "bench tree $bad succeeded"
  fi
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "bench tree $bad: not one line: $(cat "$work/err.txt")"
  [ ! -e "$work/bad.csv" ] || fail "bench tree $bad left a CSV"
done
echo "cli.bench_tree: ok"
