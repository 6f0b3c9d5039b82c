// Load polygon maps with assimp (OBJ, PLY, STL, glTF/GLB, DAE and whatever else assimp reads)
// and save them again. Errors are polyloc::MapError naming the file and the problem.
//
// Coordinates are taken as the file holds them, node transforms applied, then scaled and
// rotated into the map frame (z up) by LoadOptions. The default up axis, Auto, follows each
// format's convention: glTF/GLB are y up (their spec), a DAE says so in its <up_axis>, and
// OBJ/PLY/STL have none, so they are read as z up (the robotics convention). saveMesh writes
// by the same conventions, so save -> load with default options gives back the same coordinates,
// and the files look right in other tools (a glTF viewer shows our maps upright).
//
// Labels: per triangle, normalizeLabel() of the nearest meaningful name among its node (OBJ
// object or group, glTF/DAE node; the root node only for meshes hung on it directly), its
// mesh, its material (OBJ usemtl). Names assimp or exporters make up are skipped:
// "defaultobject", "DefaultMaterial", "$...", "<...>", glTF ids like "nodes[0]", "unlabelled".
#pragma once

#include <polyloc/map/mesh.hpp>

#include <stdexcept>
#include <string>

namespace polyloc {

class MapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The file's up axis; the map frame is always z up. Both conversions are proper rotations,
// so handedness, winding and outward normals are kept:
//   Y: (x, y, z)_map = (x, -z, y)_file   (+90 deg about x; glTF, most DAE/OBJ from Y-up tools)
//   X: (x, y, z)_map = (-z, y, x)_file   (-90 deg about y)
//   Auto: Y for .gltf/.glb, the file's <up_axis> for .dae, Z for everything else.
enum class UpAxis { Auto, Z, Y, X };

struct LoadOptions {
  double scale = 1.0;       // multiply coordinates (e.g. 0.001 for a CAD file in mm)
  UpAxis up_axis = UpAxis::Auto;  // set Y for an OBJ/PLY/STL exported from a y-up tool
  // Join vertices at bit-identical positions across all meshes (after transforms), so that
  // validation sees shared edges. Ignores normals and UVs, unlike aiProcess_JoinIdenticalVertices.
  bool merge_vertices = true;
};

// Throws MapError: missing or empty file, unreadable/corrupt file (guarded against the hangs
// and aborts of assimp 5.2 on corrupt PLY and empty faces), no triangles, non-finite
// coordinates, scale not positive. Triangles under a mirroring node transform are re-wound so
// their normals keep pointing the way they were modelled.
Mesh loadMesh(const std::string& path, const LoadOptions& options = {});
UpAxis parseUpAxis(const std::string& text);  // "auto", "z", "y", "x" (any case); throws MapError

// Writes by extension (.obj + .mtl, binary .ply and .stl, .gltf + .bin, .glb, .dae); one
// object, mesh and material per label ("unlabelled" for ""), so labels survive a round trip
// through OBJ, glTF/GLB and DAE (PLY and STL carry no names). Throws MapError on failure.
void saveMesh(const Mesh& mesh, const std::string& path);
// Throws the MapError saveMesh would for a path whose extension it cannot write: for commands to
// check before their work rather than after it.
void checkMeshPath(const std::string& path);

}  // namespace polyloc
