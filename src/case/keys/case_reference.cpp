#include "src/case/keys/case_reference.hpp"

#include "src/case/keys/case_keys.hpp"
#include "src/input/key_reference.hpp"

namespace ckpd {

namespace {

const char* const kIntro =
    R"(Every key of a case file, section by section. This page is generated from the key
table that ckpd's loader reads its keys from (`ckpd schema --markdown`; a test fails when the
page and the table differ), so it lists exactly the keys ckpd accepts.

Units are SI throughout: m, s, kg, Pa (N/m^2), J; mesh rotations are in degrees. A 2D body is a
plate of unit thickness: its densities are per area (kg/m^2), its loads per length (N/m).

Each table gives a key's **Type**, its **Unit** (`-`: none), its **Default** (what holds when
the key is left out; `required`: it must be given), the **Allowed** values and its **Meaning**.
Where a key picks a variant (a shape's `type`, a material's `model`, a condition's `type`, the
contact `law`), a map takes its section's keys and those of its variant. An unknown or misspelt
key is an error naming the file, the line, the key and the nearest known one; `ckpd check
CASE` checks a case without running it.

## Checking keys in an editor

`ckpd schema > ckpd.schema.json` writes the JSON Schema (draft 2020-12) of the case file.
Editors that use the YAML language server (VS Code with the YAML extension, Neovim, Emacs,
Helix, ...) complete keys, show their meaning and mark unknown ones when the case file's first
line names the schema, by a path relative to the case file or a URL:

    # yaml-language-server: $schema=ckpd.schema.json

The cases in `cases/` name `docs/ckpd.schema.json`, the schema of this version, kept in the
repository (a test checks that it is what `ckpd schema` prints). The schema checks the keys
and the types of their values; ranges, units and the rules between bodies (a condition's body
exists, a horizon is at least the spacing) are `ckpd check`'s.
)";

}  // namespace

std::string case_file_schema() {
  return key_schema_json(case_key_section(), "ckpd case file");
}

std::string case_file_reference() {
  return key_reference_markdown(case_key_section(), "Case-file reference", kIntro);
}

}  // namespace ckpd
