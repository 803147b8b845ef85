#!/usr/bin/env bash
# The test command (README, .ci/run): installs dependencies, builds, runs every test suite, then rebuilds
# the core and its tests with AddressSanitizer + UndefinedBehaviorSanitizer and runs them again.
# Usage (as root, from the repository root): bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

echo "== build (Release)" >&2
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"
echo "== tests (Release)" >&2
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 600

echo "== build (address,undefined sanitizers)" >&2
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDFCCD_SANITIZE=address,undefined \
  -DSDFCCD_BUILD_RENDER=OFF >/dev/null
cmake --build build-asan -j"$jobs"
echo "== tests (address,undefined sanitizers)" >&2
# The install/consumer test proves packaging, not memory safety: the Release run covered it.
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 900 -LE install

echo "== build (thread sanitizer: the haptic loops)" >&2
# The haptics module runs a 1 kHz device thread beside a simulation thread; its suite must be TSan clean.
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDFCCD_SANITIZE=thread -DSDFCCD_BUILD_BULLET=OFF \
  -DSDFCCD_BUILD_RENDER=OFF -DSDFCCD_BUILD_TOOLS=OFF >/dev/null
cmake --build build-tsan -j"$jobs" --target haptics_tests
echo "== tests (thread sanitizer)" >&2
TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build-tsan --output-on-failure -j"$jobs" --timeout 900 -L haptics_tests
