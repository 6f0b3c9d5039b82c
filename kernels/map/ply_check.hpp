// Structural check of a PLY file before assimp reads it (private to kernels/map).
#pragma once

#include <string>

namespace polyloc::detail {

// assimp 5.2's PLY reader hangs on some corrupt headers and reads past the end of (or asserts
// on) truncated bodies. This walks header and body the way the format defines them and throws
// MapError naming the file and the problem; a file that passes is complete and well-formed.
// Files that do not start with "ply" are left to assimp.
void checkPlyStructure(const std::string& path);

}  // namespace polyloc::detail
