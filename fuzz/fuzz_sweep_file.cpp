// libFuzzer harness: the sweep-file loader (load_sweep: parameters, ranges, grids, expressions,
// tables, metrics, and every run's resolved case). The input is written to sweeps/ in a copy of
// cases/, so the seeds' `base: ../mode1_2d.yaml` resolves. An input must either load or throw
// CaseError/SweepError; anything else is a finding.
#include <cstdint>
#include <string>

#include "fuzz/fuzz_workdir.hpp"
#include "src/sweep/sweep_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string file = ckpd::fuzz::write_input("sweeps/fuzz_sweep.yaml", data, size);
  try {
    ckpd::sweep::load_sweep(file);
  } catch (const ckpd::CaseError&) {
  }
  return 0;
}
