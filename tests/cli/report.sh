#!/usr/bin/env bash
# sdfccd report: bad arguments fail before any work with one line; a smoke run of the segments, integration
# and effects sections writes report.md, report.json, CSV and PNG files, and their key numbers are sane
# (the exact segment query misses no first hit, the midpoint error falls with N, effects that are off do no work).
set -euo pipefail
source "$(dirname "$0")/lib.sh"

skip_without report "built without the report command"
sections="segments,integration"
if "$tool" --help | grep -qE "^ +simulate "; then sections="$sections,effects"; fi

# Bad arguments: non-zero exit, one line on stderr, nothing written.
bad() {
  local what="$1"
  shift
  if "$tool" report "$@" > /dev/null 2> "$work/err.txt"; then fail "accepted: $what"; fi
  [ "$(wc -l < "$work/err.txt")" = 1 ] || fail "$what: error is not one line: $(cat "$work/err.txt")"
}
bad "unknown --only id" --smoke --only segments,bogus --out "$work/bad" --assets "$assets"
grep -q "bogus" "$work/err.txt" || fail "the --only error does not name the id: $(cat "$work/err.txt")"
[ ! -e "$work/bad/report.md" ] || fail "report written despite an unknown section"
bad "missing --out" --smoke --only integration --assets "$assets"
touch "$work/file"
bad "unwritable --out" --smoke --only integration --out "$work/file/sub" --assets "$assets"
bad "--threads 0" --smoke --only integration --out "$work/bad" --threads 0 --assets "$assets"
bad "--assets without meshes" --smoke --only integration --out "$work/bad" --assets "$work"

# A section that fails (no bunny mesh, no cache) is reported in report.md and report.json, the others still
# run, and the command exits 1 after writing the report.
mkdir -p "$work/no-bunny/meshes" "$work/no-bunny/scenes"
if "$tool" report --smoke --only segments,integration --out "$work/failed" --assets "$work/no-bunny" --cache "" \
  > /dev/null 2> "$work/err.txt"; then
  fail "a failed section did not make the command fail"
fi
grep -q "FAILED" "$work/failed/report.md" || fail "report.md does not show the failed section"
python3 - "$work/failed/report.json" <<'PY' || fail "report.json of the failed run"
import json, sys
s = {x["id"]: x for x in json.load(open(sys.argv[1]))["sections"]}
assert s["segments"]["failed"] and "error" in s["segments"], s
assert s["integration"]["ok"], s
PY

# The smoke run.
out="$work/report"
"$tool" report --smoke --only "$sections" --out "$out" --assets "$assets" --cache "$work/cache" --threads 2 \
  > "$work/stdout.txt" 2> "$work/stderr.txt" || fail "report failed: $(tail -3 "$work/stderr.txt")"
for f in report.md report.json segments_timing.csv segments_accuracy.csv integration_errors.csv; do
  [ -s "$out/$f" ] || fail "missing $f"
done
pngs="segments_time.png segments_misses.png integration_error.png integration_time.png"
case "$sections" in *effects*) pngs="$pngs effects_step_time.png"; [ -s "$out/effects.csv" ] || fail "effects.csv";; esac
for f in $pngs; do
  [ "$(head -c 4 "$out/$f" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "$f is not a PNG"
  grep -q "($f)" "$out/report.md" || fail "report.md does not link $f"
done
grep -q "^# sdfccd report" "$out/report.md" || fail "report title"
grep -q "Machine: " "$out/report.md" || fail "report names no machine"
grep -q "Mode: smoke" "$out/report.md" || fail "report names no mode"
grep -q "^report \[1/" "$work/stderr.txt" || fail "no progress lines on stderr"

python3 - "$out" "$sections" <<'PY'
import csv, json, sys
out, sections = sys.argv[1], sys.argv[2].split(",")
report = json.load(open(f"{out}/report.json"))
ids = [s["id"] for s in report["sections"]]
assert ids == sections, f"sections {ids} != {sections}"
for s in report["sections"]:
    assert s["ok"] and not s["failed"], f"section {s['id']} not ok"
    assert s["seconds"] > 0

# Segments: the exact query misses and misplaces nothing; the reference finds hits; bisection errs on the
# random field (several roots per cell), so the comparison can see a miss.
rows = list(csv.DictReader(open(f"{out}/segments_accuracy.csv")))
exact = [r for r in rows if r["method"] == "exact"]
assert exact and all(int(r["missed"]) == 0 and int(r["wrong"]) == 0 and int(r["spurious"]) == 0 for r in exact), exact
assert sum(int(r["reference_hits"]) for r in exact) > 100
bis = [r for r in rows if r["method"] == "bisection" and r["set"].startswith("random field")]
assert bis and int(bis[0]["missed"]) + int(bis[0]["wrong"]) > 0, "bisection never erred on the random field"
timing = list(csv.DictReader(open(f"{out}/segments_timing.csv")))
assert all(float(r["us_per_segment_cpu"]) > 0 for r in timing)

# Integration: the midpoint error falls with N on the sphere; the plane is exact for every N.
rows = list(csv.DictReader(open(f"{out}/integration_errors.csv")))
def p95(field, n):
    return float(next(r for r in rows if r["field"] == field and r["kind"] == "all" and int(r["subintervals"]) == n)["impulse_error_p95"])
assert p95("sphere (analytic)", 9) < p95("sphere (analytic)", 5) < p95("sphere (analytic)", 1)
assert p95("sphere (analytic)", 1) > 1e-4
assert all(float(r["impulse_error_max"]) < 1e-9 for r in rows if r["field"].startswith("plane"))

# Effects: an effect that is off did no work; each effect alone did some.
if "effects" in sections:
    names = ["gravity", "ground", "damping", "rotation", "friction"]
    cols = ["gravity", "ground_ccd_queries", "damping_evaluations", "torque_evaluations", "friction_evaluations"]
    runs = {r["run"]: r for r in csv.DictReader(open(f"{out}/effects.csv"))}
    assert set(runs) == {"none", "all"} | {n + " alone" for n in names}, runs.keys()
    for run, r in runs.items():
        on = set(r["effects"].split(";")) if r["effects"] else set()
        for n, c in zip(names, cols):
            if n not in on:
                assert float(r[c]) == 0, f"{n} worked while off in {run}"
            elif run == n + " alone":
                assert float(r[c]) > 0, f"{n} did no work alone"
PY
echo "ok"
