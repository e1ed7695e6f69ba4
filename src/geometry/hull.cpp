// Convex hull construction: Qhull (reentrant C API) builds the merged facets, then the facets
// are turned into a half-edge structure with outward, counter-clockwise loops.
#include "inertia/geometry/hull.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <unordered_map>

#include "inertia/core/error.h"
#include "inertia/core/math.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace inertia {
namespace {

using Vec3d = Eigen::Vector3d;

// Qhull's state and its error stream, released on every exit path.
struct QhullSession {
  qhT qh;
  char* errText = nullptr;
  std::size_t errSize = 0;
  FILE* errFile = nullptr;

  QhullSession() {
    errFile = open_memstream(&errText, &errSize);
    qh_zero(&qh, errFile);
  }
  ~QhullSession() {
    qh_freeqhull(&qh, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(&qh, &curlong, &totlong);
    if (errFile) std::fclose(errFile);
    std::free(errText);
  }
  QhullSession(const QhullSession&) = delete;
  QhullSession& operator=(const QhullSession&) = delete;

  std::string errors() {
    if (errFile) std::fflush(errFile);
    return errText ? std::string(errText, errSize) : std::string();
  }
};

// Rejects clouds that span no volume. A greedy extreme-point simplex (the same start as
// Quickhull's): p0, p1 farthest from p0, p2 farthest from the line, p3 farthest from the plane.
// Its height bounds the cloud's thickness from below, so a thin-but-solid cloud passes.
void requireVolume(const std::vector<Vec3d>& p) {
  Eigen::AlignedBox3d box;
  for (const Vec3d& x : p) box.extend(x);
  const double extent = box.diagonal().norm();
  require(extent > 0, "ConvexHull: all points coincide (no volume)");
  const double minThickness = ConvexHull::kMinThickness * extent;

  auto farthest = [&](auto&& dist) {
    std::size_t best = 0;
    double bestDist = -1;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double d = dist(p[i]);
      if (d > bestDist) bestDist = d, best = i;
    }
    return std::pair{best, bestDist};
  };
  const Vec3d a = box.min();
  const Vec3d p0 = p[farthest([&](const Vec3d& x) { return (x - a).norm(); }).first];
  const auto [i1, d1] = farthest([&](const Vec3d& x) { return (x - p0).norm(); });
  require(d1 > minThickness, "ConvexHull: all points coincide (no volume)");
  const Vec3d u = (p[i1] - p0).normalized();
  const auto [i2, d2] = farthest([&](const Vec3d& x) { return (x - p0).cross(u).norm(); });
  require(d2 > minThickness, "ConvexHull: the points are collinear (no volume)");
  const Vec3d n = u.cross(p[i2] - p0).normalized();
  const auto [i3, d3] = farthest([&](const Vec3d& x) { return std::abs((x - p0).dot(n)); });
  require(d3 > minThickness, "ConvexHull: the points are coplanar (no volume)");
}

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

}  // namespace

ConvexHull::ConvexHull(std::span<const Vec3> points) {
  require(points.size() >= 4,
          "ConvexHull: needs at least 4 points, got " + std::to_string(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    require(allFinite(points[i]), "ConvexHull: point " + std::to_string(i) + " is not finite");

  // Qhull works in double; centring the cloud keeps its round-off relative to the cloud's size.
  Eigen::AlignedBox3d box;
  for (const Vec3& x : points) box.extend(x.cast<double>());
  const Vec3d centre = box.center();
  std::vector<Vec3d> local(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) local[i] = points[i].cast<double>() - centre;
  requireVolume(local);

  std::vector<coordT> coords(3 * local.size());
  for (std::size_t i = 0; i < local.size(); ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = local[i][k];

  // Pre-merge facets whose centrums lie within `tol` of a neighbour's plane ('C-n'), so faces
  // that are coplanar up to the input's rounding (Real may be float) become one face. The
  // tolerance is a few ulps of Real at the cloud's scale; Qhull raises it to its own round-off
  // estimate when that is larger.
  const double scale = box.diagonal().norm();
  const double tol = 16.0 * double(std::numeric_limits<Real>::epsilon()) * scale;
  char options[64];
  std::snprintf(options, sizeof options, "qhull C-%.3g", tol);

  QhullSession session;
  qhT* qh = &session.qh;
  const int exitCode = qh_new_qhull(qh, 3, int(local.size()), coords.data(), False, options,
                                    nullptr, session.errFile);
  require(exitCode == 0, "ConvexHull: Qhull failed: " + session.errors());

  // Vertices: only those on the hull, renumbered densely.
  constexpr std::uint32_t kNoIndex = 0xffffffffu;
  std::vector<std::uint32_t> vertexOf(local.size(), kNoIndex);
  std::vector<std::size_t> sourceOf;  // hull vertex -> input point
  for (vertexT* v = qh->vertex_list; v && v->next; v = v->next) {
    const int id = qh_pointid(qh, v->point);
    vertexOf[std::size_t(id)] = std::uint32_t(vertices_.size());
    sourceOf.push_back(std::size_t(id));
    vertices_.push_back((local[std::size_t(id)] + centre).cast<Real>());
  }

  // Faces and their loops. qh_facet3vertex orders a 3-d facet's vertices along its ridges; the
  // loop is flipped where needed so that it turns counter-clockwise about the outward normal.
  for (facetT* f = qh->facet_list; f && f->next; f = f->next) {
    setT* loopSet = qh_facet3vertex(qh, f);
    std::vector<std::uint32_t> loop;
    for (int i = 0; i < qh_setsize(qh, loopSet); ++i) {
      const auto* v = static_cast<vertexT*>(SETelem_(loopSet, i));
      const std::uint32_t index = vertexOf[std::size_t(qh_pointid(qh, v->point))];
      require(index != kNoIndex, "ConvexHull: Qhull returned a facet with an unknown vertex");
      loop.push_back(index);
    }
    qh_settempfree(qh, &loopSet);
    require(loop.size() >= 3, "ConvexHull: Qhull returned a degenerate facet");

    const Vec3d n(f->normal[0], f->normal[1], f->normal[2]);
    // Newell's polygon normal gives the loop's winding.
    Vec3d newell = Vec3d::Zero();
    for (std::size_t i = 0; i < loop.size(); ++i) {
      newell += local[sourceOf[loop[i]]].cross(local[sourceOf[loop[(i + 1) % loop.size()]]]);
    }
    if (newell.dot(n) < 0) std::reverse(loop.begin(), loop.end());

    HullFace face;
    face.normal = n.cast<Real>();
    // Qhull's plane is n.x + offset = 0 in centred coordinates: n.(x - c) <= -offset.
    face.offset = Real(-f->offset + n.dot(centre));
    face.firstEdge = std::uint32_t(halfEdges_.size());
    face.edgeCount = std::uint32_t(loop.size());
    const auto faceIndex = std::uint32_t(faces_.size());
    for (std::size_t i = 0; i < loop.size(); ++i) {
      HullHalfEdge h;
      h.origin = loop[i];
      h.next = face.firstEdge + std::uint32_t((i + 1) % loop.size());
      h.face = faceIndex;
      halfEdges_.push_back(h);
    }
    faces_.push_back(face);
  }

  // Twins: the half-edge a->b pairs with b->a on the neighbouring face.
  std::unordered_map<std::uint64_t, std::uint32_t> byEnds;
  byEnds.reserve(halfEdges_.size());
  for (std::uint32_t h = 0; h < halfEdges_.size(); ++h) {
    const std::uint32_t a = halfEdges_[h].origin, b = halfEdges_[halfEdges_[h].next].origin;
    require(byEnds.emplace(edgeKey(a, b), h).second,
            "ConvexHull: Qhull returned a non-manifold hull");
  }
  for (std::uint32_t h = 0; h < halfEdges_.size(); ++h) {
    const std::uint32_t a = halfEdges_[h].origin, b = halfEdges_[halfEdges_[h].next].origin;
    const auto it = byEnds.find(edgeKey(b, a));
    require(it != byEnds.end(), "ConvexHull: Qhull returned a hull with an unpaired edge");
    halfEdges_[h].twin = it->second;
  }

  // Undirected edges, once each, and each vertex's incident edges (compressed rows).
  std::vector<std::uint32_t> degree(vertices_.size(), 0);
  for (std::uint32_t h = 0; h < halfEdges_.size(); ++h) {
    const std::uint32_t t = halfEdges_[h].twin;
    if (h > t) continue;
    HullEdge e;
    e.v0 = halfEdges_[h].origin;
    e.v1 = halfEdges_[t].origin;
    e.face0 = halfEdges_[h].face;
    e.face1 = halfEdges_[t].face;
    e.halfEdge = h;
    halfEdges_[h].edge = halfEdges_[t].edge = std::uint32_t(edges_.size());
    ++degree[e.v0];
    ++degree[e.v1];
    edges_.push_back(e);
  }
  vertexEdgeStart_.assign(vertices_.size() + 1, 0);
  for (std::size_t v = 0; v < vertices_.size(); ++v)
    vertexEdgeStart_[v + 1] = vertexEdgeStart_[v] + degree[v];
  vertexEdgeIndices_.resize(vertexEdgeStart_.back());
  std::vector<std::uint32_t> fill(vertexEdgeStart_.begin(), vertexEdgeStart_.end() - 1);
  for (std::uint32_t e = 0; e < edges_.size(); ++e) {
    vertexEdgeIndices_[fill[edges_[e].v0]++] = e;
    vertexEdgeIndices_[fill[edges_[e].v1]++] = e;
  }

  Vec3d mean = Vec3d::Zero();
  for (const Vec3& v : vertices_) {
    mean += v.cast<double>();
    bounds_.extend(v);
  }
  interiorPoint_ = (mean / double(vertices_.size())).cast<Real>();
}

}  // namespace inertia
