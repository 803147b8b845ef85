#!/usr/bin/env bash
# Contract test of `sdfccd build-sdf`, `info` and `convert`: outputs, format selection, round trips, and
# one-line errors with a non-zero status and no output file for every kind of bad input.
# Usage: sdf_commands.sh /path/to/sdfccd /path/to/assets
set -u
SDFCCD="$1"
ASSETS="$2"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# An error: non-zero status, exactly one line on stderr, and the named output file absent.
expect_error() {
  local output="$1"
  shift
  "$SDFCCD" "$@" >"$WORK/out.txt" 2>"$WORK/err.txt" && fail "accepted: $*"
  [ "$(wc -l <"$WORK/err.txt")" -eq 1 ] || fail "not one line of stderr for: $* ($(cat "$WORK/err.txt"))"
  if [ -n "$output" ] && [ -e "$output" ]; then fail "output left behind by: $*"; fi
  ls "$WORK" | grep -q "\.tmp-" && fail "temporary file left behind by: $*"
  return 0
}

# A tetrahedron in OFF, small enough to build instantly.
cat >"$WORK/tet.off" <<'MESH'
OFF
4 4 0
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
MESH

"$SDFCCD" build-sdf "$WORK/tet.off" --resolution 8 --padding 2 -o "$WORK/tet.sdf" >"$WORK/build.txt" 2>"$WORK/err.txt" \
  || fail "build-sdf failed: $(cat "$WORK/err.txt")"
for word in dimensions spacing "build time" memory repairs "sign method"; do
  grep -q "$word" "$WORK/build.txt" || fail "build-sdf output lacks '$word'"
done
grep -q "13 x 13 x 13 nodes" "$WORK/build.txt" || fail "unexpected dimensions: $(grep dimensions "$WORK/build.txt")"
grep -q "pseudonormal" "$WORK/build.txt" || fail "closed mesh not signed by pseudonormals"
head -c 6 "$WORK/tet.sdf" | grep -q "sdfccd" || fail "default output is not native"

"$SDFCCD" info "$WORK/tet.sdf" >"$WORK/info.txt" || fail "info failed"
for word in dimensions box spacing values memory; do grep -q "$word" "$WORK/info.txt" || fail "info lacks '$word'"; done
grep -q "13 x 13 x 13 nodes" "$WORK/info.txt" || fail "info dimensions"

# Native -> SDFGen (by extension) -> native (by --format): identical files.
"$SDFCCD" convert "$WORK/tet.sdf" "$WORK/tet.sdfgen" >/dev/null || fail "convert to sdfgen"
[ "$(head -n 1 "$WORK/tet.sdfgen")" = "13 13 13" ] || fail "SDFGen header: $(head -n 1 "$WORK/tet.sdfgen")"
[ "$(wc -l <"$WORK/tet.sdfgen")" -eq $((3 + 13 * 13 * 13)) ] || fail "SDFGen line count"
"$SDFCCD" convert "$WORK/tet.sdfgen" "$WORK/back.bin" --format native >/dev/null || fail "convert back"
cmp -s "$WORK/tet.sdf" "$WORK/back.bin" || fail "native -> sdfgen -> native is not identical"
"$SDFCCD" build-sdf "$WORK/tet.off" -r 8 -p 2 --format sdfgen -o "$WORK/forced.sdf" >/dev/null || fail "--format sdfgen"
cmp -s "$WORK/forced.sdf" "$WORK/tet.sdfgen" || fail "--format sdfgen differs from the converted file"
"$SDFCCD" info "$WORK/tet.sdfgen" | grep -q "13 x 13 x 13" || fail "info on SDFGen"

# The bundled open mesh builds and is signed by winding numbers.
"$SDFCCD" build-sdf "$ASSETS/meshes/mech-holes-shark.off" -r 12 -p 1 -o "$WORK/shark.sdf" >"$WORK/shark.txt" \
  || fail "shark build failed"
grep -q "winding-number" "$WORK/shark.txt" || fail "open mesh not signed by winding numbers"
grep -q "open (" "$WORK/shark.txt" || fail "open mesh not reported open"

# Errors.
expect_error "$WORK/x.sdf" build-sdf "$WORK/missing.off" -r 8 -o "$WORK/x.sdf"
: >"$WORK/empty.off"
expect_error "$WORK/x.sdf" build-sdf "$WORK/empty.off" -r 8 -o "$WORK/x.sdf"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n' >"$WORK/flat.off"
expect_error "$WORK/x.sdf" build-sdf "$WORK/flat.off" -r 8 -o "$WORK/x.sdf"
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r 0 -o "$WORK/x.sdf"
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r 100000 -o "$WORK/x.sdf"
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r 8 -p -1 -o "$WORK/x.sdf"
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r 4000 -p 0 -o "$WORK/x.sdf" --max-memory 100
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r 8 --threads -3 -o "$WORK/x.sdf"
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r 8 --format vtk -o "$WORK/x.sdf"
expect_error "$WORK/x.sdf" build-sdf "$WORK/tet.off" -r abc -o "$WORK/x.sdf"
expect_error "" build-sdf "$WORK/tet.off" -r 8 -o "$WORK/no/such/dir/x.sdf"
expect_error "" info "$WORK/missing.sdf"
head -c 100 "$WORK/tet.sdf" >"$WORK/truncated.sdf"
expect_error "" info "$WORK/truncated.sdf"
head -n 100 "$WORK/tet.sdfgen" >"$WORK/truncated.sdfgen"
expect_error "" info "$WORK/truncated.sdfgen"
head -c 3000 /dev/urandom >"$WORK/random.sdf" 2>/dev/null || dd if=/dev/urandom of="$WORK/random.sdf" bs=1000 count=3 2>/dev/null
expect_error "" info "$WORK/random.sdf"
cp "$WORK/tet.sdf" "$WORK/corrupt.sdf"
printf '\x55' | dd of="$WORK/corrupt.sdf" bs=1 seek=500 conv=notrunc 2>/dev/null
expect_error "$WORK/y.sdfgen" convert "$WORK/corrupt.sdf" "$WORK/y.sdfgen"
expect_error "$WORK/y.sdf" convert "$WORK/tet.sdf" "$WORK/y.sdf" --format json
echo "sdf_commands: all checks passed"
