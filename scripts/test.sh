#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (ctest) in the Release build;
# then builds again with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/, -O1) and
# runs the unit, round-trip, corrupt-input, reliability and fuzz-corpus-replay tests there.
# CAPZ_SKIP_ASAN=1 skips the sanitizer pass (e.g. for a quick local run). Last, a ThreadSanitizer
# build (build-tsan/) of the libraries and the threads tests alone runs their short tests
# (-T N's window pipelines); CAPZ_SKIP_TSAN=1 skips it. Both sanitizer builds use clang
# (scripts/install-deps.sh installs it for the fuzzers): with its sanitizers it compiles capz in
# about half the time GCC takes with ASan + UBSan, and in 0.8x with TSan.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/build_env.sh
sanitizer_compilers=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)
scripts/install-deps.sh
scripts/build.sh
(cd build && ctest --output-on-failure -j"$(nproc)" --timeout 900)

if [ "${CAPZ_SKIP_ASAN:-0}" != "1" ]; then
  cmake -S . -B build-asan $(capz_generator build-asan) -DCMAKE_BUILD_TYPE=Debug \
    "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -g1" "-DCMAKE_C_FLAGS_DEBUG=-O1 -g1" "${sanitizer_compilers[@]}" \
    -DCAPZ_SANITIZE=address,undefined -DCAPZ_BUILD_BENCH=OFF -DCAPZ_BUILD_PYTHON=OFF >/dev/null
  # Only the executables this pass runs (tests/CMakeLists.txt); the others' tests show up as
  # *_NOT_BUILT without labels, so the label filter below leaves them out.
  cmake --build build-asan -j"$(nproc)" --target capz_sanitizer_tests
  # Any sanitizer report fails the test (the build uses -fno-sanitize-recover=all).
  export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # Not the tests over whole shared sequences (names with Shared, HorseGallop, ChickenCrossing):
  # real work, which the Release suite above runs (a fifth of this pass's time).
  (cd build-asan && ctest --output-on-failure -j"$(nproc)" --timeout 1800 \
     -L '^(unit|roundtrip|corrupt|reliability|fuzz)$' -E 'Shared|HorseGallop|ChickenCrossing')
fi

if [ "${CAPZ_SKIP_TSAN:-0}" != "1" ]; then
  cmake -S . -B build-tsan $(capz_generator build-tsan) -DCMAKE_BUILD_TYPE=Debug \
    "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -g1" "-DCMAKE_C_FLAGS_DEBUG=-O1 -g1" "${sanitizer_compilers[@]}" \
    -DCAPZ_SANITIZE=thread -DCAPZ_BUILD_BENCH=OFF -DCAPZ_BUILD_PYTHON=OFF >/dev/null
  cmake --build build-tsan -j"$(nproc)" --target capz_threads_tests
  # The synthetic and data/ tests (the shared-data ones are for the Release suite): a race or a
  # lock-order inversion fails the run (third-party suppressions: tests/threads/tsan.supp).
  TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/threads/tsan.supp" \
    build-tsan/tests/capz_threads_tests --gtest_filter='ThreadsSynthetic.*:ThreadsRepo.*'
fi
