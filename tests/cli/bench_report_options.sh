#!/usr/bin/env bash
# `sdfccd bench ...` and `sdfccd report`: their model cache defaults to $XDG_CACHE_HOME/sdfccd like simulate's (never
# ./out/cache), --cache overrides it, an unwritable cache fails at once; a bogus method, an empty list and a zero or
# negative count are each a one-line error with a non-zero exit and no output, instead of an empty CSV or a silent
# default.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without bench "built without the bench command"
bunny="$assets/meshes/bunny.off"
mkdir -p "$work/cwd"
cd "$work/cwd" || fail "cd"

# Bad options: each a one-line error, non-zero exit, no CSV written.
bad() {
  local what="$1"; shift
  expect_one_line_error "$@"
  [ ! -e "$work/bad.csv" ] || fail "$what: wrote a CSV"
}
bad "unknown method" bench segments --quick --mesh "$bunny" --method bogus --out "$work/bad.csv"
grep -q -- "--method" "$work/err.txt" || fail "the --method error does not name the option: $(cat "$work/err.txt")"
bad "unknown octree mode" bench segments --quick --mesh "$bunny" --octree bogus --out "$work/bad.csv"
bad "zero segments" bench segments --quick --mesh "$bunny" --segments 0 --out "$work/bad.csv"
bad "negative segments" bench segments --quick --mesh "$bunny" --segments -3 --out "$work/bad.csv"
grep -q -- "--segments" "$work/err.txt" || fail "the --segments error does not name the option: $(cat "$work/err.txt")"
bad "zero configs" bench tree --quick --configs 0 --out "$work/bad.csv"
bad "negative resolution" bench tree --quick --resolution -64 --out "$work/bad.csv"
bad "zero dragon points" bench tree --quick --dragon-points 0 --out "$work/bad.csv"
bad "empty model list" bench tree --quick --models '' --out "$work/bad.csv"
bad "negative sdf threads" bench sdf --quick --threads -1 --out "$work/bad.csv"
bad "empty point list" bench haptics --quick --points '' --out "$work/bad.csv"
bad "zero haptic seconds" bench haptics --quick --seconds 0 --out "$work/bad.csv"
bad "NaN haptic seconds" bench haptics --quick --seconds nan --out "$work/bad.csv"
bad "empty --only" report --smoke --only '' --out "$work/bad-report" --assets "$assets"
grep -q -- "--only" "$work/err.txt" || fail "the --only error does not name the option: $(cat "$work/err.txt")"
[ ! -e "$work/bad-report" ] || fail "empty --only: made the report folder"
if "$tool" --help | grep -qE "^ +simulate "; then  # --timestep on the command line: the scene file's range
  expect_one_line_error simulate "$assets/scenes/$(ls "$assets/scenes" | grep '\.json$' | head -1)" --timestep 5 \
    --out "$work/bad-run"
  grep -q -- "--timestep" "$work/err.txt" || fail "the --timestep error does not name the option"
fi

# The default cache is $XDG_CACHE_HOME/sdfccd for report and bench alike (here a report section builds
# the bunny fields, then the benchmark loads them from there), and nothing is written under ./out.
"$tool" report --smoke --only segments --out "$work/report" --assets "$assets" > /dev/null 2> "$work/err.txt" ||
  fail "report: $(cat "$work/err.txt")"
ls "$XDG_CACHE_HOME/sdfccd"/bunny_*_pad0.sdf > /dev/null 2>&1 || fail "report: no field in \$XDG_CACHE_HOME/sdfccd"
"$tool" bench segments --quick --mesh "$bunny" --segments 100 --method exact --octree off --out "$work/s.csv" \
  > "$work/bench.txt" 2> "$work/err.txt" || fail "bench segments: $(cat "$work/err.txt")"
grep -qF "loading $XDG_CACHE_HOME/sdfccd/bunny_64_pad0.sdf" "$work/bench.txt" ||
  fail "bench segments did not use the default cache: $(cat "$work/bench.txt")"
[ "$(wc -l < "$work/s.csv")" -gt 1 ] || fail "bench segments: no CSV rows"
[ ! -e out ] || fail "wrote ./out under the current folder"

# --cache DIR overrides the default.
mkdir -p "$work/mine"
cp "$XDG_CACHE_HOME/sdfccd"/bunny_*_pad0.sdf "$work/mine/"
"$tool" bench segments --quick --mesh "$bunny" --segments 100 --method exact --octree off --cache "$work/mine" \
  --out "$work/s2.csv" > "$work/bench.txt" 2> "$work/err.txt" || fail "bench --cache: $(cat "$work/err.txt")"
grep -qF "loading $work/mine/bunny_64_pad0.sdf" "$work/bench.txt" || fail "--cache DIR not used: $(cat "$work/bench.txt")"

# An unwritable cache fails before any work, one line naming it (bench and report).
echo x > "$work/not-a-folder"
expect_one_line_error bench segments --quick --mesh "$bunny" --cache "$work/not-a-folder/cache" --out "$work/bad.csv"
grep -qF "$work/not-a-folder/cache" "$work/err.txt" || fail "bench: the error does not name the cache"
[ ! -e "$work/bad.csv" ] || fail "bench: wrote a CSV despite the cache error"
expect_one_line_error report --smoke --only segments --out "$work/bad-report" --assets "$assets" \
  --cache "$work/not-a-folder/cache"
grep -qF "$work/not-a-folder/cache" "$work/err.txt" || fail "report: the error does not name the cache"
echo "ok"
