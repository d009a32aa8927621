#!/usr/bin/env bash
# Builds ckpd and the tests with AddressSanitizer and UndefinedBehaviorSanitizer (clang, in
# build-san: scripts/sanitizer_build.sh) and runs the fast tests under them. Any sanitizer
# report fails the test that triggered it (-fno-sanitize-recover=all, abort_on_error), so a
# green run is a clean one. The tests run `ckpd` itself too: that binary is the sanitized one.
#   scripts/test_sanitized.sh [Catch2 test spec, default: the fast tests]
set -euo pipefail
cd "$(dirname "$0")/.."
spec="${1:-~[physics]~[stability]~[energy]~[calibration]}"
build="${CKPD_SAN_BUILD:-build-san}"
scripts/sanitizer_build.sh ckpd ckpd_tests
# detect_leaks=0: LeakSanitizer needs ptrace, which containers often forbid; leaks are not the
# point here (use-after-free, overflows and undefined behaviour are).
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
"./$build/tests/ckpd_tests" "$spec"
