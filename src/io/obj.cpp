// OBJ import through tinyobjloader's v2 API (ObjReader), merged into one TriangleMesh.
#include "inertia/io/obj.h"

#include <tiny_obj_loader.h>

#include <cctype>
#include <cstdint>
#include <utility>
#include <vector>

#include "inertia/core/error.h"

namespace inertia::io {

namespace {

std::string describe(const std::string& file, int line, const std::string& reason) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + reason : file + ": " + reason;
}

// tinyobjloader ends its messages with newlines and puts the line number inside the text
// ("... line 5.)", "line: 5"); pull it out for ObjError::line.
std::pair<int, std::string> splitMessage(std::string message) {
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  int line = 0;
  for (std::size_t at = message.find("line"); at != std::string::npos && line == 0;
       at = message.find("line", at + 4)) {
    std::size_t i = at + 4;
    while (i < message.size() && (message[i] == ':' || message[i] == ' ')) ++i;
    while (i < message.size() && std::isdigit(static_cast<unsigned char>(message[i])) &&
           line < 100000000)
      line = 10 * line + (message[i++] - '0');
  }
  return {line, message.empty() ? std::string("unknown parse error") : message};
}

}  // namespace

ObjError::ObjError(std::string file, int line, std::string reason)
    : std::runtime_error(describe(file, line, reason)),
      file_(std::move(file)),
      line_(line),
      reason_(std::move(reason)) {}

TriangleMesh loadObj(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw ObjError(file, 0, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw ObjError(file, 0, "is a directory");

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = path.parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(file, config)) {
    auto [line, reason] = splitMessage(reader.Error());
    throw ObjError(file, line, "tinyobjloader: " + reason);
  }

  // Merge the shapes; keep only referenced vertices, in file order.
  const std::vector<tinyobj::real_t>& v = reader.GetAttrib().vertices;
  const std::size_t vertexCount = v.size() / 3;
  std::vector<std::uint32_t> remap(vertexCount, TriangleMesh::kNone);
  std::vector<Triangle> triangles;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    std::size_t offset = 0;
    for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const std::size_t n = mesh.num_face_vertices[f];
      if (n != 3) {
        throw ObjError(file, 0,
                       "face " + std::to_string(f) + " of shape \"" + shape.name + "\" has " +
                           std::to_string(n) + " vertices after triangulation");
      }
      Triangle t;
      for (std::size_t k = 0; k < 3; ++k) {
        const int index = mesh.indices[offset + k].vertex_index;
        if (index < 0 || static_cast<std::size_t>(index) >= vertexCount) {
          throw ObjError(file, 0,
                         "face " + std::to_string(f) + " of shape \"" + shape.name +
                             "\" uses vertex " + std::to_string(index + 1) + ", but the file has " +
                             std::to_string(vertexCount) + " vertices");
        }
        t[k] = static_cast<std::uint32_t>(index);
        remap[index] = 0;  // referenced
      }
      triangles.push_back(t);
      offset += n;
    }
  }
  if (triangles.empty()) throw ObjError(file, 0, "no faces");

  std::vector<Vec3> vertices;
  for (std::size_t i = 0; i < vertexCount; ++i) {
    if (remap[i] == TriangleMesh::kNone) continue;
    remap[i] = static_cast<std::uint32_t>(vertices.size());
    vertices.emplace_back(Real(v[3 * i]), Real(v[3 * i + 1]), Real(v[3 * i + 2]));
  }
  for (Triangle& t : triangles)
    for (std::uint32_t& index : t) index = remap[index];
  try {
    return TriangleMesh(std::move(vertices), std::move(triangles));
  } catch (const InvalidArgument& e) {
    throw ObjError(file, 0, std::string("invalid mesh: ") + e.what());
  }
}

}  // namespace inertia::io
