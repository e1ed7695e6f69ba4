// Triangle mesh validation, normals and edge adjacency.
#include "inertia/geometry/mesh.h"

#include <algorithm>
#include <string>
#include <unordered_map>

#include "inertia/core/error.h"
#include "inertia/core/math.h"

namespace inertia {

TriangleMesh::TriangleMesh(std::vector<Vec3> vertices, std::vector<Triangle> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  require(!triangles_.empty(), "TriangleMesh: no triangles");
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    require(allFinite(vertices_[i]),
            "TriangleMesh: vertex " + std::to_string(i) + " is not finite");
    bounds_.extend(vertices_[i]);
  }

  normals_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    const std::string where = "TriangleMesh: triangle " + std::to_string(t);
    for (std::uint32_t v : tri)
      require(v < vertices_.size(), where + " has vertex index " + std::to_string(v) +
                                        " out of range (" + std::to_string(vertices_.size()) +
                                        " vertices)");
    require(tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0],
            where + " repeats a vertex index");
    // In double so that a thin but valid float triangle still gets a finite unit normal.
    const Eigen::Vector3d a = vertices_[tri[0]].cast<double>();
    const Eigen::Vector3d n =
        (vertices_[tri[1]].cast<double>() - a).cross(vertices_[tri[2]].cast<double>() - a);
    require(n.norm() > 0, where + " is degenerate (zero area)");
    normals_[t] = n.normalized().cast<Real>();
  }

  // Every undirected edge -> the (triangle, edge slot) pairs using it.
  struct Use {
    std::uint32_t tri;
    std::uint8_t slot;
  };
  std::unordered_map<std::uint64_t, std::vector<Use>> uses;
  uses.reserve(3 * triangles_.size());
  auto key = [](std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (std::uint32_t t = 0; t < triangles_.size(); ++t)
    for (std::uint8_t k = 0; k < 3; ++k)
      uses[key(triangles_[t][k], triangles_[t][(k + 1) % 3])].push_back({t, k});

  neighbours_.assign(triangles_.size(), {kNone, kNone, kNone});
  edgeKinds_.assign(triangles_.size(),
                    {EdgeKind::Boundary, EdgeKind::Boundary, EdgeKind::Boundary});
  closed_ = true;
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    for (std::uint8_t k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles_[t][k], b = triangles_[t][(k + 1) % 3];
      const std::vector<Use>& list = uses[key(a, b)];
      if (list.size() != 2) {
        closed_ = false;
        edgeKinds_[t][k] = list.size() == 1 ? EdgeKind::Boundary : EdgeKind::NonManifold;
        continue;
      }
      const Use other = list[0].tri == t && list[0].slot == k ? list[1] : list[0];
      const Triangle& o = triangles_[other.tri];
      // A consistently oriented neighbour runs the shared edge the other way, b -> a.
      if (o[other.slot] != b) closed_ = false;
      neighbours_[t][k] = other.tri;
      // The neighbour's apex (its vertex off the shared edge) below this triangle's plane means
      // the surface turns away from the normal: a convex edge.
      const std::uint32_t apex = o[(other.slot + 2) % 3];
      const Eigen::Vector3d toApex = vertices_[apex].cast<double>() - vertices_[a].cast<double>();
      const double sine = normals_[t].cast<double>().dot(toApex) / toApex.norm();
      edgeKinds_[t][k] = sine < -kFlatSine  ? EdgeKind::Convex
                         : sine > kFlatSine ? EdgeKind::Concave
                                            : EdgeKind::Flat;
    }
  }
}

}  // namespace inertia
