// Reading shapes from scene files (DESIGN.md section 4's shape table), shared by rigid bodies,
// particle obstacles and every later section that places a shape.
#pragma once

#include <initializer_list>
#include <string_view>

#include <vector>

#include "inertia/geometry/mesh.h"
#include "inertia/geometry/shapes.h"
#include "json_reader.h"

namespace inertia::io::detail {

/// The keys every shape object may hold beside its own: "type", "position", "orientation" plus
/// `extra` (e.g. "material", "color" for bodies).
/// Reads a shape object; the pose (position, orientation) goes to `pose`. Fails with the
/// shape's pointer on an unknown type, unknown keys or an invalid shape. Relative paths
/// ("obj") resolve against the directory of the file `n` was read from.
Shape readShape(const Node& n, Transform& pose, std::initializer_list<std::string_view> extra = {});

/// An array of points [[x, y, z], ...] (m).
std::vector<Vec3> readPoints(const Node& n);
/// An array of triangles [[i, j, k], ...], indices below vertexCount.
std::vector<Triangle> readTriangles(const Node& n, std::size_t vertexCount);

/// A pose from optional "position" and "orientation" keys of `n`.
Transform readPose(const Node& n);

}  // namespace inertia::io::detail
