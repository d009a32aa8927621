#!/usr/bin/env bash
# Installs the Debian packages ckpd builds with (only those that are missing), then configures
# ./build (Release, -O3) and builds what a run needs: the `ckpd` program and the Python module.
# The tests and benchmarks are not built here: scripts/test.sh builds and runs the tests
# (CKPD_TESTS=ON: it also installs what only the tests need). Safe to run again: it does only
# what is left to do.
set -euo pipefail
cd "$(dirname "$0")/.."

# What a run needs. libhwy-dev: Highway's vector logarithms for the Seth-Hill measures
# (bodies/CMakeLists.txt); libopenmpi-dev and openmpi-bin: MPI runs (`mpirun -np N ckpd run`,
# CMake option CKPD_MPI); libhdf5-openmpi-dev: the HDF5 for MPI, through which the ranks write
# frames and checkpoints; pybind11-dev, python3-dev, python3-numpy, python3-yaml: the Python
# module (python/); python3-h5py and python3-matplotlib: scripts/plot_history.py,
# scripts/render_damage.py and scripts/max_stretch.py.
packages=(cmake g++ make libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
          libhwy-dev libfcl-dev libassimp-dev libhdf5-dev libhdf5-openmpi-dev libopenmpi-dev
          openmpi-bin python3 pybind11-dev python3-dev python3-numpy python3-yaml python3-h5py
          python3-matplotlib)
tests="${CKPD_TESTS:-}"
if [ "$tests" = ON ]; then
  # What only the tests need. catch2: the C++ tests; libxml2-dev: the XDMF test parses the index
  # as XML; python3-pytest: the Python module's tests; mypy: the type check of examples/python
  # against the module's stubs; python3-jsonschema: the case files against `ckpd schema`;
  # python3-meshio: a run's per-body XDMF series read with meshio; clang, libclang-rt-14-dev
  # (libFuzzer, sanitizers) and libomp-dev: scripts/fuzz.sh and scripts/test_sanitized.sh.
  packages+=(catch2 libxml2-dev python3-pytest mypy python3-jsonschema python3-meshio clang
             libclang-rt-14-dev libomp-dev)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build_type="${CKPD_BUILD_TYPE:-Release}"
options=(-DCMAKE_BUILD_TYPE="$build_type")
# CKPD_BENCH=OFF (scripts/test.sh): the benchmarks in bench/ are not configured (no test uses
# them). CKPD_TESTS: ON configures the test programs (scripts/test.sh); unset, a new build folder
# is configured without them (no Catch2 needed) and an existing one keeps its choice.
[ -n "${CKPD_BENCH:-}" ] && options+=(-DCKPD_BENCH="$CKPD_BENCH")
if [ -n "$tests" ]; then
  options+=(-DCKPD_TESTS="$tests")
elif [ ! -f build/CMakeCache.txt ]; then
  options+=(-DCKPD_TESTS=OFF)
fi
cmake -S . -B build "${options[@]}" >/dev/null
# The program and, where CMake built its target (CKPD_PYTHON), the Python module.
targets=(ckpd)
grep -q "^CKPD_PYTHON:BOOL=ON" build/CMakeCache.txt && targets+=(_ckpd)
cmake --build build -j "$(nproc)" --target "${targets[@]}"
