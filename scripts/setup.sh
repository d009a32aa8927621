#!/usr/bin/env bash
# Installs the Debian packages ckpd builds with (only those that are missing), then configures and
# builds it in ./build (Release, -O3). Safe to run again: it does only what is left to do.
set -euo pipefail
cd "$(dirname "$0")/.."

# python3-h5py and python3-matplotlib: scripts/render_damage.py and scripts/max_stretch.py;
# python3-meshio: the test that reads a run's per-body XDMF series with meshio;
# libxml2-dev: the XDMF test parses the index as XML; pybind11-dev, python3-dev, python3-numpy,
# python3-pytest, python3-yaml: the Python module (python/) and its tests; clang,
# libclang-rt-14-dev (libFuzzer, sanitizers) and libomp-dev: scripts/fuzz.sh; libopenmpi-dev and
# openmpi-bin: MPI runs (`mpirun -np N ckpd run`, CMake option CKPD_MPI) and their tests;
# libhdf5-openmpi-dev: the HDF5 for MPI, through which the ranks write frames and checkpoints;
# libhwy-dev: Highway's vector logarithms for the Seth-Hill measures (bodies/CMakeLists.txt);
# python3-jsonschema: the tests that check the case files against `ckpd schema`.
packages=(cmake g++ make libeigen3-dev libyaml-cpp-dev libcli11-dev catch2 nlohmann-json3-dev
          libhwy-dev libfcl-dev libassimp-dev libhdf5-dev libhdf5-openmpi-dev libxml2-dev python3 python3-h5py
          python3-matplotlib python3-meshio
          pybind11-dev python3-dev python3-numpy python3-pytest python3-yaml python3-jsonschema
          clang libclang-rt-14-dev libomp-dev libopenmpi-dev openmpi-bin)
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
# CKPD_BENCH=OFF (scripts/test.sh): without the benchmarks in bench/, which no test uses.
cmake -S . -B build -DCMAKE_BUILD_TYPE="$build_type" -DCKPD_BENCH="${CKPD_BENCH:-ON}" >/dev/null
cmake --build build -j "$(nproc)"
