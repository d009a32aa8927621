// libFuzzer harness: the case loader (load_scene: YAML, every section's keys, geometry sampling,
// body construction). An input must either load or throw CaseError (exit 2 in the CLI); any
// other exception, a crash, a hang or a sanitizer report is a finding. The memory budget is set
// low (1 MiB: bodies of a few hundred points in 3D, about a thousand in 2D) so that a valid but
// large case is refused by the estimate instead of being built: the harness looks for loader
// bugs, not for big bodies. (At 16 MiB eight of the 20 seeds took 0.4-7 s each to set up in the
// Release build and over 60 s under the instrumentation on a loaded machine: those seeds, not
// any mutant, were all of a run's timeouts, and 30 minutes ran 1,400 inputs.)
#include <cstdint>
#include <string>

#include "fuzz/fuzz_workdir.hpp"
#include "src/case/case_loader.hpp"
#include "src/geometry/work_estimate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool budget = (ckpd::set_default_memory_budget(1ull << 20), true);
  (void)budget;
  const std::string file = ckpd::fuzz::write_input("fuzz_case.yaml", data, size);
  try {
    ckpd::load_scene(file);
  } catch (const ckpd::CaseError&) {
  }
  return 0;
}
