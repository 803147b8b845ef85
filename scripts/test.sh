#!/usr/bin/env bash
# The test command (docs/testing.md): installs dependencies, checks the docs' rules (scripts/check-docs.sh), builds
# (Release) and runs every test suite; a clang -fsyntax-only pass over each library file alone, run on the cores the
# tests leave idle, fails a file that compiles only beside its neighbours (the builds batch their files: unity builds).
# CI (.ci/run) runs the test command, then this script's `sanitizers` stages: the core and its tests rebuilt with
# AddressSanitizer + UndefinedBehaviorSanitizer and run again, the threaded haptics and Bullet tests under
# ThreadSanitizer, and the field, shell, scene, segment-file and haptic-scene readers fuzzed briefly (libFuzzer,
# clang). The test command is what a user runs after a change (its times: docs/testing.md); the sanitizer stages,
# which take longer than the rest together, run in CI.
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
source scripts/configure-release.sh
jobs=$(nproc)

# Every build uses Ninja: unlike the Makefiles (which finish a target, link included, before compiling anything of
# the targets that link it) it compiles a suite's units while the libraries it links are still being built, so a
# core does not idle through a library's last unit (the haptics library's are the longest under the sanitizers).
# A build folder configured with another generator before is configured afresh (CMake cannot switch in place).
configure() {
  local dir=$1
  shift
  if [ -f "$dir"/CMakeCache.txt ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir"/CMakeCache.txt; then
    rm -rf "$dir"/CMakeCache.txt "$dir"/CMakeFiles
  fi
  cmake -G Ninja -S . -B "$dir" "$@" >/dev/null
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
  CC=clang CXX=clang++ configure build-fuzz -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DSDFCCD_BUILD_FUZZERS=ON -DSDFCCD_BUILD_TESTS=OFF \
    -DSDFCCD_BUILD_TOOLS=OFF -DSDFCCD_BUILD_BULLET=OFF -DSDFCCD_BUILD_HAPTICS=ON -DSDFCCD_BUILD_RENDER=OFF \
    -DCMAKE_UNITY_BUILD=ON
  local targets=(fuzz_field_loader fuzz_shell_loader fuzz_scene_loader fuzz_segment_file fuzz_haptic_scene)
  cmake --build build-fuzz -j"$jobs" --target "${targets[@]}"
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

# Each library file compiled alone (clang -fsyntax-only, one file per unit as a user's build has them): every
# build of this command batches the libraries' files (unity builds, below), and a file that compiles only beside
# its neighbours (a missing #include, a helper of another file) must still fail the command. It runs in the
# background at the idle scheduling class (chrt --idle: only on a core the others leave idle: the build's links and
# last units, ctest's tail) from the Release build on, and is waited for after the tests (its stage line counts its
# CPU time; started with the tests instead, its tail would run alone after them).
# Clang because its -fsyntax-only costs half of GCC's (template instantiation is most of it; no code is generated).
alone_pid=
start_standalone_check() {
  CC=clang CXX=clang++ configure build-alone -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-DNDEBUG \
    -DCMAKE_CXX_FLAGS=-Wno-unknown-warning-option -DSDFCCD_SYNTAX_CHECK=ON -DSDFCCD_BUILD_TESTS=OFF \
    -DSDFCCD_BUILD_TOOLS=OFF -DSDFCCD_BUILD_RENDER=OFF
  (
    TIMEFORMAT='standalone check: wall %R s, CPU %U s user + %S s sys'
    time chrt --idle 0 cmake --build build-alone -j"$jobs"
  ) > build-alone/check.log 2>&1 &
  alone_pid=$!
}
wait_standalone_check() {
  stage "each library file compiled alone (clang -fsyntax-only; the rest of its run, after the overlap)"
  if ! wait "$alone_pid"; then
    grep -E -A5 'error|FAILED' build-alone/check.log | head -n 60 >&2
    echo "standalone check: a library file does not compile alone (build-alone/check.log)" >&2
    return 1
  fi
  tail -n 1 build-alone/check.log >&2
}

release_stages() {
  # First, before any build: the README's length and no issue or session numbers in code comments or the README
  # (scripts/check-docs.sh; grep only).
  stage "docs check (README length, issue and session references)"
  bash scripts/check-docs.sh
  stage "build (Release)"
  # The same folder and settings as the main job's (scripts/configure-release.sh): after it, only the suites compile.
  # The standalone check above keeps the guarantee a one-file-per-unit build gives.
  configure_release
  start_standalone_check
  cmake --build build -j"$jobs"
  stage "tests (Release)"
  ctest --test-dir build --output-on-failure -j"$jobs" --timeout 600
  wait_standalone_check
}

sanitizer_stages() {
  stage "build (address,undefined sanitizers)"
  # Sanitizer builds: -O1 -g1 (line tables: reports keep file:line) instead of RelWithDebInfo's -O2 -g, whose full
  # debug info and -O2 make compiling and linking these builds slow (the usual advice for ASan/TSan is -O1 anyway).
  # Unity builds (batches of 8 files) for the libraries too in the sanitizer and fuzz builds (the suites and the tool
  # always are): a batch instantiates once what its files share. The test command's Release build batches them too; its
  # standalone check (clang -fsyntax-only of each library file, one file per unit as a user's build has them) fails a
  # file that compiles only beside its neighbours.
  sanitizer_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_UNITY_BUILD=ON)
  # The bench and report commands (demo code that drives the library at length) are left out: the library
  # code they call runs under the sanitizers in the suites; the test command's Release run covers the commands.
  # UBSan's alignment and null checks are left out of this GCC build: GCC instruments every pointer use in the inlined
  # Eigen and Bullet code with them, which about doubles the compile of the files that inline most (bullet_ext's contact
  # system, haptics' penalty renderer). AddressSanitizer still reports every null dereference (SEGV at address 0, with
  # its stack); a misaligned load does not fault on x86-64, and C++17's aligned new gives Eigen's fixed-size members
  # their alignment. The clang fuzz stage below keeps both checks on the readers.
  configure build-asan "${sanitizer_flags[@]}" -DSDFCCD_SANITIZE=address,undefined -DSDFCCD_SANITIZE_SKIP=alignment,null \
    -DSDFCCD_BUILD_RENDER=OFF -DSDFCCD_BUILD_BENCHMARKS=OFF
  cmake --build build-asan -j"$jobs"
  stage "tests (address,undefined sanitizers)"
  # The install/consumer test proves packaging, not memory safety: the test command's Release run covers it.
  # The textbook mechanics suites (tests/bullet/textbook_*_test.cpp: seconds of simulated time each) run their
  # short subset here, the cases whose names end in "Short"; the Release run runs them all.
  # Long runs of code that shorter cases already drive under the sanitizers are left to the Release run too: the
  # golden hash (600 frames of 20 bunnies), the 100,000-step resting box, the haptic sessions that run seconds of
  # the peg and the alpha puzzle, the cached alpha-puzzle field, and 20,000 random rays against the bunny's field and
  # its triangles (the slowest cases under ASan; the shorter ray and sweep cases run here).
  textbook='Textbook[A-Za-z]*\.|Incline\.'
  long_runs='GoldenHash\.|ShapeQueries\.RandomRaysMatchTheTriangles|Stability\.RestingBoxGainsNoEnergy|HapticSession\.(ShrunkHole|PegGoesInto|Fig13Pocket)|AlphaPuzzleScene\.FieldIsCached'
  # ... and the golden drop on 1, 2 and 4 threads, the Fig. 7 peg sessions, the solved alpha puzzle's sessions and the
  # 8-bunny piles run with and without the CCD history (each drives code the shorter cases drive, for seconds).
  long_runs+='|ParallelNarrowphase\.GoldenDropIdenticalFor1To4Threads|HapticPegFig7\.|AlphaPuzzleSolved\.|CoherentWorld\.'
  # ... and the 6,000-point peg slides that compare the per-axis certificates with the fresh query for seconds (the
  # certificates' own random-grid and ridged-wall cases run here).
  long_runs+='|PenaltyRendererAxisCertificates\.PegSlide|GodObjectAxisCertificates\.PegSlide'
  # ... and solver mode's drop compared on 1 and 2 threads: the TSan stage runs it on the pool, and the
  # solver's short textbook cases (the second run below) and the other shapes' solver-mode cases run its code under ASan.
  long_runs+='|ParallelNarrowphase\.SolverDropIdenticalFor1And2Threads'
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 900 -LE install -E "$textbook|$long_runs"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 900 -R 'Textbook[A-Za-z]*\..*Short$'

  stage "build (thread sanitizer: the haptic loops and the parallel narrowphase)"
  # The haptics module runs a 1 kHz device thread beside a simulation thread, and the Bullet plugin runs a step's
  # CCD on a pool of threads: both must be TSan clean.
  # One small suite, tsan_tests (tests/CMakeLists.txt): the haptics and Bullet test files whose tests start threads,
  # not the whole haptics and Bullet suites (their single-threaded QP, friction and coupling files are much of the
  # compile and run no thread).
  configure build-tsan "${sanitizer_flags[@]}" -DSDFCCD_SANITIZE=thread \
    -DSDFCCD_BUILD_RENDER=OFF -DSDFCCD_BUILD_TOOLS=OFF -DSDFCCD_BUILD_BENCHMARKS=OFF
  cmake --build build-tsan -j"$jobs" --target tsan_tests
  stage "tests (thread sanitizer)"
  # The threads are the device loop, the simulation loop beside it and the SDF builder's workers: every haptics
  # test that runs them, not the single-threaded sessions that only run longer (the alpha puzzle, the clearance
  # cache's bit-identity runs, the peg, Fig. 13, 10 s of god-object pushing on a stiff plane: slow under TSan, all in
  # the Release and ASan runs).
  single_threaded_long='AlphaPuzzleScene\.|GodObjectClearanceCache\.|HapticSession\.(ShrunkHole|PegGoesInto|Fig13Pocket)|PassivityController\.ConstraintSession'
  # ... and the sessions of the paper's scenes (the solved alpha puzzle, the Fig. 7 peg, the landing gear, Fig. 13),
  # single-threaded too.
  single_threaded_long+='|AlphaPuzzleSolved\.|HapticPegFig7\.|LandingGear\.|Fig13NarrowPassage\.|PenaltyRendererCoherence\.'
  single_threaded_long+='|FrictionQp\.|GodObjectFriction\.'  # the friction solver's random problems: no threads
  # The Bullet file's tests: the narrowphase pool, the deferred queries and the shape cache they read, and a pile in
  # penalty mode that runs on the pool and goes to sleep, and solver mode's drop on 1 and 2 threads (the golden drop
  # on 1-4 threads runs in the Release run). One ctest run for both files: -j2 packs their tests together.
  # That drop reads the bunny's field and shell from the suites' model cache (textbook-model-cache, keyed by the
  # mesh and settings): when the Release tests of the same checkout built them (CI runs the test command first), the
  # entries are copied, bit for bit what this build would write; building the 128^3 field under TSan would be most of
  # the stage. The haptic tests here still run the SDF builder's workers (their procedural scenes' fields).
  if [ -d build/tests/textbook-model-cache ]; then
    mkdir -p build-tsan/tests
    cp -rn build/tests/textbook-model-cache build-tsan/tests/
  fi
  tsan_long="$single_threaded_long|ParallelNarrowphase\\.GoldenDropIdenticalFor1To4Threads"
  TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build-tsan --output-on-failure -j"$jobs" --timeout 900 -L tsan_tests \
    -E "$tsan_long"
  fuzz_stage
}

if [ "$mode" = sanitizers ]; then
  sanitizer_stages
else
  release_stages
fi
