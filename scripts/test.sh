#!/usr/bin/env bash
# Sets up (installs missing Debian packages, the tests' too; configures ./build with the tests)
# then builds everything in ./build (the test programs too) and runs the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
# The benchmarks (bench/) are not built here: no test uses them.
CKPD_TESTS=ON CKPD_BENCH=OFF scripts/setup.sh
cmake --build build -j "$(nproc)"
# One test at a time: each test already uses every core through OpenMP, and two OpenMP processes
# sharing two cores slow each other down far more than they gain.
ctest --test-dir build --output-on-failure "$@"
