#!/usr/bin/env bash
# The model cache: simulate and haptics cache in $XDG_CACHE_HOME/sdfccd (else ~/.cache/sdfccd), never in the current
# folder; --cache DIR overrides; an unwritable cache fails at once with one line naming it; a damaged entry is reported
# (one line naming the file), rebuilt, and the run succeeds.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"
write_tet_off "$work/tet.off"
cat > "$work/scene.json" <<JSON
{ "timestep": 0.001, "frames": 5,
  "bodies": [ { "name": "tet", "mesh": "$work/tet.off", "mass": 1.0, "points": 30, "resolution": 8 } ] }
JSON
mkdir -p "$work/cwd"
cd "$work/cwd" || fail "cd"

# Default: entries under $XDG_CACHE_HOME/sdfccd, nothing under ./out/cache.
"$tool" simulate "$work/scene.json" --out "$work/run1" > /dev/null 2> "$work/err.txt" || fail "run: $(cat "$work/err.txt")"
ls "$XDG_CACHE_HOME/sdfccd"/tet-*.sdf > /dev/null 2>&1 || fail "no field entry in \$XDG_CACHE_HOME/sdfccd"
ls "$XDG_CACHE_HOME/sdfccd"/tet-*.ply > /dev/null 2>&1 || fail "no shell entry in \$XDG_CACHE_HOME/sdfccd"
[ ! -e out ] || fail "wrote ./out under the current folder"

# Without XDG_CACHE_HOME: ~/.cache/sdfccd.
HOME="$work/home" XDG_CACHE_HOME= "$tool" simulate "$work/scene.json" --out "$work/run2" > /dev/null 2>&1 ||
  fail "run with HOME"
ls "$work/home/.cache/sdfccd"/tet-*.sdf > /dev/null 2>&1 || fail "no entry in ~/.cache/sdfccd"

# --cache overrides; --cache "" writes no cache at all.
"$tool" simulate "$work/scene.json" --out "$work/run3" --cache "$work/mine" > /dev/null 2>&1 || fail "--cache DIR"
ls "$work/mine"/tet-*.sdf > /dev/null 2>&1 || fail "--cache DIR not used"
before="$(find "$work" -name 'tet-*' | wc -l)"
"$tool" simulate "$work/scene.json" --out "$work/run4" --cache "" > /dev/null 2>&1 || fail "--cache ''"
[ "$(find "$work" -name 'tet-*' | wc -l)" = "$before" ] || fail "--cache '' wrote a cache entry"

# An unwritable cache (here a file where the folder should be) fails before any work, one line naming it.
echo x > "$work/not-a-folder"
expect_one_line_error simulate "$work/scene.json" --out "$work/run5" --cache "$work/not-a-folder/cache"
grep -qF "cache folder '$work/not-a-folder/cache'" "$work/err.txt" || fail "error does not name the cache: $(cat "$work/err.txt")"
[ ! -e "$work/run5" ] || fail "run folder left by the cache error"

# A damaged entry: reported with one line naming the file, rebuilt (the run succeeds, same result), rewritten.
entry="$(ls "$work/mine"/tet-*.sdf)"
"$tool" simulate "$work/scene.json" --out "$work/run3b" --cache "$work/mine" > /dev/null 2>&1 || fail "cached run"
good_hash="$(python3 -c "import json; print(json.load(open('$work/run3b/summary.json'))['result_hash'])")"
for damage in truncate garbage; do
  if [ $damage = truncate ]; then head -c 20 "$entry" > "$work/cut" && cp "$work/cut" "$entry"; else
    head -c 5000 /dev/urandom > "$entry"; fi
  "$tool" simulate "$work/scene.json" --out "$work/run-$damage" --cache "$work/mine" > /dev/null 2> "$work/err.txt" ||
    fail "$damage entry: run failed: $(cat "$work/err.txt")"
  [ "$(grep -c "damaged cache entry '$entry'" "$work/err.txt")" = 1 ] || fail "$damage entry not reported: $(cat "$work/err.txt")"
  hash="$(python3 -c "import json; print(json.load(open('$work/run-$damage/summary.json'))['result_hash'])")"
  [ "$hash" = "$good_hash" ] || fail "$damage entry: different result ($hash vs $good_hash)"
  "$tool" simulate "$work/scene.json" --out "$work/run-again" --cache "$work/mine" > /dev/null 2> "$work/err.txt"
  [ ! -s "$work/err.txt" ] || fail "$damage entry not rewritten: $(cat "$work/err.txt")"
  rm -rf "$work/run-again"
done

# haptics: the same default and check.
if "$tool" --help | grep -qE "^ +haptics "; then
  expect_one_line_error haptics "$assets/scenes/haptics/plane-slide.json" --seconds 0.01 --virtual-time \
    --cache "$work/not-a-folder/cache"
  grep -qF "cache folder" "$work/err.txt" || fail "haptics: cache error $(cat "$work/err.txt")"
fi
echo "ok"
