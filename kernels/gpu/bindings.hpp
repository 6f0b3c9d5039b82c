#pragma once
// The names the C++ side and the shaders share: storage-buffer binding points and the work-group
// size. raycast/gpu.cpp binds and dispatches by them, and every shader is compiled with them as
// #defines (glslDefines()), so gpu/shaders/*.glsl say `binding = BIND_HITS`, never a number.

#include <cstdint>
#include <string>

namespace polyloc::gpu_bindings {

enum Binding : unsigned {
  kNodes = 0,   // BVH nodes
  kVerts = 1,   // triangle corners, leaf order
  kTriIds = 2,  // Mesh triangle of each leaf triangle
  kIn0 = 3,     // poses (scans), ray origins or free-space points
  kIn1 = 4,     // beams (scans) or ray directions
  kHits = 5,    // range bits and triangle per ray; free-space flags
  kTerms = 6,   // beam model terms per beam
  kTables = 7,  // hit density table
  kSums = 8,    // log-likelihood per pose
};

inline constexpr uint32_t kGroupSize = 64;  // local_size_x of every program

inline std::string glslDefines() {
  std::string s;
  auto define = [&s](const char* name, unsigned value) { s += "#define " + std::string(name) + " " + std::to_string(value) + "\n"; };
  define("GROUP_SIZE", kGroupSize);
  define("BIND_NODES", kNodes), define("BIND_VERTS", kVerts), define("BIND_TRI_IDS", kTriIds);
  define("BIND_IN0", kIn0), define("BIND_IN1", kIn1), define("BIND_HITS", kHits);
  define("BIND_TERMS", kTerms), define("BIND_TABLES", kTables), define("BIND_SUMS", kSums);
  return s;
}

}  // namespace polyloc::gpu_bindings
