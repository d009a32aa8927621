#!/usr/bin/env bash
# Builds the tests with AddressSanitizer and UndefinedBehaviorSanitizer (-DCKPD_SANITIZE=
# address,undefined, in build-asan) and runs the fast tests under them. Any sanitizer report
# fails the test that triggered it (-fno-sanitize-recover=all), so a green run is a clean one.
#   scripts/test_sanitized.sh [Catch2 test spec, default: the fast tests]
set -euo pipefail
cd "$(dirname "$0")/.."
spec="${1:-~[physics]~[stability]~[energy]~[calibration]}"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
  -DCKPD_SANITIZE=address,undefined \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache >/dev/null
cmake --build build-asan -j "${CKPD_JOBS:-2}" --target ckpd ckpd_tests
# detect_leaks=0: LeakSanitizer needs ptrace, which containers often forbid; leaks are not the
# point here (use-after-free, overflows and undefined behaviour are).
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
./build-asan/tests/ckpd_tests "$spec"
