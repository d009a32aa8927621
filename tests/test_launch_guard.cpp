// Without MPI ckpd is one process: started by mpirun or srun as several, `run` and an unsharded
// `sweep` refuse with exit 2 and write nothing (src/cli/launch_guard.hpp), instead of N copies
// writing the same files. A sharded sweep, a group of one and CKPD_ALLOW_MULTIPLE=1 are let
// through, and so is `run` in a build with MPI (its processes are one run's ranks; tests/mpi/).
#include <stdlib.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "run_helpers.hpp"
#include "src/cli/launch_guard.hpp"
#include "src/engine/ranks.hpp"

using namespace ckpd::testing;

namespace {

// Sets an environment variable for the test's scope (the ckpd children inherit it).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) { setenv(name, value, 1); }
  ~ScopedEnv() { unsetenv(name_); }

 private:
  const char* name_;
};

const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: cube, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.003, 0.003, 0.003]},
     spacing: 0.001, horizon_ratio: 2.015}
time: {steps: 3}
)";

}  // namespace

TEST_CASE("the launchers' process counts are read and a group of one is let through", "[cli]") {
  CHECK_FALSE(ckpd::parallel_launch_refusal().has_value());
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"}) {
    {
      ScopedEnv one(name, "1");
      CHECK_FALSE(ckpd::parallel_launch_refusal().has_value());
    }
    ScopedEnv four(name, "4");
    CHECK_FALSE(ckpd::parallel_launch_refusal(true).has_value());  // an MPI run's ranks
    const auto refusal = ckpd::parallel_launch_refusal();
    REQUIRE(refusal.has_value());
    CHECK(refusal->find(std::string(name) + "=4") != std::string::npos);
    ScopedEnv allow("CKPD_ALLOW_MULTIPLE", "1");
    CHECK_FALSE(ckpd::parallel_launch_refusal().has_value());
  }
}

TEST_CASE("run under mpirun with two processes refuses and writes nothing", "[cli]") {
  // A build with MPI runs them as ranks of one run (tests/mpi/mpi_check.sh); a faked launcher
  // environment would have it wait for ranks that do not exist.
  if (ckpd::ranks::built_with_mpi()) {
    WARN("built with MPI: run's refusal applies to builds without it");
    return;
  }
  const auto dir = fresh_dir("launch_guard");
  const std::string file = write_file(dir / "case.yaml", kCase);
  ScopedEnv two("OMPI_COMM_WORLD_SIZE", "2");
  const CommandResult r = run_ckpd("run " + file + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("one of 2 started together (OMPI_COMM_WORLD_SIZE=2)") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out"));
  // check writes nothing and may run anywhere.
  CHECK(run_ckpd("check " + file + " --steps 1").exit_code == 0);
}
