// The `ckpd` command line: run a case, inspect a discretisation.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <exception>
#include <iostream>

#include "src/cli/check_command.hpp"
#include "src/cli/cli_options.hpp"
#include "src/cli/patch_test_command.hpp"
#include "src/cli/run_command.hpp"
#include "src/cli/schema_command.hpp"
#include "src/cli/sweep_command.hpp"
#include "src/input/case_node.hpp"
#include "src/input/nearest_name.hpp"
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

// A usage error: one line naming what was wrong, exit 2 (as for bad input in a case file).
int usage_error(const std::string& message) {
  std::cerr << "ckpd: error: " << message << " (see ckpd --help)\n";
  return 2;
}

// The first argument must be a subcommand or an option of ckpd itself; CLI11 would report a
// misspelt command as "A subcommand is required".
std::string check_command_name(int argc, char** argv, const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  const std::string list = ckpd::join_names(names);
  if (argc < 2) return "no command given (commands: " + list + ")";
  const std::string first = argv[1];
  if (first.empty() || first[0] == '-') return "";
  for (const std::string& n : names)
    if (n == first) return "";
  return "unknown command '" + first + "'" + ckpd::did_you_mean(first, names) +
         " (commands: " + list + ")";
}

}  // namespace

int main(int argc, char** argv) {
  choose_omp_wait_policy(argv);
  ckpd::set_command_line(argc, argv);
  CLI::App app{"ckpd: continuum-kinematics-based peridynamics impact simulator"};
  app.require_subcommand(1);
  app.set_version_flag("--version", ckpd::version_line(), "print the version and build flags");
  int exit_status = 0;
  ckpd::add_run_command(app, exit_status);
  ckpd::add_check_command(app, exit_status);
  ckpd::add_patch_test_command(app);
  ckpd::add_sweep_command(app, exit_status);
  ckpd::add_schema_command(app);
  if (const std::string bad = check_command_name(argc, argv, app); !bad.empty())
    return usage_error(bad);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end parsing with exit code 0; every other parse error is a usage
    // error (CLI11's own codes, 105-109, are not what scripts expect).
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string message = e.what();
    for (const CLI::App* sub : app.get_subcommands()) message = sub->get_name() + ": " + message;
    return usage_error(message);
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
