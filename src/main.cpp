// The `ckpd` command line: run a case, inspect a discretisation.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "src/cli/check_command.hpp"
#include "src/cli/patch_test_command.hpp"
#include "src/cli/run_command.hpp"
#include "src/cli/sweep_command.hpp"
#include "src/output/checkpoint.hpp"
#include "src/scene/case_node.hpp"

int main(int argc, char** argv) {
  CLI::App app{"ckpd: continuum-kinematics-based peridynamics impact simulator"};
  app.require_subcommand(1);
  int exit_status = 0;
  ckpd::add_run_command(app, exit_status);
  ckpd::add_check_command(app);
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
