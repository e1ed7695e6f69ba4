// Manifolds against triangle meshes and height fields: the triangles near the convex shape (BVH
// or grid cells), detail::collideTriangle on each, then the internal-edge correction and the
// merging of manifolds that share a normal. Mesh against mesh: a simultaneous BVH traversal.
//
// Internal edges ("ghost collisions"): a triangle sees only itself, so a shape sliding over a
// flat mesh meets the edges and vertices between triangles and gets normals that lean over them
// (bumps). A contact's normal is legitimate only inside the normal cone of the mesh feature it
// touches. As in Jolt's active edges and Bullet's btAdjustInternalEdgeContacts: when a
// triangle's normal is not its face normal and none of the edges its points touch is active (a
// boundary or non-manifold edge, or an edge that is convex seen from the contact's side), the
// normal is replaced by the face normal and the contact rebuilt along it (the convex shape's
// supporting feature clipped to the triangle's prism); nothing left in the prism means a
// neighbour carries the contact, and the manifold is dropped.
#include "mesh_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "contact_pairs.h"
#include "inertia/collision/mesh_bvh.h"
#include "inertia/collision/triangle.h"
#include "inertia/geometry/bounds.h"
#include "local_queries.h"
#include "polyhedron.h"

namespace inertia::detail {

namespace {

constexpr Real kEps = std::numeric_limits<Real>::epsilon();
/// Unit normals whose dot product is at least this are equal up to rounding (0.3 degrees in
/// float, 1e-6 degrees in double): a face contact, or two manifolds that may merge.
constexpr Real kSameNormalCos = 1 - 100 * kEps;
/// A contact point lies on a triangle's edge within this fraction of its longest edge.
constexpr Real kOnEdgeRel = Real(1e-4);

/// A triangle as the contact code sees it, in the mesh's (field's) local frame.
struct TriangleInfo {
  Vec3 v[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  Vec3 normal = Vec3::UnitY();
  std::array<EdgeKind, 3> kinds{EdgeKind::Boundary, EdgeKind::Boundary, EdgeKind::Boundary};
  /// Mesh-wide keys of the corners and edges, so that the points two triangles report for the
  /// same vertex or edge get the same id (and merge).
  std::array<std::uint32_t, 3> vertexIds{};
  std::array<std::uint32_t, 3> edgeIds{};
};

EdgeKind classifyEdge(const Vec3& normal, const Vec3& edgeStart, const Vec3& apex) {
  // As TriangleMesh: the neighbour's apex below this triangle's plane is a convex edge.
  const Eigen::Vector3d toApex = apex.cast<double>() - edgeStart.cast<double>();
  const double sine = normal.cast<double>().dot(toApex) / toApex.norm();
  return sine < -TriangleMesh::kFlatSine  ? EdgeKind::Convex
         : sine > TriangleMesh::kFlatSine ? EdgeKind::Concave
                                          : EdgeKind::Flat;
}

// ---- Triangle sources --------------------------------------------------------------------

class MeshSource {
 public:
  MeshSource(const TriangleMesh& mesh, const MeshBvh& bvh) : mesh_(mesh), bvh_(bvh) {}

  template <class F>
  void forEachCandidate(const Aabb& box, F&& f) const {
    bvh_.forEachOverlap(box, f);
  }

  void get(std::uint32_t t, TriangleInfo& info) const {
    const Triangle& tri = mesh_.triangles()[t];
    const auto& nb = mesh_.neighbours()[t];
    for (int k = 0; k < 3; ++k) {
      const std::size_t ks = std::size_t(k);
      info.v[k] = mesh_.vertices()[tri[ks]];
      info.vertexIds[ks] = tri[ks];
      info.kinds[ks] = mesh_.edgeKinds()[t][ks];
      // The edge's key is 3 * triangle + slot of the lower-indexed of its two triangles.
      std::uint32_t key = 3 * t + std::uint32_t(k);
      const std::uint32_t n = nb[ks];
      if (n != TriangleMesh::kNone && n < t)
        for (std::uint32_t s = 0; s < 3; ++s)
          if (mesh_.neighbours()[n][s] == t) key = 3 * n + s;
      info.edgeIds[ks] = key;
    }
    info.normal = mesh_.normals()[t];
  }

 private:
  const TriangleMesh& mesh_;
  const MeshBvh& bvh_;
};

// Height-field triangle t = 2 * (row * (cols - 1) + col) + half; half 0 is (a, c, b) and half 1
// (a, d, c) with a = (i, j), b = (i, j + 1), c = (i + 1, j + 1), d = (i + 1, j). Across each
// edge (grid topology): half 0: edge 0 (a-c) -> half 1 of the cell, slot 2; edge 1 (c-b) ->
// cell (i, j + 1) half 1, slot 0; edge 2 (b-a) -> cell (i - 1, j) half 1, slot 1. Half 1:
// edge 0 (a-d) -> cell (i, j - 1) half 0, slot 1; edge 1 (d-c) -> cell (i + 1, j) half 0,
// slot 2; edge 2 (c-a) -> half 0 of the cell, slot 0.
class FieldSource {
 public:
  explicit FieldSource(const HeightField& field) : f_(field) {}

  template <class F>
  void forEachCandidate(const Aabb& box, F&& f) const {
    const Real s = f_.spacing();
    const std::size_t cellsX = f_.cols() - 1, cellsZ = f_.rows() - 1;
    if (box.upper.x() < 0 || box.upper.z() < 0 || box.lower.x() > Real(cellsX) * s ||
        box.lower.z() > Real(cellsZ) * s || box.upper.y() < f_.minHeight() ||
        box.lower.y() > f_.maxHeight())
      return;
    const auto cellRange = [s](Real lo, Real hi, std::size_t cells, std::size_t* a,
                               std::size_t* b) {
      const Real fa = std::floor(lo / s), fb = std::floor(hi / s), last = Real(cells - 1);
      *a = fa <= 0 ? 0 : fa >= last ? cells - 1 : std::size_t(fa);
      *b = fb <= 0 ? 0 : fb >= last ? cells - 1 : std::size_t(fb);
    };
    std::size_t i0, i1, j0, j1;
    cellRange(box.lower.x(), box.upper.x(), cellsX, &j0, &j1);
    cellRange(box.lower.z(), box.upper.z(), cellsZ, &i0, &i1);
    for (std::size_t i = i0; i <= i1; ++i)
      for (std::size_t j = j0; j <= j1; ++j) {
        const Real lo = std::min({f_.height(i, j), f_.height(i, j + 1), f_.height(i + 1, j),
                                  f_.height(i + 1, j + 1)});
        const Real hi = std::max({f_.height(i, j), f_.height(i, j + 1), f_.height(i + 1, j),
                                  f_.height(i + 1, j + 1)});
        if (hi < box.lower.y() || lo > box.upper.y()) continue;
        const std::uint32_t cell = std::uint32_t(i * cellsX + j);
        f(2 * cell);
        f(2 * cell + 1);
      }
  }

  void get(std::uint32_t t, TriangleInfo& info) const {
    const std::size_t cellsX = f_.cols() - 1, cellsZ = f_.rows() - 1;
    const std::size_t half = t & 1u, cell = t >> 1, i = cell / cellsX, j = cell % cellsX;
    std::array<std::uint32_t, 3> ids{};
    corners(i, j, half, ids);
    for (int k = 0; k < 3; ++k) {
      info.vertexIds[std::size_t(k)] = ids[std::size_t(k)];
      info.v[k] = vertex(ids[std::size_t(k)]);
    }
    info.normal = normalizedOr((info.v[1] - info.v[0]).cross(info.v[2] - info.v[0]), Vec3::UnitY());
    struct Across {
      bool exists = false;
      std::size_t i = 0, j = 0, half = 0, slot = 0;
    };
    std::array<Across, 3> across{};
    if (half == 0) {
      across[0] = {true, i, j, 1, 2};
      across[1] = {j + 1 < cellsX, i, j + 1, 1, 0};
      across[2] = {i >= 1, i - 1, j, 1, 1};
    } else {
      across[0] = {j >= 1, i, j - 1, 0, 1};
      across[1] = {i + 1 < cellsZ, i + 1, j, 0, 2};
      across[2] = {true, i, j, 0, 0};
    }
    for (std::size_t k = 0; k < 3; ++k) {
      info.edgeIds[k] = 3 * t + std::uint32_t(k);
      info.kinds[k] = EdgeKind::Boundary;
      const Across& a = across[k];
      if (!a.exists) continue;
      std::array<std::uint32_t, 3> other{};
      corners(a.i, a.j, a.half, other);
      info.kinds[k] = classifyEdge(info.normal, info.v[k], vertex(other[(a.slot + 2) % 3]));
      const std::uint32_t tn = std::uint32_t(2 * (a.i * cellsX + a.j) + a.half);
      if (tn < t) info.edgeIds[k] = 3 * tn + std::uint32_t(a.slot);
    }
  }

 private:
  void corners(std::size_t i, std::size_t j, std::size_t half,
               std::array<std::uint32_t, 3>& ids) const {
    const std::size_t c = f_.cols();
    const std::uint32_t a = std::uint32_t(i * c + j), b = a + 1;
    const std::uint32_t d = std::uint32_t((i + 1) * c + j), cc = d + 1;
    ids = half == 0 ? std::array<std::uint32_t, 3>{a, cc, b} : std::array<std::uint32_t, 3>{a, d, cc};
  }
  Vec3 vertex(std::uint32_t id) const { return f_.point(id / f_.cols(), id % f_.cols()); }

  const HeightField& f_;
};

// ---- Feature ids ---------------------------------------------------------------------------

// collideTriangle keys the triangle's features by its local corner / edge index; mesh-wide keys
// let the points of neighbouring triangles that are the same point merge.
std::uint32_t globalFeature(const TriangleInfo& info, std::uint32_t feature, bool sphere) {
  const auto type = static_cast<Feature>(feature >> 14);
  const std::uint32_t index = feature & 0x3fffu;
  if (sphere && type == Feature::Face) {  // collideTriangle's sphere: a TriangleFeature index
    if (index <= 2) return featureKey(Feature::Vertex, info.vertexIds[index]);
    if (index <= 5) return featureKey(Feature::Edge, info.edgeIds[index - 3]);
    return featureKey(Feature::Face, 0);
  }
  if (type == Feature::Vertex && index < 3) return featureKey(Feature::Vertex, info.vertexIds[index]);
  if (type == Feature::Edge && index < 3) return featureKey(Feature::Edge, info.edgeIds[index]);
  return feature;
}

// ---- Face contact along a forced normal ----------------------------------------------------

/// The convex shape's supporting feature in its local unit direction d (the points maximising
/// d . x, a polygon in loop order, a segment or a point) with a feature key per point.
int supportFeature(const Collider& convex, const Vec3& d, Vec3* pts, std::uint32_t* keys,
                   int capacity) {
  const Shape& shape = convex.shape();
  const auto polygon = [&](const PolyView& view) {
    const HullFace& face = view.faces[incidentFace(view, -d)];
    const int n = std::min(int(face.edgeCount), capacity);
    for (int k = 0; k < n; ++k) {
      const std::uint32_t v = view.halfEdges[face.firstEdge + std::uint32_t(k)].origin;
      pts[k] = view.vertices[v];
      keys[k] = featureKey(Feature::Vertex, v);
    }
    return n;
  };
  switch (shape.type()) {
    case ShapeType::Sphere:
      pts[0] = shape.get<Sphere>().radius * d;
      keys[0] = featureKey(Feature::Vertex, 0);
      return 1;
    case ShapeType::Capsule: {
      const Capsule& c = shape.get<Capsule>();
      const Vec3 axis(0, 2 * c.halfHeight, 0), s0(0, -c.halfHeight, 0);
      // The contact normal (from the mesh to the capsule) is -d.
      if (std::abs(d.y()) < kCylinderFeatureSine) {
        for (int k = 0; k < 2; ++k) {
          pts[k] = s0 + Real(k) * axis - c.radius * capsuleOffset(-d, axis, Real(k));
          keys[k] = featureKey(Feature::Vertex, std::uint32_t(k));
        }
        return 2;
      }
      const int k = d.y() > 0 ? 1 : 0;
      pts[0] = s0 + Real(k) * axis + c.radius * d;
      keys[0] = featureKey(Feature::Vertex, std::uint32_t(k));
      return 1;
    }
    case ShapeType::Box: {
      PolyStorage storage;
      return polygon(makePolyView(shape.get<Box>(), storage));
    }
    case ShapeType::Hull:
      return polygon(makePolyView(shape.get<ConvexHull>()));
    case ShapeType::Cylinder:
      return cylinderSupportFeature(shape.get<Cylinder>(), d, pts, keys);
    default:
      return 0;
  }
}

struct FeatureClipVertex {
  Vec3 p = Vec3::Zero();
  /// The convex feature the vertex is (kOriginal | key), or the polygon edge leading into it:
  /// an edge of the convex's feature (its index) or a triangle side plane (kAlongPlane | k).
  std::uint32_t key = 0;
  std::uint32_t edgeIn = 0;
  bool original = false;
};
constexpr std::uint32_t kAlongPlane = 0x80000000u;
constexpr int kClipCapacity = kMaxClipVertices + 8;

/// The contact of triangle `t` with the convex at `pose` (mesh frame) along the normal `ns`
/// (the face normal on the convex's side): its supporting feature along -ns clipped to the
/// triangle's prism (Sutherland-Hodgman), the points below the plane + speculative distance.
int faceContact(const TriangleInfo& t, const Vec3& ns, bool back, const Collider& convex,
                const Transform& pose, Real spec, ContactCandidate* out) {
  Vec3 local[kMaxClipVertices];
  std::uint32_t keys[kMaxClipVertices];
  const int n = supportFeature(convex, pose.q.conjugate() * (-ns), local, keys,
                               kMaxClipVertices - 8);
  FeatureClipVertex buf[2][kClipCapacity];
  int count = n, cur = 0;
  for (int k = 0; k < n; ++k)
    buf[0][k] = {pose.apply(local[k]), keys[k], std::uint32_t((k + n - 1) % n), true};
  for (int k = 0; k < 3 && count > 0; ++k) {
    const Vec3 side = (t.v[(k + 1) % 3] - t.v[k]).cross(t.normal);
    const Real offset = side.dot(t.v[k]);
    const FeatureClipVertex* in = buf[cur];
    FeatureClipVertex* o = buf[1 - cur];
    int m = 0;
    for (int i = 0; i < count; ++i) {
      const FeatureClipVertex& prev = in[(i + count - 1) % count];
      const FeatureClipVertex& v = in[i];
      const Real dp = side.dot(prev.p) - offset, dv = side.dot(v.p) - offset;
      if ((dp <= 0) != (dv <= 0)) {
        FeatureClipVertex x;
        x.p = prev.p + (dp / (dp - dv)) * (v.p - prev.p);
        x.original = false;
        // The crossing lies on the polygon edge leading into v, at side plane k; it is itself
        // followed (when entering) by a stretch along plane k.
        if (v.edgeIn & kAlongPlane) {
          const int j = int(v.edgeIn & ~kAlongPlane);
          const int corner = (k == (j + 1) % 3) ? k : j;  // the triangle corner of sides j, k
          x.key = makeId(featureKey(Feature::Vertex, t.vertexIds[std::size_t(corner)]),
                         featureKey(Feature::Face, 0));
        } else {
          x.key = makeId(featureKey(Feature::Edge, t.edgeIds[std::size_t(k)]),
                         featureKey(Feature::Edge, v.edgeIn));
        }
        x.edgeIn = dv <= 0 ? (kAlongPlane | std::uint32_t(k)) : v.edgeIn;
        if (m < kClipCapacity) o[m++] = x;
      }
      if (dv <= 0 && m < kClipCapacity) o[m++] = v;
    }
    count = m;
    cur = 1 - cur;
  }
  const std::uint32_t faceKey = featureKey(Feature::Face, back ? 1 : 0);
  int kept = 0;
  for (int i = 0; i < count && kept < kMaxClipVertices; ++i) {
    const FeatureClipVertex& v = buf[cur][i];
    const Real sep = ns.dot(v.p - t.v[0]);
    if (sep > spec) continue;
    ContactCandidate& c = out[kept++];
    c.pointB = v.p;
    c.pointA = v.p - sep * ns;
    c.separation = sep;
    c.id = v.original ? makeId(faceKey, v.key) : v.key;
  }
  return kept;
}

bool activeEdge(EdgeKind kind, bool back) {
  switch (kind) {
    case EdgeKind::Boundary:
    case EdgeKind::NonManifold:
      return true;
    case EdgeKind::Convex:
      return !back;
    case EdgeKind::Concave:
      return back;
    case EdgeKind::Flat:
      return false;
  }
  return true;
}

/// The side of triangle t the convex shape is on (true: behind it): its origin's side, or the
/// normal's when the origin lies in the plane (an edge axis can lean below the plane while the
/// shape is above it).
bool behind(const TriangleInfo& t, const Transform& pose, const ContactManifold& m) {
  const Real originSide = t.normal.dot(pose.p - t.v[0]);
  return originSide != 0 ? originSide < 0 : m.normal.dot(t.normal) < 0;
}

/// Applies the internal-edge rule to triangle t's manifold m (mesh frame). Returns false when
/// the manifold is to be dropped.
bool fixInternalEdges(const TriangleInfo& t, const Collider& convex, const Transform& pose,
                      const ContactSettings& settings, ContactManifold& m) {
  const bool back = behind(t, pose, m);
  const Vec3 ns = back ? Vec3(-t.normal) : t.normal;
  const bool sphere = convex.type() == ShapeType::Sphere;
  if (m.normal.dot(ns) < kSameNormalCos) {
    Vec3 outward[3];
    Real longest = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = t.v[(k + 1) % 3] - t.v[k];
      longest = std::max(longest, e.norm());
      outward[k] = normalizedOr(e.cross(t.normal), Vec3::Zero());
    }
    const Real tol = kOnEdgeRel * longest;
    bool active = false;
    for (int i = 0; i < m.pointCount && !active; ++i)
      for (int k = 0; k < 3 && !active; ++k)
        active = activeEdge(t.kinds[std::size_t(k)], back) &&
                 outward[k].dot(m.points[std::size_t(i)].pointA - t.v[k]) >= -tol;
    if (!active) {
      ContactCandidate pts[kMaxClipVertices];
      const int n = faceContact(t, ns, back, convex, pose, settings.speculativeDistance, pts);
      if (n == 0) return false;
      reduceManifold(pts, n, ns, Transform::identity(), m);
      return true;
    }
  }
  for (int i = 0; i < m.pointCount; ++i) {
    ContactPoint& p = m.points[std::size_t(i)];
    p.id = makeId(globalFeature(t, p.id >> 16, sphere), p.id & 0xffffu);
  }
  return true;
}

// ---- Merging -------------------------------------------------------------------------------

/// The full clipped face contacts of triangles whose manifold collideTriangle reduced (it keeps
/// at most four points, and fewer when its deepest and farthest points span an edge of the
/// contact polygon): merging selects its four from these, so that no corner lost in one
/// triangle's reduction is missing from the merged manifold. Per thread, reused (no allocation once grown).
struct PoolRange {
  std::uint32_t triangle = 0, begin = 0, count = 0;
};
struct FacePool {
  std::vector<ContactCandidate> points;
  std::vector<PoolRange> ranges;  // by triangle, ascending once sorted
};
FacePool& facePool() {
  thread_local FacePool pool;
  return pool;
}

/// Sorts out[first, end) by triangle (subShapeA), merges the manifolds whose normals agree
/// within rounding into the lowest triangle's (each point keeps its own separation, so the
/// triangles need not be coplanar), maps them from the mesh frame to the world and flips them
/// so that the convex shape is A.
void finishManifolds(std::vector<ContactManifold>& out, std::size_t first,
                     const Transform& poseMesh) {
  std::sort(out.begin() + std::ptrdiff_t(first), out.end(),
            [](const ContactManifold& a, const ContactManifold& b) {
              return a.subShapeA < b.subShapeA;
            });
  thread_local std::vector<ContactCandidate> scratch;
  FacePool& pool = facePool();
  std::sort(pool.ranges.begin(), pool.ranges.end(),
            [](const PoolRange& a, const PoolRange& b) { return a.triangle < b.triangle; });
  std::size_t write = first;
  for (std::size_t i = first; i < out.size(); ++i) {
    ContactManifold m = out[i];
    if (m.pointCount == 0) continue;  // merged into an earlier one
    scratch.clear();
    bool pooled = false;
    const auto gather = [&pool, &pooled](const ContactManifold& g) {
      const auto r = std::lower_bound(
          pool.ranges.begin(), pool.ranges.end(), g.subShapeA,
          [](const PoolRange& x, std::uint32_t t) { return x.triangle < t; });
      if (r != pool.ranges.end() && r->triangle == g.subShapeA) {
        pooled = true;
        scratch.insert(scratch.end(), pool.points.begin() + r->begin,
                       pool.points.begin() + r->begin + r->count);
        return;
      }
      for (int k = 0; k < g.pointCount; ++k) {
        const ContactPoint& p = g.points[std::size_t(k)];
        scratch.push_back({p.pointA, p.pointB, p.separation, p.id});
      }
    };
    gather(m);
    bool merged = false;
    for (std::size_t j = i + 1; j < out.size(); ++j) {
      if (out[j].pointCount == 0 || out[j].normal.dot(m.normal) < kSameNormalCos) continue;
      gather(out[j]);
      out[j].pointCount = 0;
      merged = true;
    }
    if (merged || pooled) {
      // One point per id (the deepest), in id order: deterministic whatever the gather order.
      std::sort(scratch.begin(), scratch.end(),
                [](const ContactCandidate& a, const ContactCandidate& b) {
                  return a.id != b.id ? a.id < b.id : a.separation < b.separation;
                });
      scratch.erase(std::unique(scratch.begin(), scratch.end(),
                                [](const ContactCandidate& a, const ContactCandidate& b) {
                                  return a.id == b.id;
                                }),
                    scratch.end());
      std::array<int, 4> keep{};
      thread_local std::vector<int> order;
      order.resize(scratch.size());
      std::iota(order.begin(), order.end(), 0);
      m.pointCount = spanningFour(scratch.data(), order.data(), int(scratch.size()), m.normal,
                                  true, keep);
      for (int k = 0; k < m.pointCount; ++k) {
        const ContactCandidate& c = scratch[std::size_t(keep[std::size_t(k)])];
        m.points[std::size_t(k)] = {c.pointA, c.pointB, c.separation, c.id};
      }
    }
    m.normal = poseMesh.rotate(m.normal);
    for (int k = 0; k < m.pointCount; ++k) {
      ContactPoint& p = m.points[std::size_t(k)];
      p.pointA = poseMesh.apply(p.pointA);
      p.pointB = poseMesh.apply(p.pointB);
    }
    flipManifold(m);
    out[write++] = m;
  }
  out.resize(write);
}

template <class Source>
void collideConvexTriangles(const Source& source, const Collider& convex,
                            const Transform& poseConvex, const Transform& poseMesh,
                            const ContactSettings& settings, std::vector<ContactManifold>& out) {
  if (!isConvex(convex.type())) return;
  const Transform pose = poseMesh.inverse() * poseConvex;  // convex -> mesh frame
  const Aabb box = worldBounds(convex.shape(), pose).inflated(settings.speculativeDistance);
  const std::size_t first = out.size();
  FacePool& pool = facePool();
  pool.points.clear();
  pool.ranges.clear();
  source.forEachCandidate(box, [&](std::uint32_t t) {
    TriangleInfo info;
    source.get(t, info);
    ContactManifold m;
    if (!collideTriangle(info.v, convex, pose, settings, m)) return;
    if (!fixInternalEdges(info, convex, pose, settings, m)) return;
    const bool back = behind(info, pose, m);
    const Vec3 ns = back ? Vec3(-info.normal) : info.normal;
    if (m.normal.dot(ns) >= kSameNormalCos) {
      ContactCandidate pts[kMaxClipVertices];
      const int n = faceContact(info, ns, back, convex, pose, settings.speculativeDistance, pts);
      if (n > m.pointCount) {
        pool.ranges.push_back({t, std::uint32_t(pool.points.size()), std::uint32_t(n)});
        pool.points.insert(pool.points.end(), pts, pts + n);
      }
    }
    m.subShapeA = t;
    m.subShapeB = 0;
    out.push_back(m);
  });
  finishManifolds(out, first, poseMesh);
}

/// The largest gap between two triangles (b's corners already in a's frame) over the complete
/// set of separating axes of two triangles: both normals, the nine edge-edge crosses, and each
/// triangle's in-plane edge normals (needed when they are coplanar or nearly so; the flat
/// polyhedra of collidePolyhedra have no side faces, so its SAT alone can report a touching pair
/// that a side axis separates). Positive: apart by at least that much.
Real triangleGap(const Vec3 (&a)[3], const Vec3 (&b)[3]) {
  Real best = -std::numeric_limits<Real>::infinity();
  const auto test = [&](const Vec3& axis) {
    const Real len = axis.norm();
    if (!(len > std::numeric_limits<Real>::min())) return;
    const Vec3 u = axis / len;
    Real minA = u.dot(a[0]), maxA = minA, minB = u.dot(b[0]), maxB = minB;
    for (int k = 1; k < 3; ++k) {
      minA = std::min(minA, u.dot(a[k])), maxA = std::max(maxA, u.dot(a[k]));
      minB = std::min(minB, u.dot(b[k])), maxB = std::max(maxB, u.dot(b[k]));
    }
    best = std::max(best, std::max(minB - maxA, minA - maxB));
  };
  const Vec3 na = (a[1] - a[0]).cross(a[2] - a[0]), nb = (b[1] - b[0]).cross(b[2] - b[0]);
  test(na);
  test(nb);
  for (int i = 0; i < 3; ++i) {
    const Vec3 ea = a[(i + 1) % 3] - a[i], eb = b[(i + 1) % 3] - b[i];
    test(na.cross(ea));
    test(nb.cross(eb));
    for (int j = 0; j < 3; ++j) test(ea.cross(b[(j + 1) % 3] - b[j]));
  }
  return best;
}

/// The closest points of two disjoint triangles (both in A's frame): the nearest of the six
/// vertex-triangle and nine edge-edge pairs. Writes a one-point manifold in the world (normal
/// from a to b, ids: feature pair kinds); false when they touch (no direction).
bool closestTrianglePoints(const Vec3 (&a)[3], const Vec3 (&b)[3], const Transform& poseA,
                           ContactManifold& m) {
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 pa = a[0], pb = b[0];
  std::uint32_t id = 0;
  const auto consider = [&](const Vec3& x, const Vec3& y, std::uint32_t key) {
    const Real d2 = (y - x).squaredNorm();
    if (d2 < best) best = d2, pa = x, pb = y, id = key;
  };
  for (std::uint32_t k = 0; k < 3; ++k) {
    consider(closestPointOnTriangle(b[k], a[0], a[1], a[2]).point, b[k],
             makeId(featureKey(Feature::Face, 0), featureKey(Feature::Vertex, k)));
    consider(a[k], closestPointOnTriangle(a[k], b[0], b[1], b[2]).point,
             makeId(featureKey(Feature::Vertex, k), featureKey(Feature::Face, 0)));
    for (std::uint32_t j = 0; j < 3; ++j) {
      Real s, t;
      const Vec3 &a0 = a[k], &a1 = a[(k + 1) % 3], &b0 = b[j], &b1 = b[(j + 1) % 3];
      closestSegmentPoints(a0, a1, b0, b1, &s, &t);
      consider(a0 + s * (a1 - a0), b0 + t * (b1 - b0),
               makeId(featureKey(Feature::Edge, k), featureKey(Feature::Edge, j)));
    }
  }
  const Real dist = std::sqrt(best);
  if (!(dist > 0)) return false;
  m = ContactManifold{};
  m.normal = poseA.rotate((pb - pa) / dist);
  m.pointCount = 1;
  m.points[0] = {poseA.apply(pa), poseA.apply(pb), dist, id};
  return true;
}

}  // namespace

void collideConvexMesh(const Collider& a, const Transform& poseA, const Collider& b,
                       const Transform& poseB, const ContactSettings& settings,
                       std::vector<ContactManifold>& out) {
  const MeshSource source(b.shape().get<TriangleMesh>(), *b.meshBvh());
  collideConvexTriangles(source, a, poseA, poseB, settings, out);
}

void collideConvexHeightField(const Collider& a, const Transform& poseA, const Collider& b,
                              const Transform& poseB, const ContactSettings& settings,
                              std::vector<ContactManifold>& out) {
  const FieldSource source(b.shape().get<HeightField>());
  collideConvexTriangles(source, a, poseA, poseB, settings, out);
}

void collideMeshes(const Collider& a, const Transform& poseA, const Collider& b,
                   const Transform& poseB, const ContactSettings& settings,
                   std::vector<ContactManifold>& out) {
  const MeshBvh& ta = *a.meshBvh();
  const MeshBvh& tb = *b.meshBvh();
  const Transform bToA = poseA.inverse() * poseB;
  const Real spec = settings.speculativeDistance;
  // Each pop pushes at most two pairs and one of the two nodes is a level deeper, so the stack
  // never holds more than depthA + depthB + 2 pairs.
  struct Pair {
    std::uint32_t a = 0, b = 0;
  };
  Pair stack[2 * MeshBvh::kMaxDepth + 4];
  int top = 0;
  stack[top++] = {0, 0};
  const std::size_t first = out.size();
  while (top > 0) {
    const Pair pr = stack[--top];
    const MeshBvh::Node& na = ta.nodes()[pr.a];
    const MeshBvh::Node& nb = tb.nodes()[pr.b];
    const Aabb boxA{na.lower, na.upper};
    const Aabb boxB = transformAabb(Aabb{nb.lower, nb.upper}, bToA).inflated(spec);
    if (!boxA.overlaps(boxB)) continue;
    if (na.isLeaf() && nb.isLeaf()) {
      for (std::uint32_t s = na.index; s < na.index + na.count; ++s) {
        const auto& ca = ta.slotCorners(s);
        const Vec3 triA[3] = {ca[0], ca[1], ca[2]};
        PolyStorage storeA;
        const PolyView viewA = makePolyView(triA, storeA);
        for (std::uint32_t r = nb.index; r < nb.index + nb.count; ++r) {
          const auto& cb = tb.slotCorners(r);
          const Vec3 triB[3] = {cb[0], cb[1], cb[2]};
          const Vec3 triBInA[3] = {bToA.apply(cb[0]), bToA.apply(cb[1]), bToA.apply(cb[2])};
          const Real gap = triangleGap(triA, triBInA);
          if (gap > spec) continue;
          ContactManifold m;
          if (gap > 0) {
            // Apart (speculative): the exact closest points, one point along their direction.
            if (!closestTrianglePoints(triA, triBInA, poseA, m)) continue;
            if (m.points[0].separation > spec) continue;
          } else {
            PolyStorage storeB;
            if (!collidePolyhedra(viewA, poseA, makePolyView(triB, storeB), poseB, settings, m))
              continue;
          }
          m.subShapeA = ta.slotTriangles()[s];
          m.subShapeB = tb.slotTriangles()[r];
          out.push_back(m);
        }
      }
      continue;
    }
    // Split the leaf-less side, or the larger box when both are inner nodes.
    const bool splitA = nb.isLeaf() || (!na.isLeaf() && boxA.surfaceArea() >= boxB.surfaceArea());
    if (splitA) {
      stack[top++] = {na.index, pr.b};
      stack[top++] = {pr.a + 1, pr.b};
    } else {
      stack[top++] = {pr.a, nb.index};
      stack[top++] = {pr.a, pr.b + 1};
    }
  }
  std::sort(out.begin() + std::ptrdiff_t(first), out.end(),
            [](const ContactManifold& x, const ContactManifold& y) {
              return x.subShapeA != y.subShapeA ? x.subShapeA < y.subShapeA
                                                : x.subShapeB < y.subShapeB;
            });
}

}  // namespace inertia::detail
