#pragma once
// The key table's section of a whole case file (src/input/key_table.hpp), with every section
// below it registered.
#include "src/input/key_table.hpp"

namespace ckpd {

// Throws std::logic_error when the table is incomplete (a key names a section that is not
// registered).
const KeySection& case_key_section();

}  // namespace ckpd
