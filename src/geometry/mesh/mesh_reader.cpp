#include "src/geometry/mesh/mesh_reader.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cstring>
#include <filesystem>
#include <unordered_map>

namespace ckpd {

void TriangleMesh::bounds(Vec3& lo, Vec3& hi) const {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Vec3& v : vertex) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

namespace {

// Exact float positions as a key: the same float triple from two facets is one vertex.
struct PositionKey {
  std::uint32_t bits[3];
  bool operator==(const PositionKey& o) const {
    return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
  }
};
struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    return (std::size_t{k.bits[0]} * 73856093u) ^ (std::size_t{k.bits[1]} * 19349663u) ^
           (std::size_t{k.bits[2]} * 83492791u);
  }
};

PositionKey key_of(const aiVector3D& v) {
  PositionKey k;
  const float c[3] = {v.x == 0 ? 0.0f : v.x, v.y == 0 ? 0.0f : v.y,
                      v.z == 0 ? 0.0f : v.z};  // -0 and +0 are one position
  for (int d = 0; d < 3; ++d) std::memcpy(&k.bits[d], &c[d], sizeof(float));
  return k;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw MeshError("a mesh file (" + path + " does not exist or is not a file)");
  Assimp::Importer importer;
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension.empty() || !importer.IsExtensionSupported(extension))
    throw MeshError("a mesh format that assimp reads (the file name ends in '" + extension +
                    "'; known: .stl .obj .ply .off .gltf .glb .fbx .dae .3ds and more)");
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_PreTransformVertices);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw MeshError(
        "a mesh file assimp can parse (assimp: " + std::string(importer.GetErrorString()) + ")");
  TriangleMesh mesh;
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> index;
  std::size_t others = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    std::vector<std::uint32_t> welded(am->mNumVertices);
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      const auto [it, fresh] =
          index.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh.vertex.size()));
      if (fresh) mesh.vertex.emplace_back(p.x, p.y, p.z);
      welded[v] = it->second;
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) {
        ++others;  // points and lines
        continue;
      }
      mesh.triangle.push_back(
          {welded[face.mIndices[0]], welded[face.mIndices[1]], welded[face.mIndices[2]]});
    }
  }
  if (mesh.triangle.empty())
    throw MeshError("a mesh with triangles (the file holds " + std::to_string(mesh.vertex.size()) +
                    " vertices and " + std::to_string(others) + " points or lines but no faces)");
  return mesh;
}

}  // namespace ckpd
