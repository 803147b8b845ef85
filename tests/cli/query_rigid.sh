#!/usr/bin/env bash
# Contract test of `sdfccd query-rigid`: a shell of five points moving rigidly against the field of an
# axis-aligned cube, checked three ways:
#   - closed form: a point moving straight toward a face touches it at fraction distance / travel (the field of
#     the cube is x - 1 near the face x = 1, away from edges, and trilinear interpolation reproduces it exactly);
#   - brute force: every point's segment, computed here, queried alone with `sdfccd query`: the rigid `all`
#     rows must be the segment query's rows with a contact, bit for bit, and `earliest` their minimum with every
#     point tied at it (motions whose rotations are exact in binary: identity and half turns);
#   - consistency: tree on/off, every octree mode, earliest vs all.
# Plus one-line errors naming the line for bad motions, and missing files.
# Usage: query_rigid.sh /path/to/sdfccd /path/to/assets
source "$(dirname "$0")/lib.sh"

# The cube [-1,1]^3, outward triangles. At -r 8 -p 4 the grid spacing is 0.25 and the box [-2,2]^3: node values
# are multiples of 0.25, exact in float.
cat > "$work/cube.obj" <<'MESH'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
MESH
"$tool" build-sdf "$work/cube.obj" -r 8 -p 4 -o "$work/cube.sdf" > /dev/null 2> "$work/err.txt" \
  || fail "build-sdf of the cube: $(cat "$work/err.txt")"

# Five points within 0.5 of the shell's origin (normals do not matter to the CCD). Points 2 and 3 share x.
cat > "$work/shell.csv" <<'EOF'
x,y,z,nx,ny,nz
0,0,0,1,0,0
0.3,0.2,-0.1,1,0,0
-0.25,0.4,0.3,1,0,0
-0.25,-0.3,0.1,1,0,0
0.1,-0.45,-0.35,1,0,0
EOF

# Start pose then end pose: x,y,z,qw,qx,qy,qz each.
cat > "$work/motions.txt" <<'EOF'
# 0: translation along -x toward the face x = 1, from x = 2.5 + px to 0.5 + px: t = (1.5 + px) / 2
2.5,0,0,1,0,0,0, 0.5,0,0,1,0,0,0

# 1: a half turn about z on the way (x: 3 + px -> 1.2 - px): t = (2 + px) / (1.8 + 2 px), a hit iff px >= 0.2
3,0,0,1,0,0,0, 1.2,0,0,0,0,0,1
# 2: half turn about x at both ends, down onto z = 1 (z: 2.6 - pz -> 0.4 - pz): t = (1.6 - pz) / 2.2
0,0.1,2.6,0,1,0,0, 0,0.1,0.4,0,1,0,0
# 3: far outside the field's box
10,10,10,1,0,0,0, 11,10,10,1,0,0,0
# 4: starts inside the cube: every point at fraction 0
0,0,0,1,0,0,0, 0.1,0,0,1,0,0,0
# 5: parallel to the face x = 1, never reaching it
2.5,0,0,1,0,0,0, 2.5,0.5,0,1,0,0,0
EOF

"$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" > "$work/earliest.csv" \
  2> "$work/err.txt" || fail "query-rigid exited non-zero: $(cat "$work/err.txt")"
"$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --query all > "$work/all.csv" \
  2> "$work/err.txt" || fail "query-rigid --query all exited non-zero: $(cat "$work/err.txt")"
[ "$(head -1 "$work/earliest.csv")" = "motion,first_hit,points" ] || fail "earliest header: $(head -1 "$work/earliest.csv")"
[ "$(head -1 "$work/all.csv")" = "motion,point,first_hit,intervals" ] || fail "all header: $(head -1 "$work/all.csv")"
[ "$(wc -l < "$work/earliest.csv")" -eq 7 ] || fail "earliest: one row per motion expected:
$(cat "$work/earliest.csv")"

# Closed form, within a tolerance for the cubic's roots: motion, expected fraction, expected points.
check_earliest() {
  local row
  row=$(awk -F, -v m="$1" '$1 == m' "$work/earliest.csv")
  awk -F, -v t="$2" -v row="$row" 'BEGIN { split(row, f, ","); d = f[2] - t; if (d < 0) d = -d;
    exit !(f[2] != "" && d < 1e-9) }' || fail "motion $1: first hit is not $2: '$row'"
  [ "$(echo "$row" | cut -d, -f3)" = "$3" ] || fail "motion $1: points are not '$3': '$row'"
}
check_earliest 0 0.625 "2 3"                # px = -0.25 for points 2 and 3: (1.5 - 0.25) / 2
check_earliest 1 0.95833333333333333 "1"    # only point 1 (px = 0.3): 2.3 / 2.4
check_earliest 2 0.59090909090909091 "2"    # pz = 0.3 (point 2): 1.3 / 2.2
check_earliest 4 0 "0 1 2 3 4"
grep -qx '3,,' "$work/earliest.csv" || fail "motion 3 (outside the box) should have no contact"
grep -qx '5,,' "$work/earliest.csv" || fail "motion 5 (parallel to the face) should have no contact"
# Motion 1 in `all`: only point 1 touches (the others end short of the face).
[ "$(awk -F, '$1 == 1' "$work/all.csv" | cut -d, -f2)" = "1" ] || fail "motion 1: only point 1 should touch"

# `all` and `earliest` agree: per motion, the minimum first hit of `all` and every point at it.
awk -F, 'NR > 1 { if (!($1 in best) || $3 + 0 < best[$1] + 0) { best[$1] = $3; pts[$1] = $2 }
                  else if ($3 + 0 == best[$1] + 0) pts[$1] = pts[$1] " " $2 }
         END { for (m = 0; m < 6; ++m) print m "," (m in best ? best[m] : "") "," (m in pts ? pts[m] : "") }' \
  "$work/all.csv" > "$work/from_all.csv"
[ "$(tail -n +2 "$work/earliest.csv")" = "$(cat "$work/from_all.csv")" ] || fail "earliest differs from all's minima:
$(cat "$work/earliest.csv")
---
$(cat "$work/from_all.csv")"

# Brute force: each point's segment, start = R0 p + t0 and end = R1 p + t1, written with 17 digits (the
# rotations here have entries 0 and +-1, so these are the doubles the core computes), queried by `sdfccd query`.
# The quaternion's matrix (w = 0 or 1, one unit component): identity or a half turn about x, y or z.
segments_of_motion() {  # motion line (14 numbers) -> one segment per shell point on stdout
  awk -F, -v motion="$1" '
    function rotate(w, qx, qy, qz, p, out) {
      if (w == 1) { out[1] = p[1]; out[2] = p[2]; out[3] = p[3] }
      else if (qx == 1) { out[1] = p[1]; out[2] = -p[2]; out[3] = -p[3] }
      else if (qy == 1) { out[1] = -p[1]; out[2] = p[2]; out[3] = -p[3] }
      else if (qz == 1) { out[1] = -p[1]; out[2] = -p[2]; out[3] = p[3] }
      else { print "unsupported quaternion" > "/dev/stderr"; exit 1 }
    }
    BEGIN { n = split(motion, v, ","); if (n != 14) exit 1 }
    NR > 1 {
      p[1] = $1; p[2] = $2; p[3] = $3
      rotate(v[4], v[5], v[6], v[7], p, a); rotate(v[11], v[12], v[13], v[14], p, b)
      printf "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", a[1] + v[1], a[2] + v[2], a[3] + v[3], b[1] + v[8], b[2] + v[9], b[3] + v[10]
    }' "$work/shell.csv"
}
brute_force_all() {  # extra query options... -> the rows `query-rigid --query all` must print, header included
  echo "motion,point,first_hit,intervals"
  local m=0
  while read -r motion; do
    segments_of_motion "$motion" > "$work/segments.txt" || fail "segments of motion $m"
    "$tool" query "$work/cube.sdf" --segments "$work/segments.txt" "$@" > "$work/segments.csv" \
      || fail "sdfccd query of motion $m"
    awk -F, -v m="$m" 'NR > 1 && $2 != "" { print m "," $0 }' "$work/segments.csv"
    m=$((m + 1))
  done < <(grep -v '^ *#' "$work/motions.txt" | grep -v '^ *$' | tr -d ' ')
}
for options in "" "--method bisection" "--octree leaves" "--octree off" "--sigma 0.1"; do
  # shellcheck disable=SC2086
  brute_force_all $options > "$work/reference.csv"
  # shellcheck disable=SC2086
  "$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --query all $options \
    > "$work/rigid.csv" || fail "query-rigid --query all $options"
  cmp -s "$work/rigid.csv" "$work/reference.csv" || fail "query-rigid --query all $options differs from sdfccd query:
$(diff "$work/rigid.csv" "$work/reference.csv")"
done

# Tree on/off and every octree mode: identical answers, both queries.
for query in earliest all; do
  "$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --query "$query" \
    > "$work/ref.csv" || fail "--query $query"
  for tree in on off; do
    for octree in full leaves off; do
      "$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --query "$query" \
        --tree "$tree" --octree "$octree" > "$work/m.csv" || fail "--query $query --tree $tree --octree $octree"
      cmp -s "$work/m.csv" "$work/ref.csv" || fail "--query $query --tree $tree --octree $octree differs"
    done
  done
done

# A rotation that is not exact in binary (a quarter turn about z, maps (x, y) to (-y, x)): closed form only.
# x: 2.5 - py -> 0.5 - py, so t = (1.5 - py) / 2, earliest for py = 0.4 (point 2): 0.55. Seven-digit
# quaternions (norm 1 + 4e-8) are accepted and normalized.
cat > "$work/quarter.txt" <<'EOF'
2.5,0,0,0.70710678118654752,0,0,0.70710678118654752, 0.5,0,0,0.70710678118654752,0,0,0.70710678118654752
2.5,0,0,0.7071068,0,0,0.7071068, 0.5,0,0,0.7071068,0,0,0.7071068
EOF
"$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/quarter.txt" > "$work/earliest.csv" \
  2> "$work/err.txt" || fail "quarter turn: $(cat "$work/err.txt")"
check_earliest 0 0.55 "2"
check_earliest 1 0.55 "2"

# Malformed motions: one-line error naming the line, non-zero exit, nothing on stdout.
check_error() {  # name, file content, expected line number
  printf '%s' "$2" > "$work/bad.txt"
  if "$tool" query-rigid "$work/cube.sdf" "$work/shell.csv" --motions "$work/bad.txt" > "$work/bad.out" \
    2> "$work/bad.err"; then
    fail "$1: expected a non-zero exit"
  fi
  [ -s "$work/bad.out" ] && fail "$1: printed output despite the error"
  [ "$(wc -l < "$work/bad.err")" -eq 1 ] || fail "$1: error is not one line: $(cat "$work/bad.err")"
  grep -q ":$3:" "$work/bad.err" || fail "$1: error does not name line $3: $(cat "$work/bad.err")"
}
good='2.5,0,0,1,0,0,0,0.5,0,0,1,0,0,0'
check_error "13 values" $'# ok\n'"$good"$'\n2.5,0,0,1,0,0,0,0.5,0,0,1,0,0\n' 3
check_error "15 values" "$good"$'\n\n'"$good"$',1\n' 3
check_error "7 values (one pose)" $'2.5,0,0,1,0,0,0\n' 1
check_error "not a number" $'2.5,0,0,1,0,0,0,0.5,0,0,one,0,0,0\n' 1
check_error "nan" "$good"$'\n2.5,0,nan,1,0,0,0,0.5,0,0,1,0,0,0\n' 2
check_error "inf" $'2.5,0,0,1,0,0,0,inf,0,0,1,0,0,0\n' 1
check_error "empty value" $'2.5,,0,1,0,0,0,0.5,0,0,1,0,0,0\n' 1
check_error "start quaternion not unit" "$good"$'\n'"$good"$'\n2.5,0,0,1.00001,0,0,0,0.5,0,0,1,0,0,0\n' 3
check_error "end quaternion not unit" $'2.5,0,0,1,0,0,0,0.5,0,0,0.5,0.5,0.5,0\n' 1
check_error "zero quaternion" $'2.5,0,0,0,0,0,0,0.5,0,0,1,0,0,0\n' 1
grep -q "quaternion" "$work/bad.err" || fail "the quaternion error does not say so: $(cat "$work/bad.err")"

# Bad options and files: a non-zero exit and one line on stderr.
expect_failure() {  # name, arguments...
  local name="$1"
  shift
  "$tool" query-rigid "$@" > "$work/bad.out" 2> "$work/bad.err" && fail "$name: expected a non-zero exit"
  [ -s "$work/bad.out" ] && fail "$name: printed output despite the error"
  [ "$(wc -l < "$work/bad.err")" -eq 1 ] || fail "$name: error is not one line: $(cat "$work/bad.err")"
  return 0
}
expect_failure "missing motions file" "$work/cube.sdf" "$work/shell.csv" --motions "$work/missing.txt"
expect_failure "missing shell" "$work/cube.sdf" "$work/missing.csv" --motions "$work/motions.txt"
expect_failure "missing field" "$work/missing.sdf" "$work/shell.csv" --motions "$work/motions.txt"
expect_failure "no --motions" "$work/cube.sdf" "$work/shell.csv"
expect_failure "bad --query" "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --query first
expect_failure "bad --method" "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --method cardano
expect_failure "bad --octree" "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --octree some
expect_failure "bad --tree" "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --tree maybe
expect_failure "inf --sigma" "$work/cube.sdf" "$work/shell.csv" --motions "$work/motions.txt" --sigma inf
echo "PASS"
