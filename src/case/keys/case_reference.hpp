#pragma once
// The case file's key table as `ckpd schema` prints it: a JSON Schema and the reference page
// docs/CASE_FILE.md (a test checks that the page is this text).
#include <string>

namespace ckpd {

std::string case_file_schema();
std::string case_file_reference();

}  // namespace ckpd
