#!/usr/bin/env bash
# The Release build folder `build`, configured one way for the main job and the test command, so that the test
# command reuses what the main job compiled (the tool and the libraries) and compiles only the test suites on top.
# Ninja compiles a suite's units while the libraries it links are still being built; unity builds (batches of 8
# files) instantiate Eigen's templates once per batch. A folder configured with another generator before is
# configured afresh (CMake cannot switch generators in place).
# Usage (sourced): source scripts/configure-release.sh; configure_release
configure_release() {
  if [ -f build/CMakeCache.txt ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; then
    rm -rf build/CMakeCache.txt build/CMakeFiles
  fi
  cmake -G Ninja -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON >/dev/null
}
