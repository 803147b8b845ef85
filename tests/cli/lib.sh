#!/usr/bin/env bash
# Shared prologue of the CLI contract tests (tests/cli/*.sh; not a test itself: tests/CMakeLists.txt leaves it
# out). Sourced first thing by each script, called as `bash script.sh /path/to/sdfccd /path/to/assets`:
#   source "$(dirname "$0")/lib.sh"
# It sets `set -u`, and defines
#   tool    the sdfccd executable ($1)
#   assets  the assets folder ($2; empty when not given)
#   work    a fresh temporary folder, removed on exit (XDG_CACHE_HOME points into it: the default model cache
#           of simulate and haptics never touches the user's)
#   fail MESSAGE            print "FAIL: MESSAGE" on stderr and exit 1 (scripts that count failures and go on
#                           redefine it after sourcing)
#   skip_without COMMAND WHY   exit 0 with "skipped: WHY" when `sdfccd --help` lists no COMMAND
#   png_size FILE           a PNG's "WIDTHxHEIGHT" from its IHDR chunk
#   write_tet_off FILE      writes the unit tetrahedron (outward faces) as OFF, small enough to build instantly
#   expect_one_line_error ARGS...   runs `sdfccd ARGS...` (stdout to $work/out.txt, stderr to $work/err.txt) and
#                           fails unless it exits non-zero with exactly one line on stderr
set -u
tool="${1:?usage: bash script.sh /path/to/sdfccd /path/to/assets}"
assets="${2:-}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# Hermetic: the tools' default model cache ($XDG_CACHE_HOME/sdfccd) is inside $work, never the user's.
export XDG_CACHE_HOME="$work/xdg-cache"

fail() { echo "FAIL: $*" >&2; exit 1; }

skip_without() {
  if ! "$tool" --help | grep -qE "^ +$1 "; then echo "skipped: $2"; exit 0; fi
}

# PNG width and height from the IHDR chunk (bytes 16..23, big-endian).
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{printf "%dx%d", $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}'; }

write_tet_off() {
  cat >"$1" <<'MESH'
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
}

expect_one_line_error() {
  "$tool" "$@" >"$work/out.txt" 2>"$work/err.txt" && fail "accepted: $*"
  [ "$(wc -l <"$work/err.txt")" -eq 1 ] || fail "not one line of stderr for: $* ($(cat "$work/err.txt"))"
  return 0
}
