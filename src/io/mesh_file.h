// Vertices of a mesh file, for shapes built from them (URDF's collision meshes): Wavefront OBJ
// through io/obj.h, every other format Assimp reads (STL, COLLADA, PLY, ...) through Assimp.
// Private to the io layer.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "inertia/core/types.h"

namespace inertia::io::detail {

/// The vertices of every mesh in the file (m, the file's units taken as metres), each moved by
/// the transforms of the file's node hierarchy. Throws std::runtime_error whose what() names
/// the file and the problem (missing file, parse error, no vertices).
std::vector<Vec3> loadMeshVertices(const std::filesystem::path& path);

}  // namespace inertia::io::detail
