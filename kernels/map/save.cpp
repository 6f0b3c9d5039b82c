// saveMesh: one aiMesh + aiNode + material per label, so the labels survive a round trip
// through formats that carry names (OBJ, glTF/GLB, DAE).
#include <polyloc/map/load.hpp>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>

namespace polyloc {
namespace {

struct Format {
  const char* extension;
  const char* exporter_id;
};
// Binary STL/PLY: exact floats and a quarter of the size; the text formats write 9 digits.
constexpr Format kFormats[] = {{".obj", "obj"},    {".ply", "plyb"}, {".stl", "stlb"},
                               {".gltf", "gltf2"}, {".glb", "glb2"}, {".dae", "collada"}};

// Map (z up) to y up: (x, y, z) -> (x, z, -y). As the root of a glTF it makes the file y up,
// as its spec wants; the collada exporter instead writes it as <up_axis>Z_UP</up_axis> and no
// root transform, which is also true of our data.
aiMatrix4x4 zUpToYUpRoot() {
  return aiMatrix4x4(1, 0, 0, 0,   //
                     0, 0, 1, 0,   //
                     0, -1, 0, 0,  //
                     0, 0, 0, 1);
}

aiMesh* buildMesh(const Mesh& mesh, const std::vector<size_t>& tris, const std::string& name,
                  unsigned material) {
  // Compact to the vertices this label uses; old index -> new index.
  std::vector<uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
  std::vector<uint32_t> used;
  for (size_t t : tris)
    for (uint32_t v : mesh.triangles[t])
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<uint32_t>(used.size());
        used.push_back(v);
      }
  auto* m = new aiMesh();
  m->mName = aiString(name);
  m->mMaterialIndex = material;
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mNumVertices = static_cast<unsigned>(used.size());
  m->mVertices = new aiVector3D[used.size()];
  for (size_t i = 0; i < used.size(); ++i) {
    const Eigen::Vector3f& p = mesh.vertices[used[i]];
    m->mVertices[i] = aiVector3D(p.x(), p.y(), p.z());
  }
  m->mNumFaces = static_cast<unsigned>(tris.size());
  m->mFaces = new aiFace[tris.size()];
  for (size_t i = 0; i < tris.size(); ++i) {
    aiFace& f = m->mFaces[i];
    f.mNumIndices = 3;
    f.mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) f.mIndices[k] = remap[mesh.triangles[tris[i]][k]];
  }
  return m;
}

const Format& formatOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const Format& f : kFormats)
    if (ext == f.extension) return f;
  throw MapError(fmt::format("cannot save map '{}': unknown extension '{}' (use .obj, .ply, .stl, .gltf, .glb or .dae)",
                             path, ext));
}

}  // namespace

void checkMeshPath(const std::string& path) { formatOf(path); }

void saveMesh(const Mesh& mesh, const std::string& path) {
  const Format* format = &formatOf(path);
  const std::string ext = format->extension;
  if (mesh.triangles.empty())
    throw MapError(fmt::format("cannot save map '{}': mesh is empty", path));
  if (mesh.triangle_label.size() != mesh.triangles.size())
    throw MapError(fmt::format("cannot save map '{}': {} labels for {} triangles", path,
                               mesh.triangle_label.size(), mesh.triangles.size()));

  // Triangles grouped by label, in label order.
  std::vector<std::vector<size_t>> groups(mesh.label_names.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t label = mesh.triangle_label[t];
    if (label >= groups.size())
      throw MapError(fmt::format("cannot save map '{}': triangle {} has label id {} of {}", path, t,
                                 label, groups.size()));
    for (uint32_t v : mesh.triangles[t])
      if (v >= mesh.vertices.size())
        throw MapError(fmt::format("cannot save map '{}': triangle {} uses vertex {} of {}", path,
                                   t, v, mesh.vertices.size()));
    groups[label].push_back(t);
  }
  std::vector<uint32_t> labels;
  for (uint32_t l = 0; l < groups.size(); ++l)
    if (!groups[l].empty()) labels.push_back(l);

  // aiScene owns everything below and frees it with delete/delete[].
  auto scene = std::make_unique<aiScene>();
  // Faces share vertices, but we leave AI_SCENE_FLAGS_NON_VERBOSE_FORMAT unset: with it, the
  // normal generation that the OBJ and STL exporters enforce throws instead of running.
  const unsigned n = static_cast<unsigned>(labels.size());
  scene->mRootNode = new aiNode("polyloc_map");
  if (ext == ".dae" || ext == ".gltf" || ext == ".glb") scene->mRootNode->mTransformation = zUpToYUpRoot();
  scene->mNumMeshes = scene->mNumMaterials = n;
  scene->mMeshes = new aiMesh*[n];
  scene->mMaterials = new aiMaterial*[n];
  scene->mRootNode->mNumChildren = n;
  scene->mRootNode->mChildren = new aiNode*[n];
  for (unsigned i = 0; i < n; ++i) {
    const std::string& label = mesh.label_names[labels[i]];
    const std::string name = label.empty() ? "unlabelled" : label;
    auto* material = new aiMaterial();
    const aiString ai_name(name);
    material->AddProperty(&ai_name, AI_MATKEY_NAME);
    const aiColor3D grey(0.7f, 0.7f, 0.7f);
    material->AddProperty(&grey, 1, AI_MATKEY_COLOR_DIFFUSE);
    scene->mMaterials[i] = material;
    scene->mMeshes[i] = buildMesh(mesh, groups[labels[i]], name, i);
    auto* node = new aiNode(name);
    node->mParent = scene->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
    scene->mRootNode->mChildren[i] = node;
  }

  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), format->exporter_id, path) != aiReturn_SUCCESS)
    throw MapError(fmt::format("cannot save map '{}': {}", path, exporter.GetErrorString()));
}

}  // namespace polyloc
