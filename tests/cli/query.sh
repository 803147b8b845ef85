#!/usr/bin/env bash
# Contract test of `sdfccd query`: CSV output on a plane field with closed-form answers, per-line sigma,
# comments and blank lines, identical output for every octree mode, and one-line errors naming the line.
# Usage: query.sh /path/to/sdfccd /path/to/assets
source "$(dirname "$0")/lib.sh"

# phi = x - 1 on a 5x3x3 grid with spacing 0.5 from the origin (SDFGen text, i fastest): exact in float and
# reproduced exactly by trilinear interpolation.
{
  echo "5 3 3"
  echo "0 0 0"
  echo "0.5"
  for k in 0 1 2; do for j in 0 1 2; do for i in 0 1 2 3 4; do
    echo "$(awk -v i="$i" 'BEGIN { printf "%.17g", i * 0.5 - 1 }')"
  done; done; done
} > "$work/plane.sdfgen"

cat > "$work/segments.txt" <<'EOF'
# x0,y0,z0,x1,y1,z1[,sigma]

2,0.5,0.5,0,0.5,0.5
0,0,0,2,1,1,0.5
  0.5 , 0.2 , 0.3 , 1.5 , 0.8 , 0.9
5,5,5,6,6,6
1.5,0.5,0.5,1.75,0.5,0.5
EOF

"$tool" query "$work/plane.sdfgen" --segments "$work/segments.txt" > "$work/out.csv" 2> "$work/err.txt" \
  || fail "query exited non-zero: $(cat "$work/err.txt")"
# Row 0: x from 2 to 0, phi <= 0 from x = 1: t = 0.5.  Row 1: sigma 0.5, x <= 1.5 -> t <= 0.75.
# Row 2: starts inside (x = 0.5), leaves at x = 1: t = 0.5.  Row 3: outside the box.  Row 4: never reaches x = 1.
expected='segment,first_hit,intervals
0,0.5,0.5:1
1,0,0:0.75
2,0,0:0.5
3,,
4,,'
[ "$(cat "$work/out.csv")" = "$expected" ] || fail "unexpected output:
$(cat "$work/out.csv")"

# --sigma applies to lines without a 7th value; every octree mode and both methods agree on this field.
"$tool" query "$work/plane.sdfgen" --segments "$work/segments.txt" --sigma 0.25 > "$work/s.csv" || fail "--sigma"
grep -qx '0,0.375,0.375:1' "$work/s.csv" || fail "--sigma 0.25 row 0: $(sed -n 2p "$work/s.csv")"
grep -qx '1,0,0:0.75' "$work/s.csv" || fail "per-line sigma must override --sigma"
for octree in full leaves off; do
  for method in exact bisection; do
    "$tool" query "$work/plane.sdfgen" --segments "$work/segments.txt" --octree "$octree" --method "$method" \
      > "$work/m.csv" || fail "--octree $octree --method $method"
    cmp -s "$work/m.csv" "$work/out.csv" || fail "--octree $octree --method $method differs"
  done
done

# At least 12 significant digits: a crossing at t = 1/3.
echo "1.5,0.5,0.5,0,0.5,0.5" > "$work/third.txt"
"$tool" query "$work/plane.sdfgen" --segments "$work/third.txt" > "$work/third.csv" || fail "third"
first=$(sed -n 2p "$work/third.csv" | cut -d, -f2)
awk -v t="$first" 'BEGIN { d = t - 1/3; if (d < 0) d = -d; exit !(d < 1e-13 && length(t) >= 14) }' \
  || fail "t = 1/3 printed as '$first'"

# Very long segments through the field: the part inside the box is clipped and walked in its own frame, so the hit is
# found; the fraction is rounded to double precision. Rows 0-2 cross x = 1 near t = 0.5 (2e16 and 2e20 long, and
# oblique), rows 3-5 reach the field only at their very end, t ~ 1 - 1e-17, where a walk in t would find nothing (rows:
# ending inside at x = 0.7, crossing x = 1, and oblique).
printf '%s\n' '1e16,0.5,0.5,-1e16,0.5,0.5' '1e20,0.5,0.5,-1e20,0.5,0.5' '1e16,0.5,1e15,-1e16,0.5,-1e15' \
  '-2e16,0.5,0.5,0.7,0.5,0.5' '-2e16,0.5,0.5,1.7,0.5,0.5' '-2e16,0.5,-2e15,1.7,0.5,0.3' > "$work/long.txt"
for octree in full leaves off; do
  for method in exact bisection; do
    "$tool" query "$work/plane.sdfgen" --segments "$work/long.txt" --octree "$octree" --method "$method" \
      > "$work/long.csv" || fail "long segments --octree $octree --method $method"
    for expect in 0:0.5 1:0.5 2:0.5 3:1 4:1 5:1; do
      row=${expect%%:*}
      first=$(awk -F, -v r="$row" '$1 == r { print $2 }' "$work/long.csv")
      [ -n "$first" ] || fail "long segment $row ($octree, $method): no hit: $(cat "$work/long.csv")"
      awk -v t="$first" -v e="${expect#*:}" 'BEGIN { d = t - e; if (d < 0) d = -d; exit !(d < 1e-12) }' ||
        fail "long segment $row ($octree, $method): first hit $first, expected ${expect#*:}"
    done
  done
done

# Malformed lines: one-line error naming the line, non-zero exit, nothing on stdout.
check_error() {  # name, file content, expected line number
  printf '%s' "$2" > "$work/bad.txt"
  if "$tool" query "$work/plane.sdfgen" --segments "$work/bad.txt" > "$work/bad.out" 2> "$work/bad.err"; then
    fail "$1: expected a non-zero exit"
  fi
  [ -s "$work/bad.out" ] && fail "$1: printed output despite the error"
  [ "$(wc -l < "$work/bad.err")" -eq 1 ] || fail "$1: error is not one line: $(cat "$work/bad.err")"
  grep -q ":$3:" "$work/bad.err" || fail "$1: error does not name line $3: $(cat "$work/bad.err")"
}
check_error "five values" $'# ok\n0,0,0,1,1,1\n0,0,0,1,1\n' 3
check_error "eight values" $'0,0,0,1,1,1,0,5\n' 1
check_error "not a number" $'0,0,0,1,1,1\n\n0,0,zero,1,1,1\n' 3
check_error "nan" $'0,0,0,1,nan,1\n' 1
check_error "inf sigma" $'0,0,0,1,1,1,inf\n' 1
check_error "empty value" $'0,,0,1,1,1\n' 1

# Bad options and files.
"$tool" query "$work/plane.sdfgen" --segments "$work/segments.txt" --method cardano > /dev/null 2>&1 && fail "bad --method"
"$tool" query "$work/plane.sdfgen" --segments "$work/segments.txt" --octree some > /dev/null 2>&1 && fail "bad --octree"
"$tool" query "$work/plane.sdfgen" --segments "$work/missing.txt" > /dev/null 2>&1 && fail "missing segments file"
"$tool" query "$work/missing.sdfgen" --segments "$work/segments.txt" > /dev/null 2>&1 && fail "missing field"
echo "PASS"
