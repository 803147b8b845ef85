#!/usr/bin/env bash
# The docs check of the test command (docs/testing.md): the README stays a short user guide, and code comments and
# the README explain the design as it is, not the issues or sessions that shaped it (that history belongs in
# CHANGELOG.md and git log). Fails, one line per problem on stderr, when
# - README.md has 200 lines or more;
# - a comment in a source, script or CMake file under plugin/, bullet_ext/, haptics/, demos/ or tests/ (*.h, *.hpp,
#   *.cpp, *.cc, *.sh, CMakeLists.txt, *.cmake), or any line of README.md, names an issue or a session by number
#   ("issue 12", "Issue #12", "issues 16-17", "session 3"; any case);
# - README.md's first ```cpp block is not, line for line, demos/examples/drop_bunny.cpp (the install test builds and
#   runs that file against the installed package, so the README's example compiles and runs).
# CHANGELOG.md and docs/ may cite history and are not checked. Only grep, wc, awk and cmp, so it is cheap.
# Usage: bash scripts/check-docs.sh [--comments-only]   (--comments-only: skip the README's checks)
set -uo pipefail
cd "$(dirname "$0")/.."

readme=1
case "${1:-}" in
  "") ;;
  --comments-only) readme=0 ;;
  *)
    echo "usage: bash scripts/check-docs.sh [--comments-only] (got '$1')" >&2
    exit 2
    ;;
esac

max_readme_lines=199
example=demos/examples/drop_bunny.cpp  # the README's ```cpp block, line for line
# An issue or a session named by number: "issue 12", "Issue #12", "issue-13", "issues 16-17", "session 3".
reference='\b(issue|session)s?[[:space:]]*[#-]?[[:space:]]*[0-9]+'
# Where a comment holds it: after "//" or "/*", or on a block comment's continuation line (" * ..."), in C++;
# after "#" in shell and CMake files.
cpp_comment="(//|/\\*|^[[:space:]]*\\*).*$reference"
hash_comment="#.*$reference"
dirs=(plugin bullet_ext haptics demos tests)

problems=0
report() {  # report FILE:LINE:TEXT WHAT: one line on stderr
  local where=${1%%:*} rest=${1#*:}
  local line=${rest%%:*} text=${rest#*:}
  text=$(printf '%s' "$text" | sed -E 's/^[[:space:]]+//' | cut -c1-120)
  echo "check-docs: $where:$line: $2: $text" >&2
  problems=$((problems + 1))
}

while IFS= read -r hit; do
  report "$hit" "issue or session reference in a comment"
done < <(
  grep -rnHEi --include='*.h' --include='*.hpp' --include='*.cpp' --include='*.cc' -- "$cpp_comment" "${dirs[@]}"
  grep -rnHEi --include='*.sh' --include='CMakeLists.txt' --include='*.cmake' -- "$hash_comment" "${dirs[@]}"
)

if [ "$readme" = 1 ]; then
  if [ ! -f README.md ]; then
    echo "check-docs: README.md is missing" >&2
    problems=$((problems + 1))
  else
    lines=$(wc -l < README.md)
    if [ "$lines" -gt "$max_readme_lines" ]; then
      echo "check-docs: README.md: $lines lines, at most $max_readme_lines allowed (the rest belongs in docs/)" >&2
      problems=$((problems + 1))
    fi
    while IFS= read -r hit; do
      report "README.md:$hit" "issue or session reference"
    done < <(grep -nEi -- "$reference" README.md)
    if ! awk '/^```cpp$/ { inside = 1; next } inside && /^```$/ { exit } inside' README.md | cmp -s - "$example"; then
      echo "check-docs: README.md: its \`\`\`cpp block differs from $example (the README's example is that file)" >&2
      problems=$((problems + 1))
    fi
  fi
fi

[ "$problems" -eq 0 ]
