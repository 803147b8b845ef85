#!/usr/bin/env bash
# cli.sample: `sdfccd sample` writes PLY/CSV shells with the requested counts; bad input fails with one line
# on stderr, a non-zero exit and no output file.
source "$(dirname "$0")/lib.sh"

write_tet_off "$work/tet.off"

"$tool" sample "$work/tet.off" --points 60 -o "$work/tet.ply" > "$work/out.txt" 2> "$work/err.txt" \
  || fail "sample --points failed: $(cat "$work/err.txt")"
grep -q "^element vertex 60$" "$work/tet.ply" || fail "PLY does not hold 60 points"
[ "$(sed -n '/end_header/,$p' "$work/tet.ply" | tail -n +2 | wc -l)" -eq 60 ] || fail "PLY body is not 60 lines"
grep -q "60 points" "$work/out.txt" || fail "summary does not state the count"

"$tool" sample "$work/tet.off" --vertices -o "$work/tet.csv" > /dev/null 2>&1 || fail "sample --vertices failed"
[ "$(head -1 "$work/tet.csv")" = "x,y,z,nx,ny,nz" ] || fail "CSV header"
[ "$(wc -l < "$work/tet.csv")" -eq 5 ] || fail "CSV should hold the 4 vertices"

# Same seed, same shell; the thread count does not matter.
"$tool" sample "$work/tet.off" --points 60 --threads 2 -o "$work/tet2.ply" > /dev/null 2>&1 || fail "threads 2"
cmp -s "$work/tet.ply" "$work/tet2.ply" || fail "sampling depends on the thread count"

# A real model from the assets.
"$tool" sample "$assets/meshes/bunny.off" --points 200 --iterations 3 -o "$work/bunny.csv" > /dev/null 2>&1 \
  || fail "bunny sampling failed"
[ "$(wc -l < "$work/bunny.csv")" -eq 201 ] || fail "bunny CSV should hold 200 points"

# Bad input: one line on stderr, non-zero exit, no output.
expect_error() {
  local name="$1"; shift
  "$tool" "$@" > /dev/null 2> "$work/err.txt"
  [ $? -eq 1 ] || fail "$name: should fail with exit code 1 (not succeed or crash)"

  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "$name: stderr is not one line: $(cat "$work/err.txt")"
}
expect_error "missing mesh" sample "$work/nope.off" --points 10 -o "$work/a.ply"
[ ! -e "$work/a.ply" ] || fail "missing mesh left an output"
expect_error "no count" sample "$work/tet.off" -o "$work/b.ply"
expect_error "both" sample "$work/tet.off" --points 10 --vertices -o "$work/c.ply"
expect_error "bad extension" sample "$work/tet.off" --points 10 -o "$work/d.xyz"
[ ! -e "$work/d.xyz" ] || fail "bad extension left an output"
printf 'not a mesh\n' > "$work/garbage.off"
expect_error "garbage mesh" sample "$work/garbage.off" --points 10 -o "$work/e.ply"
[ ! -e "$work/e.ply" ] || fail "garbage mesh left an output"
ls "$work" | grep -q "tmp-" && fail "temporary files left behind"
echo "cli.sample: ok"
