#!/usr/bin/env bash
# Contract test of `sdfccd build-sdf`, `info` and `convert`: outputs, format selection, round trips, and
# one-line errors with a non-zero status and no output file for every kind of bad input.
# Usage: sdf_commands.sh /path/to/sdfccd /path/to/assets
source "$(dirname "$0")/lib.sh"

# An error: non-zero status, exactly one line on stderr, and the named output file absent.
expect_error() {
  local output="$1"
  shift
  expect_one_line_error "$@"
  if [ -n "$output" ] && [ -e "$output" ]; then fail "output left behind by: $*"; fi
  ls "$work" | grep -q "\.tmp-" && fail "temporary file left behind by: $*"
  return 0
}

write_tet_off "$work/tet.off"

"$tool" build-sdf "$work/tet.off" --resolution 8 --padding 2 -o "$work/tet.sdf" >"$work/build.txt" 2>"$work/err.txt" \
  || fail "build-sdf failed: $(cat "$work/err.txt")"
for word in dimensions spacing "build time" memory repairs "sign method"; do
  grep -q "$word" "$work/build.txt" || fail "build-sdf output lacks '$word'"
done
grep -q "13 x 13 x 13 nodes" "$work/build.txt" || fail "unexpected dimensions: $(grep dimensions "$work/build.txt")"
grep -q "pseudonormal" "$work/build.txt" || fail "closed mesh not signed by pseudonormals"
head -c 6 "$work/tet.sdf" | grep -q "sdfccd" || fail "default output is not native"

"$tool" info "$work/tet.sdf" >"$work/info.txt" || fail "info failed"
for word in dimensions box spacing values memory; do grep -q "$word" "$work/info.txt" || fail "info lacks '$word'"; done
grep -q "13 x 13 x 13 nodes" "$work/info.txt" || fail "info dimensions"

# Native -> SDFGen (by extension) -> native (by --format): identical files.
"$tool" convert "$work/tet.sdf" "$work/tet.sdfgen" >/dev/null || fail "convert to sdfgen"
[ "$(head -n 1 "$work/tet.sdfgen")" = "13 13 13" ] || fail "SDFGen header: $(head -n 1 "$work/tet.sdfgen")"
[ "$(wc -l <"$work/tet.sdfgen")" -eq $((3 + 13 * 13 * 13)) ] || fail "SDFGen line count"
"$tool" convert "$work/tet.sdfgen" "$work/back.bin" --format native >/dev/null || fail "convert back"
cmp -s "$work/tet.sdf" "$work/back.bin" || fail "native -> sdfgen -> native is not identical"
"$tool" build-sdf "$work/tet.off" -r 8 -p 2 --format sdfgen -o "$work/forced.sdf" >/dev/null || fail "--format sdfgen"
cmp -s "$work/forced.sdf" "$work/tet.sdfgen" || fail "--format sdfgen differs from the converted file"
"$tool" info "$work/tet.sdfgen" | grep -q "13 x 13 x 13" || fail "info on SDFGen"

# The bundled open mesh builds and is signed by winding numbers.
"$tool" build-sdf "$assets/meshes/mech-holes-shark.off" -r 12 -p 1 -o "$work/shark.sdf" >"$work/shark.txt" \
  || fail "shark build failed"
grep -q "winding-number" "$work/shark.txt" || fail "open mesh not signed by winding numbers"
grep -q "open (" "$work/shark.txt" || fail "open mesh not reported open"

# Errors.
expect_error "$work/x.sdf" build-sdf "$work/missing.off" -r 8 -o "$work/x.sdf"
: >"$work/empty.off"
expect_error "$work/x.sdf" build-sdf "$work/empty.off" -r 8 -o "$work/x.sdf"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n' >"$work/flat.off"
expect_error "$work/x.sdf" build-sdf "$work/flat.off" -r 8 -o "$work/x.sdf"
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r 0 -o "$work/x.sdf"
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r 100000 -o "$work/x.sdf"
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r 8 -p -1 -o "$work/x.sdf"
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r 4000 -p 0 -o "$work/x.sdf" --max-memory 100
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r 8 --threads -3 -o "$work/x.sdf"
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r 8 --format vtk -o "$work/x.sdf"
expect_error "$work/x.sdf" build-sdf "$work/tet.off" -r abc -o "$work/x.sdf"
expect_error "" build-sdf "$work/tet.off" -r 8 -o "$work/no/such/dir/x.sdf"
expect_error "" info "$work/missing.sdf"
head -c 100 "$work/tet.sdf" >"$work/truncated.sdf"
expect_error "" info "$work/truncated.sdf"
head -n 100 "$work/tet.sdfgen" >"$work/truncated.sdfgen"
expect_error "" info "$work/truncated.sdfgen"
head -c 3000 /dev/urandom >"$work/random.sdf" 2>/dev/null || dd if=/dev/urandom of="$work/random.sdf" bs=1000 count=3 2>/dev/null
expect_error "" info "$work/random.sdf"
cp "$work/tet.sdf" "$work/corrupt.sdf"
printf '\x55' | dd of="$work/corrupt.sdf" bs=1 seek=500 conv=notrunc 2>/dev/null
expect_error "$work/y.sdfgen" convert "$work/corrupt.sdf" "$work/y.sdfgen"
expect_error "$work/y.sdf" convert "$work/tet.sdf" "$work/y.sdf" --format json
echo "sdf_commands: all checks passed"
