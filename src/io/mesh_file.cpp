#include "mesh_file.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <string>

#include "inertia/io/obj.h"

namespace inertia::io::detail {

namespace {

bool isObj(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".obj";
}

// Every mesh under `node`, its vertices moved by the node's transform to the file's root.
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
             std::vector<Vec3>& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.emplace_back(Real(p.x), Real(p.y), Real(p.z));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    collect(scene, *node.mChildren[c], transform, out);
}

std::vector<Vec3> loadWithAssimp(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error(file + ": no such file");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(file, aiProcess_JoinIdenticalVertices);
  if (!scene || !scene->mRootNode)
    throw std::runtime_error(file + ": " + importer.GetErrorString());
  std::vector<Vec3> vertices;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), vertices);
  if (vertices.empty()) throw std::runtime_error(file + ": no vertices");
  return vertices;
}

}  // namespace

std::vector<Vec3> loadMeshVertices(const std::filesystem::path& path) {
  if (!isObj(path)) return loadWithAssimp(path);
  try {
    return loadObj(path).vertices();
  } catch (const ObjError& e) {
    throw std::runtime_error(e.what());
  }
}

}  // namespace inertia::io::detail
