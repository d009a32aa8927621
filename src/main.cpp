// The `ckpd` command line: run a case, inspect a discretisation.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <exception>
#include <iostream>

#include "src/cli/check_command.hpp"
#include "src/cli/patch_test_command.hpp"
#include "src/cli/run_command.hpp"
#include "src/cli/sweep_command.hpp"
#include "src/input/case_node.hpp"
#include "src/output/checkpoint.hpp"

namespace {

// OpenMP reads its wait policy once, when the runtime loads, before main. GNU OpenMP's default
// lets idle threads spin between parallel regions; on a machine whose cores are shared (the
// usual workstation, and every CI machine) the spinning thread takes the core that the serial
// part of a step needs: the LAMMPS in.peri.pmb counterpart (3,487 points) ran 2.2x slower at 2
// threads than with threads that sleep, while the 50,653-point block lost 2-4 % by sleeping
// (docs/PERFORMANCE.md). So unless the user chose a policy, ckpd starts itself once more with
// OMP_WAIT_POLICY=passive; OMP_WAIT_POLICY=active (or any value) in the environment is kept.
void choose_omp_wait_policy(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 0) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: then run as we are
}

}  // namespace

int main(int argc, char** argv) {
  choose_omp_wait_policy(argv);
  CLI::App app{"ckpd: continuum-kinematics-based peridynamics impact simulator"};
  app.require_subcommand(1);
  int exit_status = 0;
  ckpd::add_run_command(app, exit_status);
  ckpd::add_check_command(app, exit_status);
  ckpd::add_patch_test_command(app);
  ckpd::add_sweep_command(app, exit_status);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ckpd::CaseError& e) {
    std::cerr << "ckpd: error: " << e.what() << '\n';
    return 2;
  } catch (const ckpd::CheckpointError& e) {
    std::cerr << "ckpd: error: " << e.what() << '\n';
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "ckpd: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ckpd: error: " << e.what() << '\n';
    return 1;
  }
  return exit_status;
}
