#include "src/cli/schema_command.hpp"

#include <iostream>
#include <memory>

#include "src/case/keys/case_reference.hpp"

namespace ckpd {

void add_schema_command(CLI::App& app) {
  auto markdown = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "schema",
      "print the JSON Schema of the case file (for editors: ckpd schema > ckpd.schema.json)");
  cmd->add_flag("--markdown", *markdown,
                "print the case-file reference (docs/CASE_FILE.md) instead");
  cmd->callback(
      [markdown] { std::cout << (*markdown ? case_file_reference() : case_file_schema()); });
}

}  // namespace ckpd
