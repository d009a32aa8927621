#!/usr/bin/env bash
# Builds TARGET... in build-san: clang, AddressSanitizer + UndefinedBehaviorSanitizer
# (-fno-sanitize-recover=all) and libFuzzer's coverage instrumentation (-DCKPD_FUZZ=ON), -O1 -g.
# One build serves both scripts/test_sanitized.sh (ckpd, ckpd_tests) and scripts/fuzz.sh (the
# harnesses in fuzz/): the engine is compiled once. Environment: CKPD_SAN_BUILD (the folder,
# default build-san), CKPD_JOBS (parallel compiles, default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${CKPD_SAN_BUILD:-build-san}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DCKPD_FUZZ=ON -DCKPD_PYTHON=OFF -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache >/dev/null
fi
cmake --build "$build" -j "${CKPD_JOBS:-2}" --target "$@"
