// Load polygon maps with assimp (OBJ, PLY, STL, glTF/GLB, DAE and whatever else assimp reads)
// and save them again. Errors are polyloc::MapError naming the file and the problem.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <stdexcept>
#include <string>

namespace polyloc {

class MapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class UpAxis { Z, Y, X };  // file's up axis; the map frame is always z up

struct LoadOptions {
  double scale = 1.0;       // multiply coordinates (e.g. 0.001 for a CAD file in mm)
  UpAxis up_axis = UpAxis::Z;  // Y for most glTF/DAE exports from modelling tools
  bool merge_vertices = true;  // join identical vertices so validation sees shared edges
};

// Throws MapError: missing file, unreadable/corrupt file, or a file without triangles.
Mesh loadMesh(const std::string& path, const LoadOptions& options = {});
UpAxis parseUpAxis(const std::string& text);  // "z", "y", "x" (case-insensitive); throws MapError

// Writes by extension (.obj, .ply, .stl, .gltf, .glb, .dae); one object per label so the
// labels survive a round trip. Throws MapError on failure.
void saveMesh(const Mesh& mesh, const std::string& path);

}  // namespace polyloc
