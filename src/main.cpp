// The `ckpd` command line: run a case, inspect a discretisation.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "src/cli/patch_test_command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"ckpd: continuum-kinematics-based peridynamics impact simulator"};
  app.require_subcommand(1);
  ckpd::add_patch_test_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "ckpd: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
