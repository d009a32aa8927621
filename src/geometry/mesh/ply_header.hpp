#pragma once
// A PLY file's header checked against the file before assimp reads it: assimp's PLY importer
// spent its whole CPU limit (two minutes) on a header cut short before `end_header`. The
// header must end in `end_header` within its first MiB, name a known format and property
// types, and its element counts must fit in the bytes after it.
#include <string>

namespace ckpd {

// Throws MeshError (what was expected, naming `path`) for a header that fails these checks.
void check_ply_header(const std::string& path);

}  // namespace ckpd
