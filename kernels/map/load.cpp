// loadMesh: any assimp-readable file -> one polyloc::Mesh in the map frame, with labels.
#include <polyloc/map/load.hpp>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/core.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unordered_map>

#include "ply_check.hpp"

namespace polyloc {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A name a person gave (object, group, material), not one assimp or an exporter made up:
// "defaultobject" and "DefaultMaterial" (OBJ), "<STL_BINARY>", "$ColladaAutoName$_3",
// glTF ids like "nodes[0]" for unnamed nodes, and our own "unlabelled".
std::string meaningfulLabel(const aiString& ai_name) {
  const std::string name(ai_name.C_Str());
  if (name.empty() || name[0] == '$' || name[0] == '<') return {};
  const std::string label = normalizeLabel(name);
  if (label.empty() || label == "defaultobject" || label == "defaultmaterial" ||
      label == "unlabelled" || label == "unlabeled")
    return {};
  const size_t bracket = label.find('[');
  if (bracket != std::string::npos && label.back() == ']' &&
      std::all_of(label.begin(), label.begin() + bracket,
                  [](char c) { return std::isalpha(static_cast<unsigned char>(c)); }) &&
      std::all_of(label.begin() + bracket + 1, label.end() - 1,
                  [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
    return {};
  return label;
}

// The map frame is z up. The rotations are proper (det +1), so winding and outward normals
// survive: Y up: (x, y, z)_map = (x, -z, y)_file, +90 deg about x;
//          X up: (x, y, z)_map = (-z, y, x)_file, -90 deg about y.
Eigen::Matrix3d upAxisRotation(UpAxis up) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (up == UpAxis::Y) r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  if (up == UpAxis::X) r << 0, 0, -1, 0, 1, 0, 1, 0, 0;
  return r;
}

Eigen::Affine3d toEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return Eigen::Affine3d(e);
}

// Walks the node graph with accumulated transforms and appends every triangle to `out`.
class SceneWalker {
 public:
  SceneWalker(const aiScene& scene, const std::string& path, Mesh& out)
      : scene_(scene), path_(path), out_(out) {}

  void walk(const aiNode* node, const Eigen::Affine3d& parent, const std::string& inherited,
            int depth) {
    if (!node) return;
    if (depth > 256) fail("node graph is deeper than 256 levels (a cycle?)");
    const Eigen::Affine3d world = parent * toEigen(node->mTransformation);
    // The root's name is the file or scene name (OBJ, DAE, glTF "ROOT"); it labels only meshes
    // hung on the root itself, e.g. a glTF whose single node became the root.
    std::string own = meaningfulLabel(node->mName);
    if (own.empty()) own = inherited;
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      if (!node->mMeshes || node->mMeshes[i] >= scene_.mNumMeshes ||
          !scene_.mMeshes[node->mMeshes[i]])
        fail(fmt::format("node '{}' refers to a missing mesh", node->mName.C_Str()));
      addMesh(*scene_.mMeshes[node->mMeshes[i]], world, own);
    }
    const std::string& for_children = depth == 0 ? inherited : own;
    for (unsigned i = 0; i < node->mNumChildren; ++i)
      if (node->mChildren) walk(node->mChildren[i], world, for_children, depth + 1);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw MapError(fmt::format("map file '{}': {}", path_, problem));
  }

  std::string labelOf(const aiMesh& mesh, const std::string& node_label) const {
    if (!node_label.empty()) return node_label;
    std::string label = meaningfulLabel(mesh.mName);
    if (!label.empty()) return label;
    if (mesh.mMaterialIndex < scene_.mNumMaterials && scene_.mMaterials[mesh.mMaterialIndex]) {
      aiString name;
      if (scene_.mMaterials[mesh.mMaterialIndex]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS)
        label = meaningfulLabel(name);
    }
    return label;
  }

  void addMesh(const aiMesh& mesh, const Eigen::Affine3d& transform,
               const std::string& node_label) {
    if (mesh.mNumFaces == 0 || !mesh.mFaces || !mesh.mVertices) return;
    const uint32_t label = out_.labelId(labelOf(mesh, node_label));
    // A mirroring transform turns the triangles inside out; swapping two corners keeps the
    // normals pointing the way the modeller made them.
    const bool mirrored = transform.linear().determinant() < 0.0;
    const uint32_t base = static_cast<uint32_t>(out_.vertices.size());
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& v = mesh.mVertices[i];
      const Eigen::Vector3d p = transform * Eigen::Vector3d(v.x, v.y, v.z);
      const Eigen::Vector3f pf = p.cast<float>();
      if (!pf.allFinite())
        fail(fmt::format("vertex {} of mesh '{}' has a non-finite coordinate ({}, {}, {})", i,
                         mesh.mName.C_Str(), v.x, v.y, v.z));
      out_.vertices.push_back(pf);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3 || !face.mIndices) continue;  // points and lines
      Triangle t;
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh.mNumVertices)
          fail(fmt::format("face {} of mesh '{}' uses vertex {} of {}", f, mesh.mName.C_Str(),
                           face.mIndices[k], mesh.mNumVertices));
        t[k] = base + face.mIndices[k];
      }
      if (mirrored) std::swap(t[1], t[2]);
      out_.triangles.push_back(t);
      out_.triangle_label.push_back(label);
    }
  }

  const aiScene& scene_;
  const std::string& path_;
  Mesh& out_;
};

// Drops vertices no triangle uses and, if `weld`, joins vertices at bit-identical positions
// across all meshes (assimp's JoinIdenticalVertices works per mesh and also compares normals,
// so it leaves the corners of an STL cube or of two labelled parts apart).
void compactVertices(Mesh& mesh, bool weld) {
  struct Key {
    uint32_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return (static_cast<size_t>(k.x) * 73856093u) ^ (static_cast<size_t>(k.y) * 19349663u) ^
             (static_cast<size_t>(k.z) * 83492791u);
    }
  };
  auto bits = [](float f) {
    if (f == 0.f) f = 0.f;  // -0 and +0 are one position
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
  };
  std::vector<uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
  std::vector<Eigen::Vector3f> kept;
  kept.reserve(mesh.vertices.size());
  std::unordered_map<Key, uint32_t, KeyHash> index;
  if (weld) index.reserve(mesh.vertices.size());
  for (Triangle& t : mesh.triangles)
    for (uint32_t& v : t) {
      if (remap[v] == UINT32_MAX) {
        const Eigen::Vector3f& p = mesh.vertices[v];
        uint32_t id = static_cast<uint32_t>(kept.size());
        if (weld)
          id = index.try_emplace(Key{bits(p.x()), bits(p.y()), bits(p.z())}, id).first->second;
        if (id == kept.size()) kept.push_back(p);
        remap[v] = id;
      }
      v = remap[v];
    }
  mesh.vertices = std::move(kept);
}

// Faces that corrupt files give assimp's importers: no corners, or corners past the vertex array.
void checkFaces(const aiScene& scene, const std::string& path) {
  if (scene.mNumMeshes > 0 && !scene.mMeshes)
    throw MapError(fmt::format("cannot read map file '{}': mesh list missing", path));
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (!mesh || mesh->mNumFaces == 0) continue;
    if (!mesh->mFaces || !mesh->mVertices)
      throw MapError(
          fmt::format("cannot read map file '{}': mesh {} has faces but no vertices", path, m));
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices == 0 || !face.mIndices)
        throw MapError(fmt::format("cannot read map file '{}': face {} of mesh {} has no corners",
                                   path, f, m));
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= mesh->mNumVertices)
          throw MapError(
              fmt::format("cannot read map file '{}': face {} of mesh {} uses vertex {} of {}",
                          path, f, m, face.mIndices[k], mesh->mNumVertices));
    }
  }
}

}  // namespace

UpAxis parseUpAxis(const std::string& text) {
  const std::string t = lower(text);
  if (t == "auto") return UpAxis::Auto;
  if (t == "z") return UpAxis::Z;
  if (t == "y") return UpAxis::Y;
  if (t == "x") return UpAxis::X;
  throw MapError(fmt::format("unknown up axis '{}' (use auto, z, y or x)", text));
}

Mesh loadMesh(const std::string& path, const LoadOptions& options) {
  if (!std::isfinite(options.scale) || options.scale <= 0.0)
    throw MapError(
        fmt::format("map file '{}': scale must be positive, got {}", path, options.scale));
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw MapError(fmt::format("map file '{}' does not exist", path));
  if (!fs::is_regular_file(status))
    throw MapError(fmt::format("map file '{}' is not a regular file", path));
  if (fs::file_size(path, ec) == 0)
    throw MapError(fmt::format("map file '{}' is empty (0 bytes)", path));
  detail::checkPlyStructure(path);  // assimp's PLY reader hangs or crashes on corrupt files

  Assimp::Importer importer;
  // Auto: glTF is y up by its spec; for DAE the collada importer turns whatever <up_axis> the
  // file declares into y up. An explicit axis means coordinates as written, for every format.
  std::string ext = lower(fs::path(path).extension().string());
  UpAxis up = options.up_axis;
  if (up == UpAxis::Auto) up = ext == ".gltf" || ext == ".glb" || ext == ".dae" ? UpAxis::Y : UpAxis::Z;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION,
                           options.up_axis != UpAxis::Auto);
  // No normal generation, no winding flips, no pre-transform (we walk the nodes ourselves),
  // no aiProcess_ValidateDataStructure (the walker checks what it uses, and validation rejects
  // harmless files, e.g. an OBJ face with two corners).
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene)
    throw MapError(fmt::format("cannot read map file '{}': {}", path, importer.GetErrorString()));
  checkFaces(*scene, path);  // triangulation asserts (aborts) or reads out of bounds otherwise
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (!scene)
    throw MapError(fmt::format("cannot read map file '{}': {}", path, importer.GetErrorString()));

  Mesh mesh;
  mesh.source = path;
  Eigen::Affine3d to_map = Eigen::Affine3d::Identity();
  to_map.linear() = options.scale * upAxisRotation(up);
  try {
    SceneWalker(*scene, path, mesh).walk(scene->mRootNode, to_map, "", 0);
  } catch (const std::bad_alloc&) {
    throw MapError(fmt::format("map file '{}': out of memory", path));
  }
  if (mesh.triangles.empty())
    throw MapError(fmt::format("map file '{}' holds no triangles (empty map)", path));
  compactVertices(mesh, options.merge_vertices);
  return mesh;
}

}  // namespace polyloc
