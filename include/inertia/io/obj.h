// Wavefront OBJ import (through tinyobjloader): the triangle mesh of a file, for mesh shapes and
// the scene file's {"type": "mesh", "obj": "..."}.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "inertia/geometry/mesh.h"

namespace inertia::io {

/// A problem with an OBJ file. what() reads "FILE:LINE: REASON" when the parser names a line,
/// else "FILE: REASON".
class ObjError : public std::runtime_error {
 public:
  ObjError(std::string file, int line, std::string reason);
  const std::string& file() const { return file_; }
  /// 1-based line of the problem, or 0 when not known.
  int line() const { return line_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_;
  int line_ = 0;
  std::string reason_;
};

/// Loads the OBJ file at `path` as one triangle mesh (m, the file's units taken as metres):
/// every shape (o / g groups) merged, polygons triangulated as fans, vertices not referenced by
/// any face dropped (the others keep their order), normals, texture coordinates, materials,
/// lines and points ignored. Faces keep the file's winding (counter-clockwise seen from
/// outside for TriangleMesh's normals). Throws ObjError for a missing or unreadable file, a
/// parse error, a face index out of range, no faces, or a mesh TriangleMesh rejects (repeated
/// vertex in a face, zero-area face, non-finite coordinate).
TriangleMesh loadObj(const std::filesystem::path& path);

}  // namespace inertia::io
