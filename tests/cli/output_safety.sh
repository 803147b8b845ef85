#!/usr/bin/env bash
# How every command writes its outputs: an output that is an input is refused before any work; /dev/null, a FIFO and
# stdout are written in place; a link planted at a temporary name is never followed, a link the user names is; modes are
# kept; SIGTERM leaves no temporary file and no empty run folder; --record-every thins frames.csv; body names with
# commas survive the CSV.
# Usage: output_safety.sh /path/to/sdfccd /path/to/assets
source "$(dirname "$0")/lib.sh"

# An error: non-zero status, one line on stderr naming $1.
expect_refused() {
  local name="$1"
  shift
  expect_one_line_error "$@"
  grep -qF "$name" "$work/err.txt" || fail "error does not name $name: $(cat "$work/err.txt")"
  return 0
}
# No temporary file anywhere under the work folder.
no_temporaries() { ! find "$work" -name '*.tmp-*' ! -type l | grep -q . || fail "temporary file left: $1"; }

case "$tool" in /*) ;; *) tool="$PWD/$tool" ;; esac  # this script works inside $work
cd "$work" || fail "cd"
write_tet_off tet.off
cp tet.off tet.orig
"$tool" build-sdf tet.off -r 8 -p 2 -o ref.sdf >/dev/null 2>&1 || fail "reference build failed"

# 1. An output that is one of the inputs: refused, the input unchanged (also through a link, a hard link).
expect_refused tet.off build-sdf tet.off -r 8 -o tet.off
cmp -s tet.off tet.orig || fail "build-sdf -o MESH changed the mesh"
ln -s tet.off tet-link.off
expect_refused tet-link.off build-sdf tet.off -r 8 -o tet-link.off
ln tet.off tet-hard.off
expect_refused tet-hard.off build-sdf tet.off -r 8 -o tet-hard.off
cmp -s tet.off tet.orig || fail "build-sdf through a link changed the mesh"
cp ref.sdf a.sdf
expect_refused a.sdf convert a.sdf a.sdf
cmp -s a.sdf ref.sdf || fail "convert a.sdf a.sdf changed it"
"$tool" sample tet.off --vertices -o tet.ply >/dev/null 2>&1 || fail "sample to PLY failed"
cp tet.ply tet-ply.orig
expect_refused tet.ply sample tet.ply --vertices -o tet.ply
cmp -s tet.ply tet-ply.orig || fail "sample m.ply -o m.ply changed it"
cp ref.sdf b.sdf
"$tool" convert b.sdf - >>b.sdf 2>"$work/err.txt" && fail "convert b.sdf - >> b.sdf accepted"
grep -q "standard output" "$work/err.txt" || fail "stdout that is the input: $(cat "$work/err.txt")"
cmp -s b.sdf ref.sdf || fail "convert b.sdf - >> b.sdf changed it"
no_temporaries "refusals"

# 2. Non-regular targets are written in place.
"$tool" build-sdf tet.off -r 8 -p 2 -o /dev/null >/dev/null 2>&1 || fail "-o /dev/null failed"
[ -c /dev/null ] || fail "/dev/null is no longer a character device"
mkfifo field.fifo
cat field.fifo >from-fifo.sdf &
reader=$!
"$tool" build-sdf tet.off -r 8 -p 2 -o field.fifo >/dev/null 2>&1 || fail "-o FIFO failed"
wait "$reader"
[ -p field.fifo ] || fail "the FIFO was replaced"
cmp -s from-fifo.sdf ref.sdf || fail "the FIFO did not carry the field"
"$tool" build-sdf tet.off -r 8 -p 2 -o - >from-stdout.sdf 2>stdout-report.txt || fail "-o - failed"
cmp -s from-stdout.sdf ref.sdf || fail "-o - did not write the field on stdout"
grep -q dimensions stdout-report.txt || fail "-o -: the report did not go to stderr"

# 3. A link planted at a predictable temporary name (the target's name, ".tmp-", the pid, a counter) is not followed.
echo precious >victim.txt
bash -c 'ln -s victim.txt o.sdf.tmp-$$-0; ln -s victim.txt o.sdf.tmp-$$-1; exec "$0" build-sdf tet.off -r 8 -p 2 -o o.sdf' \
  "$tool" >/dev/null 2>&1 || fail "build-sdf with planted links failed"
[ "$(cat victim.txt)" = precious ] || fail "the planted link redirected the write"
cmp -s o.sdf ref.sdf || fail "o.sdf is not the field"
[ "$(find . -maxdepth 1 -name 'o.sdf.tmp-*' | wc -l)" -eq 2 ] || fail "planted links were touched"

# 4. A link the user names is followed (cp semantics); the target's mode is kept.
mkdir real
ln -s real/target.sdf named-link.sdf
"$tool" build-sdf tet.off -r 8 -p 2 -o named-link.sdf >/dev/null 2>&1 || fail "build-sdf through a named link"
[ -L named-link.sdf ] || fail "the named link was replaced"
cmp -s real/target.sdf ref.sdf || fail "the link's target was not written"
: >private.sdf
chmod 600 private.sdf
"$tool" build-sdf tet.off -r 8 -p 2 -o private.sdf >/dev/null 2>&1 || fail "build-sdf over a 0600 file"
[ "$(stat -c %a private.sdf)" = 600 ] || fail "mode 0600 became $(stat -c %a private.sdf)"
no_temporaries "writes"

if ! "$tool" --help | grep -qE "^ +simulate "; then
  echo "output_safety: simulate checks skipped (built without the Bullet plugin)"
  exit 0
fi

# 5. A run that fails after its folder was made leaves no empty folder.
cat >bad.json <<'JSON'
{ "bodies": [ { "name": "b", "mesh": "nowhere.off", "mass": 1 } ] }
JSON
"$tool" simulate bad.json --out deep/er/run --cache "" >/dev/null 2>&1 && fail "bad scene accepted"
[ ! -e deep ] || fail "a failed run left the folders it made"

# 6. SIGTERM during a long run: the process ends by the signal, no temporary file, no empty run folder.
cat >long.json <<'JSON'
{ "timestep": 0.001, "frames": 100000000, "effects": ["gravity", "ground"],
  "bodies": [ { "name": "box", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "mass": 1.0,
                "position": [0, 0.06, 0], "points": 50, "resolution": 8 } ] }
JSON
"$tool" simulate long.json --out long/run --cache "" >/dev/null 2>&1 &
sim=$!
for _ in $(seq 1 200); do
  ls long/run/frames.csv.tmp-* >/dev/null 2>&1 && break
  sleep 0.1
done
ls long/run/frames.csv.tmp-* >/dev/null 2>&1 || fail "the long run never started writing frames.csv"
sleep 0.3
kill -TERM "$sim"
wait "$sim"
status=$?
[ "$status" -eq 143 ] || fail "simulate did not end by SIGTERM (status $status)"
[ ! -e long ] || fail "SIGTERM left $(find long | tr '\n' ' ')"

# 7. --record-every K: every K-th frame and the last; K < 1 is refused.
cat >drop.json <<'JSON'
{ "timestep": 0.001, "frames": 95, "effects": ["gravity", "ground"],
  "bodies": [ { "name": "a,b \"quoted\"", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] },
                "mass": 1.0, "position": [0, 0.06, 0], "points": 50, "resolution": 8 } ] }
JSON
"$tool" simulate drop.json --out thin --record-every 10 --cache "" >/dev/null 2>&1 || fail "--record-every 10"
[ "$(tail -n +2 thin/frames.csv | cut -d, -f1 | tr '\n' ' ')" = "10 20 30 40 50 60 70 80 90 95 " ] ||
  fail "--record-every 10 rows: $(tail -n +2 thin/frames.csv | cut -d, -f1 | tr '\n' ' ')"
expect_refused record-every simulate drop.json --out thin0 --record-every 0 --cache ""

# 8. A body name with a comma and quotes is one quoted CSV field, and the run reads back.
python3 - thin/frames.csv <<'PY' || fail "frames.csv header is not proper CSV"
import csv, sys
header = next(csv.reader(open(sys.argv[1])))
assert header[2] == 'a,b "quoted".px', header[:4]
PY
out="$("$tool" render thin --size 64x48 --every 50 --sheet-cells 0 --no-video 2>&1)"
if ! echo "$out" | grep -q "built without the renderer"; then
  [ -f thin/frames/frame_00050.png ] || fail "render of a quoted body name: $out"
fi
if command -v gnuplot >/dev/null 2>&1; then
  # Also: gnuplot never writes at a predictable name beside the plots.
  mkdir -p thin/plots
  ln -s ../../victim.txt thin/plots/penetration.png.tmp-gnuplot
  "$tool" plot thin --size 200x120 >/dev/null 2>"$work/err.txt" || fail "plot of a quoted body name: $(cat "$work/err.txt")"
  [ "$(cat victim.txt)" = precious ] || fail "gnuplot wrote through a planted link"
  [ "$(png_size thin/plots/penetration.png)" = 200x120 ] || fail "plot size"
fi
no_temporaries "runs"
echo "output_safety: all checks passed"
