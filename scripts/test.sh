#!/usr/bin/env bash
# The test command (README, docs/testing.md): installs dependencies, checks the docs' rules, builds (Release) and runs
# every test suite.
# CI (.ci/run) runs the test command, then this script's `sanitizers` stages: each library file compiled alone (clang
# -fsyntax-only: the builds batch their files in unity builds), the core and its tests rebuilt with
# AddressSanitizer + UndefinedBehaviorSanitizer and run again but the long tests, the suites whose tests start
# threads under ThreadSanitizer, and the field, shell, scene, segment-file and haptic-scene readers fuzzed briefly
# (libFuzzer, clang). Every tree is a preset of CMakePresets.json (release, syntax-check, asan-ubsan, tsan, fuzz),
# and the tests each stage runs are chosen by their ctest labels (tests/CMakeLists.txt: long, short, threads).
# Usage (as root, from the repository root): bash scripts/test.sh [sanitizers | fuzz]
#   (no argument: the test command; sanitizers: ASan+UBSan, TSan and fuzz stages; fuzz: the libFuzzer stage alone)
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}
case "$mode" in
  "" | sanitizers | fuzz) ;;
  *)
    echo "usage: bash scripts/test.sh [sanitizers | fuzz] (got '$mode')" >&2
    exit 2
    ;;
esac
bash scripts/install-deps.sh
jobs=$(nproc)

# Every preset uses Ninja: unlike the Makefiles (which finish a target, link included, before compiling anything
# of the targets that link it) it compiles a suite's units while the libraries it links are still being built.
# A build folder configured with another generator before is configured afresh (CMake cannot switch in place).
# configure PRESET FOLDER (the preset's binaryDir)
configure() {
  local preset=$1 dir=$2
  if [ -f "$dir"/CMakeCache.txt ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir"/CMakeCache.txt; then
    rm -rf "$dir"/CMakeCache.txt "$dir"/CMakeFiles
  fi
  cmake --preset "$preset" >/dev/null
}

# stage NAME: prints the stage's header, after a line with the previous stage's wall time and the CPU time (user +
# sys) its commands used (bash's `times`: the children this shell waited for); the last stage's line comes at exit.
stage_name=
stage_wall=$SECONDS
stage_cpu=0
children_cpu() {  # sets cpu_now (s); `times` must run in this shell, not in a $(...) subshell
  local t
  t=$(mktemp)
  times > "$t"
  # Line 2 of `times`: the children's user and system time, e.g. "12m3.456s 0m20.100s".
  cpu_now=$(awk 'NR == 2 { split($1, u, /[ms]/); split($2, s, /[ms]/); printf "%.0f", u[1] * 60 + u[2] + s[1] * 60 + s[2] }' "$t")
  rm -f "$t"
}
stage_end() {
  [ -n "$stage_name" ] || return 0
  children_cpu
  echo "== $(date -u +%H:%M:%S) $stage_name: wall $((SECONDS - stage_wall)) s, CPU $((cpu_now - stage_cpu)) s" >&2
  stage_name=
}
stage() {
  stage_end
  stage_name=$1
  stage_wall=$SECONDS
  children_cpu
  stage_cpu=$cpu_now
  echo "== $(date -u +%H:%M:%S) $1" >&2
}
trap stage_end EXIT

# The loaders under libFuzzer (tests/fuzz): arbitrary bytes must give a valid object or an sdfccd::Error; a
# crash, another exception, a leak or UB fails the command. The five fuzzers (field, shell, scene, segment file,
# haptic scene) run at once for 30 s each on a copy of their corpus: the stage's wall time stays 30 s, and on the
# 2-core CI machine each gets the CPU of 12 s.
fuzz_stage() {
  stage "build (libFuzzer targets: clang, address,undefined sanitizers)"
  configure fuzz build-fuzz
  cmake --build --preset fuzz -j"$jobs"
  local targets=(fuzz_field_loader fuzz_shell_loader fuzz_scene_loader fuzz_segment_file fuzz_haptic_scene)
  stage "fuzz (field, shell, scene, segment file and haptic scene readers, 30 s at once)"
  mkdir -p build-fuzz/artifacts
  local pids=() corpora=() target corpus i failed=0
  for target in "${targets[@]}"; do
    corpus=$(mktemp -d)
    corpora+=("$corpus")
    cp tests/fuzz/corpus/"$target"/* "$corpus"/
    dict=()
    [ -f tests/fuzz/"$target".dict ] && dict=(-dict=tests/fuzz/"$target".dict)
    build-fuzz/tests/fuzz/"$target" -max_total_time=30 -timeout=10 -rss_limit_mb=2048 "${dict[@]}" \
      -artifact_prefix=build-fuzz/artifacts/"$target"- "$corpus" 2> build-fuzz/"$target".log &
    pids+=($!)
  done
  for i in "${!targets[@]}"; do
    target=${targets[$i]}
    if wait "${pids[$i]}"; then
      grep -E "^Done [0-9]+ runs" build-fuzz/"$target".log >&2 || true
    else
      tail -n 40 build-fuzz/"$target".log >&2
      echo "fuzz: $target failed; reproducer in build-fuzz/artifacts/" >&2
      failed=1
    fi
  done
  rm -rf "${corpora[@]}"
  return "$failed"
}
if [ "$mode" = fuzz ]; then
  fuzz_stage
  exit 0
fi

# Each library file compiled alone (the syntax-check preset: clang -fsyntax-only, one file per unit as a build
# without unity batches has them): every build of this command batches the files (unity builds), and a file that
# compiles only beside its neighbours (a missing #include, a helper of another file) must still fail. A CI stage
# (the first of `sanitizers`): it costs the test command's 2 cores minutes that a user's check after a change does
# not need.
standalone_check_stage() {
  stage "each library file compiled alone (clang -fsyntax-only)"
  configure syntax-check build-alone
  if ! cmake --build --preset syntax-check -j"$jobs" > build-alone/check.log 2>&1; then
    grep -E -A5 'error|FAILED' build-alone/check.log | head -n 60 >&2
    echo "standalone check: a library file does not compile alone (build-alone/check.log)" >&2
    return 1
  fi
}

release_stages() {
  # First, before any build: the README's length and no issue or session numbers in code comments or the README
  # (scripts/check-docs.sh; grep only).
  stage "docs check (README length, issue and session references)"
  bash scripts/check-docs.sh
  stage "build (Release)"
  configure release build
  cmake --build --preset release -j"$jobs"
  stage "tests (Release)"
  ctest --preset release -j"$jobs"
}

sanitizer_stages() {
  standalone_check_stage
  stage "build (address,undefined sanitizers)"
  configure asan-ubsan build-asan
  cmake --build --preset asan-ubsan -j"$jobs"
  stage "tests (address,undefined sanitizers)"
  # Every test but those labelled long (seconds in the Release run, tens under the sanitizers: the Release run
  # covers them) and the install test (packaging, not memory safety).
  ctest --preset asan-ubsan -j"$jobs"

  stage "build (thread sanitizer: the haptic loops and the parallel narrowphase)"
  # The haptics module runs a 1 kHz device thread beside a simulation thread, and the Bullet plugin runs a step's
  # CCD on a pool of threads: both must be TSan clean. The tree builds the two suites whose tests start threads
  # (bullet_thread_tests, haptics_thread_tests) and runs their tests but the long ones.
  configure tsan build-tsan
  cmake --build --preset tsan -j"$jobs"
  stage "tests (thread sanitizer)"
  # The solver-mode drop reads the bunny's field and shell from the suites' model cache (textbook-model-cache,
  # keyed by the mesh and settings): when the Release tests of the same checkout built them (CI runs the test
  # command first), the entries are copied, bit for bit what this build would write, instead of building the
  # 128^3 field under TSan.
  if [ -d build/tests/textbook-model-cache ]; then
    mkdir -p build-tsan/tests
    cp -rn build/tests/textbook-model-cache build-tsan/tests/
  fi
  ctest --preset tsan -j"$jobs"
  fuzz_stage
}

if [ "$mode" = sanitizers ]; then
  sanitizer_stages
else
  release_stages
fi
