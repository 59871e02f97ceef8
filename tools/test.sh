#!/usr/bin/env bash
# The whole test suite, built with AddressSanitizer and UndefinedBehaviorSanitizer: the
# README's test command and CI (.ci/run) run this after tools/install-deps.sh.
#
# One instrumented build serves both purposes: every GoogleTest case runs (Highway kernels
# on every target the machine supports) and any memory error or undefined behaviour on the
# way fails the run (-fno-sanitize-recover). -O1 keeps the Highway kernels fast enough for
# the 10-million-input sweeps while compiling in about half the time of -O2. libstdc++'s own
# checks are on too (-D_GLIBCXX_ASSERTIONS: an out-of-range operator[] or front() of an empty
# vector aborts), which the sanitizers miss where the element is never read (a reference to
# cut_maps_[kNoFurCut] was formed and not used, 2026-11-28); benchmarks
# are built too, so a change that breaks them is caught. The test files themselves compile at
# -O0 (PELT_TEST_CODE_FLAGS, tests/CMakeLists.txt): a quarter less compile time for the suite,
# about the same run time. Each test binary runs as a few GoogleTest shards, not a process per
# case (PELT_TEST_SHARDS, tests/CMakeLists.txt): the same cases in about half the time; a
# failing shard's log shows each case it ran and its failures, and `ctest -R binary_name` runs
# one binary's shards. The libFuzzer targets need clang
# and run separately (tools/fuzz.sh, docs/robustness.md).
#   PELT_TEST_JOBS   build and ctest parallelism (default: nproc)
#   PELT_TEST_BUILD  build folder (default: build-test)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
jobs=${PELT_TEST_JOBS:-$(nproc)}
build=${PELT_TEST_BUILD:-build-test}

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -D_GLIBCXX_ASSERTIONS" \
  -DPELT_SANITIZE=address,undefined -DPELT_TEST_CODE_FLAGS=-O0 -DPELT_TEST_SHARDS=ON
cmake --build "$build" -j"$jobs"
# ASan's leak checker and UBSan both end the process with an error; halt_on_error makes
# ASan stop at the first report so the failing test names the cause.
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:halt_on_error=1} \
  UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
  ctest --test-dir "$build" --output-on-failure -j"$jobs"
