#!/usr/bin/env bash
# `sdfccd render` and `sdfccd plot` of a haptic run folder (`sdfccd haptics --out`): a short virtual-time session
# on the thin wire (a grid obstacle) is rendered (frames of the tool and the wire, contact sheet) and plotted
# (force, torque, contacts, penetration per tick); the PNGs have the asked sizes and are not blank, frames at
# different ticks differ, the plotted force is the magnitude of ticks.csv's force columns; the plane scene is
# drawn too (its slab); a truncated ticks.csv or a summary without "scene_file" is one error line and a
# non-zero exit.
# Usage: bash haptic_render_plot.sh /path/to/sdfccd /path/to/assets
source "$(dirname "$0")/lib.sh"
skip_without haptics "built without the haptics module"

# "WxH distinct_colours non_background_fraction" of an 8-bit RGB/RGBA PNG (background: the top-left pixel).
png_content() {
  python3 - "$1" <<'PY'
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
pos, idat, width = 8, b"", 0
while pos < len(data):
    length, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + length]
    if kind == b"IHDR":
        width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        assert depth == 8 and colour in (2, 6), "only 8-bit RGB/RGBA"
        bpp = 3 if colour == 2 else 4
    elif kind == b"IDAT":
        idat += body
    pos += 12 + length
raw, stride, prev, pixels = zlib.decompress(idat), width * bpp, bytearray(width * bpp), []
for y in range(height):
    kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for x in range(stride):  # PNG filters: none, sub, up, average, Paeth
        a = line[x - bpp] if x >= bpp else 0
        b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
        if kind == 1: line[x] = (line[x] + a) & 255
        elif kind == 2: line[x] = (line[x] + b) & 255
        elif kind == 3: line[x] = (line[x] + (a + b) // 2) & 255
        elif kind == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    pixels += [bytes(line[i:i + 3]) for i in range(0, stride, bpp)]
    prev = line
other = sum(1 for p in pixels if p != pixels[0])
print("%dx%d %d %.4f" % (width, height, len(set(pixels)), other / len(pixels)))
PY
}

# check_png FILE WxH: the size, and not blank (at least 10 colours, at least 1% of the pixels not background).
check_png() {
  [ -f "$1" ] || fail "$1 missing"
  [ "$(png_size "$1")" = "$2" ] || fail "$1 is $(png_size "$1"), not $2"
  if command -v python3 >/dev/null 2>&1; then
    read -r size colours fraction <<<"$(png_content "$1")"
    [ "$size" = "$2" ] || fail "$1: decoded size $size"
    awk -v c="$colours" -v f="$fraction" 'BEGIN { exit !(c >= 10 && f >= 0.01) }' ||
      fail "$1 looks blank: $colours colours, $fraction of the pixels not background"
  fi
}

run="$work/wire"
"$tool" haptics "$assets/scenes/haptics/thin-wire.json" --method constraint --seconds 0.3 --virtual-time \
  --out "$run" >/dev/null 2>"$work/err.txt" || fail "haptics failed: $(cat "$work/err.txt")"
grep -q "\"scene_file\": \".*/thin-wire.json\"" "$run/summary.json" || fail "summary.json names no scene_file"

render_out="$("$tool" render "$run" --size 320x180 --every 100 --sheet-cells 4 --thumb-width 160 --no-video 2>&1)"
render_status=$?
if echo "$render_out" | grep -q "built without the renderer"; then
  echo "renderer not built: render checks skipped" >&2
else
  [ "$render_status" -eq 0 ] || fail "render exited $render_status: $render_out"
  # 300 ticks (0..299), every 100th: three frames named by tick.
  [ "$(ls "$run/frames" | grep -c '^frame_.*\.png$')" -eq 3 ] || fail "expected 3 frames: $(ls "$run/frames")"
  for f in 00000 00100 00200; do check_png "$run/frames/frame_$f.png" 320x180; done
  # The tool falls onto the wire between tick 0 and tick 100: the frames differ.
  cmp -s "$run/frames/frame_00000.png" "$run/frames/frame_00100.png" && fail "frames 0 and 100 are the same"
  # 4 cells of 160x90 in a 2x2 grid with 4 px padding: 2*164+4 by 2*94+4.
  check_png "$run/contact_sheet.png" 332x192

  # A plane obstacle is drawn as a slab.
  "$tool" haptics "$assets/scenes/haptics/plane-slide.json" --seconds 0.05 --virtual-time --out "$work/slide" \
    >/dev/null 2>&1 || fail "plane-slide session failed"
  "$tool" render "$work/slide" --size 160x90 --no-frames --sheet-cells 1 --thumb-width 160 >/dev/null 2>&1 ||
    fail "render of the plane run failed"
  check_png "$work/slide/contact_sheet.png" 168x98
fi

if command -v gnuplot >/dev/null 2>&1; then
  out="$("$tool" plot "$run" --size 320x200 2>&1)" || fail "plot failed: $out"
  for p in force torque contacts penetration; do check_png "$run/plots/$p.png" 320x200; done
  [ -f "$run/plots/overview.png" ] || fail "plots/overview.png missing"
  [ "$(grep -vc '^#' "$run/plots/series.dat")" -eq 300 ] || fail "series.dat does not have 300 rows"
  # The plotted force is |(force_x, force_y, force_z)| of ticks.csv, tick by tick (columns 17..19; series.dat:
  # frame time penetration contacts force torque).
  awk -F, 'NR > 1 { printf "%.12g\n", sqrt($17 * $17 + $18 * $18 + $19 * $19) }' "$run/ticks.csv" > "$work/force_ref.txt"
  grep -v '^#' "$run/plots/series.dat" | awk '{ print $5 }' | paste - "$work/force_ref.txt" |
    awk '{ d = $1 - $2; if (d * d > 1e-16 * (1 + $2 * $2)) bad++; if ($2 > peak) peak = $2 }
         END { exit !(bad == 0 && peak > 0) }' || fail "plotted force differs from ticks.csv's (or is zero)"
fi

# Bad input: a truncated ticks.csv (cut inside a row, or at a row's end), and a summary without the scene file.
bad="$work/truncated"
mkdir -p "$bad"
cp "$run/summary.json" "$bad/"
head -c 5000 "$run/ticks.csv" > "$bad/ticks.csv"
if ! echo "${render_out:-}" | grep -q "built without the renderer"; then
  expect_one_line_error render "$bad" --size 64x64
  grep -q "ticks.csv:[0-9]*: .*truncated" "$work/err.txt" || fail "truncated render message: $(cat "$work/err.txt")"
fi
expect_one_line_error plot "$bad"
grep -q "ticks.csv:[0-9]*: .*truncated" "$work/err.txt" || fail "truncated plot message: $(cat "$work/err.txt")"
# Cut at a line's end: the rows no longer match summary.json's haptic_ticks.
head -n 101 "$run/ticks.csv" > "$bad/ticks.csv"
expect_one_line_error plot "$bad"
grep -q "ticks.csv: 100 ticks, summary.json's haptic_ticks is 300" "$work/err.txt" ||
  fail "short ticks.csv message: $(cat "$work/err.txt")"
old="$work/old"
mkdir -p "$old"
cp "$run/ticks.csv" "$old/"
grep -v scene_file "$run/summary.json" > "$old/summary.json"
if ! echo "${render_out:-}" | grep -q "built without the renderer"; then
  expect_one_line_error render "$old" --size 64x64
  grep -q "summary.json: no \"scene_file\"" "$work/err.txt" || fail "no scene_file message: $(cat "$work/err.txt")"
fi
echo "haptic_render_plot: all checks passed"
