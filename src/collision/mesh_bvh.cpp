// The mesh BVH: binned-SAH construction into a flat node array, and its three traversals.
#include "inertia/collision/mesh_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "local_queries.h"

namespace inertia {

using detail::normalizedOr;

namespace {

constexpr int kBins = 16;
// Below this depth splits follow the SAH; deeper, object-median splits halve the count, so
// the depth stays under kSahDepth + log2(2^32 / kMaxLeafSize) < MeshBvh::kMaxDepth.
constexpr int kSahDepth = 64;

struct BuildItem {
  Aabb box;
  Vec3 centroid;
  std::uint32_t triangle;
};

struct Builder {
  std::vector<BuildItem>& items;
  std::vector<MeshBvh::Node>& nodes;
  Real inflate;
  int maxDepth = 0;

  std::uint32_t build(std::uint32_t begin, std::uint32_t end, int depth) {
    maxDepth = std::max(maxDepth, depth);
    const std::uint32_t self = std::uint32_t(nodes.size());
    nodes.emplace_back();
    Aabb box, centroids;
    for (std::uint32_t i = begin; i < end; ++i) {
      box.merge(items[i].box);
      centroids.extend(items[i].centroid);
    }
    const std::uint32_t count = end - begin;
    std::uint32_t mid = split(begin, end, box, centroids, depth);
    if (mid == begin) {  // leaf
      nodes[self].lower = box.lower.array() - inflate;
      nodes[self].upper = box.upper.array() + inflate;
      nodes[self].index = begin;
      nodes[self].count = count;
      return self;
    }
    build(begin, mid, depth + 1);
    const std::uint32_t right = build(mid, end, depth + 1);
    Node& n = nodes[self];
    n.index = right;
    n.count = 0;
    // Children were inflated already; the parent is their union.
    n.lower = nodes[self + 1].lower.cwiseMin(nodes[right].lower);
    n.upper = nodes[self + 1].upper.cwiseMax(nodes[right].upper);
    return self;
  }
  using Node = MeshBvh::Node;

  // Returns the split position, or begin for "make a leaf".
  std::uint32_t split(std::uint32_t begin, std::uint32_t end, const Aabb& box,
                      const Aabb& centroids, int depth) {
    const std::uint32_t count = end - begin;
    if (count <= 1) return begin;
    if (depth < kSahDepth) {
      // Binned SAH (Wald 2007): cost Ct + (A_L N_L + A_R N_R) / A with Ct = Ci = 1, in units
      // of A: leaf cost N A versus A + A_L N_L + A_R N_R.
      Real bestCost = kInfinity;
      int bestAxis = -1, bestBin = -1;
      for (int axis = 0; axis < 3; ++axis) {
        const Real lo = centroids.lower[axis], extent = centroids.upper[axis] - lo;
        if (!(extent > 0)) continue;
        const Real scale = Real(kBins) / extent;
        Aabb bins[kBins];
        std::uint32_t counts[kBins] = {};
        for (std::uint32_t i = begin; i < end; ++i) {
          const int b = std::min(kBins - 1, int((items[i].centroid[axis] - lo) * scale));
          bins[b].merge(items[i].box);
          ++counts[b];
        }
        Real rightArea[kBins];
        std::uint32_t rightCount[kBins];
        Aabb acc;
        std::uint32_t n = 0;
        for (int b = kBins - 1; b > 0; --b) {
          acc.merge(bins[b]);
          n += counts[b];
          rightArea[b] = n ? acc.surfaceArea() : Real(0);
          rightCount[b] = n;
        }
        acc = Aabb::empty();
        n = 0;
        for (int b = 0; b < kBins - 1; ++b) {
          acc.merge(bins[b]);
          n += counts[b];
          if (n == 0 || rightCount[b + 1] == 0) continue;
          const Real cost =
              acc.surfaceArea() * Real(n) + rightArea[b + 1] * Real(rightCount[b + 1]);
          if (cost < bestCost) {
            bestCost = cost;
            bestAxis = axis;
            bestBin = b;
          }
        }
      }
      const Real area = box.surfaceArea();
      if (bestAxis < 0)
        return count <= MeshBvh::kMaxLeafSize ? begin : medianSplit(begin, end, centroids);
      if (count <= MeshBvh::kMaxLeafSize && area + bestCost >= Real(count) * area) return begin;
      const Real lo = centroids.lower[bestAxis];
      const Real scale = Real(kBins) / (centroids.upper[bestAxis] - lo);
      auto* mid =
          std::partition(items.data() + begin, items.data() + end, [&](const BuildItem& it) {
            return std::min(kBins - 1, int((it.centroid[bestAxis] - lo) * scale)) <= bestBin;
          });
      const std::uint32_t m = std::uint32_t(mid - items.data());
      if (m > begin && m < end) return m;
      return medianSplit(begin, end, centroids);
    }
    if (count <= MeshBvh::kMaxLeafSize) return begin;
    return medianSplit(begin, end, centroids);
  }

  std::uint32_t medianSplit(std::uint32_t begin, std::uint32_t end, const Aabb& centroids) {
    int axis = 0;
    const Vec3 e = centroids.upper - centroids.lower;
    if (e.y() > e[axis]) axis = 1;
    if (e.z() > e[axis]) axis = 2;
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(items.data() + begin, items.data() + mid, items.data() + end,
                     [axis](const BuildItem& x, const BuildItem& y) {
                       return x.centroid[axis] < y.centroid[axis];
                     });
    return mid;
  }
};

// Distance squared from p to the node's box (0 inside).
Real boxDistanceSquared(const MeshBvh::Node& n, const Vec3& p) {
  const Vec3 d = (n.lower - p).cwiseMax(p - n.upper).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

// Slab test of the ray against the node's box: the entry s, or +inf for a miss.
Real boxEntry(const MeshBvh::Node& n, const Vec3& o, const Vec3& inv, Real tMax) {
  const Vec3 t1 = (n.lower - o).cwiseProduct(inv);
  const Vec3 t2 = (n.upper - o).cwiseProduct(inv);
  const Real enter = std::max(t1.cwiseMin(t2).maxCoeff(), Real(0));
  const Real exit = std::min(t1.cwiseMax(t2).minCoeff(), tMax);
  return enter <= exit ? enter : kInfinity;
}

}  // namespace

MeshBvh::MeshBvh(const TriangleMesh& mesh) {
  const auto& verts = mesh.vertices();
  const auto& tris = mesh.triangles();
  const std::uint32_t n = std::uint32_t(tris.size());
  std::vector<BuildItem> items(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    Aabb b;
    for (int k = 0; k < 3; ++k) b.extend(verts[tris[t][k]]);
    items[t] = {b, b.center(), t};
  }
  // Inflate the boxes by a few ulps of the mesh's coordinates, so that the slab test never
  // rejects a box whose triangle Moller-Trumbore hits (both round differently).
  const Aabb& mb = mesh.bounds();
  const Real scale = std::max(mb.lower.cwiseAbs().maxCoeff(), mb.upper.cwiseAbs().maxCoeff());
  Builder builder{items, nodes_, 16 * std::numeric_limits<Real>::epsilon() * scale};
  nodes_.reserve(2 * std::size_t(n));
  builder.build(0, n, 0);
  nodes_.shrink_to_fit();
  depth_ = builder.maxDepth;

  corners_.resize(n);
  slotTriangle_.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) {
    const Triangle& t = tris[items[s].triangle];
    corners_[s] = {verts[t[0]], verts[t[1]], verts[t[2]]};
    slotTriangle_[s] = items[s].triangle;
  }
  normals_ = mesh.normals();

  closed_ = mesh.isClosed();
  if (closed_) {
    // Baerentzen and Aanaes 2005: edge pseudonormal = sum of the two face normals; vertex
    // pseudonormal = sum of the face normals weighted by the incident angles.
    std::vector<Vec3> vertexSum(verts.size(), Vec3::Zero());
    for (std::uint32_t t = 0; t < n; ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3& v = verts[tris[t][k]];
        const Vec3 e1 = verts[tris[t][(k + 1) % 3]] - v, e2 = verts[tris[t][(k + 2) % 3]] - v;
        const Real angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
        vertexSum[tris[t][k]] += angle * normals_[t];
      }
    edgeNormals_.resize(n);
    vertexNormals_.resize(n);
    const auto& nb = mesh.neighbours();
    for (std::uint32_t t = 0; t < n; ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3 sum =
            nb[t][k] == TriangleMesh::kNone ? normals_[t] : Vec3(normals_[t] + normals_[nb[t][k]]);
        edgeNormals_[t][k] = normalizedOr(sum, normals_[t]);
        vertexNormals_[t][k] = normalizedOr(vertexSum[tris[t][k]], normals_[t]);
      }
  }
}

Vec3 MeshBvh::pseudonormal(std::uint32_t triangle, TriangleFeature feature) const {
  if (!closed_ || feature == TriangleFeature::Face) return normals_[triangle];
  const int f = int(feature);
  return f < 3 ? vertexNormals_[triangle][f] : edgeNormals_[triangle][f - 3];
}

std::optional<MeshBvh::RayHit> MeshBvh::castRay(const Vec3& origin, const Vec3& direction,
                                                Real maxFraction) const {
  // A zero direction component gets a huge finite inverse instead of inf, so that
  // (bound - origin) * inv is never 0 * inf = NaN.
  constexpr Real kTiny = std::numeric_limits<Real>::min() * 16;
  Vec3 inv;
  for (int i = 0; i < 3; ++i) {
    const Real d = direction[i];
    inv[i] = std::abs(d) > kTiny ? Real(1) / d : std::copysign(Real(1) / kTiny, d);
  }
  Real best = maxFraction;
  std::uint32_t bestSlot = 0;
  bool found = false;
  struct Entry {
    std::uint32_t node;
    Real enter;
  };
  Entry stack[kMaxDepth + 2];
  int top = 0;
  if (boxEntry(nodes_[0], origin, inv, best) < kInfinity) stack[top++] = {0, 0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.enter > best) continue;  // entered beyond the best hit: cannot improve
    const Node& n = nodes_[e.node];
    if (n.isLeaf()) {
      for (std::uint32_t s = n.index; s < n.index + n.count; ++s) {
        const auto& c = corners_[s];
        const Real t = intersectRayTriangle(origin, direction, best, c[0], c[1], c[2]);
        if (t >= 0 && (!found || t < best)) {
          best = t;
          bestSlot = s;
          found = true;
        }
      }
      continue;
    }
    const std::uint32_t a = e.node + 1, b = n.index;
    const Real ta = boxEntry(nodes_[a], origin, inv, best);
    const Real tb = boxEntry(nodes_[b], origin, inv, best);
    // Push the farther child first so the nearer one is visited first.
    if (ta <= tb) {
      if (tb < kInfinity) stack[top++] = {b, tb};
      if (ta < kInfinity) stack[top++] = {a, ta};
    } else {
      if (ta < kInfinity) stack[top++] = {a, ta};
      stack[top++] = {b, tb};
    }
  }
  if (!found) return std::nullopt;
  const std::uint32_t tri = slotTriangle_[bestSlot];
  Vec3 normal = normals_[tri];
  if (normal.dot(direction) > 0) normal = -normal;
  return RayHit{best, tri, normal};
}

MeshBvh::Closest MeshBvh::closestPoint(const Vec3& p) const {
  Closest best;
  best.distanceSquared = kInfinity;
  struct Entry {
    std::uint32_t node;
    Real d2;
  };
  Entry stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = {0, 0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best.distanceSquared) continue;
    const Node& n = nodes_[e.node];
    if (n.isLeaf()) {
      for (std::uint32_t s = n.index; s < n.index + n.count; ++s) {
        const auto& c = corners_[s];
        const TriangleClosest q = closestPointOnTriangle(p, c[0], c[1], c[2]);
        const Real d2 = (p - q.point).squaredNorm();
        if (d2 < best.distanceSquared) {
          best = {q.point, d2, slotTriangle_[s], q.feature};
        }
      }
      continue;
    }
    const std::uint32_t a = e.node + 1, b = n.index;
    const Real da = boxDistanceSquared(nodes_[a], p), db = boxDistanceSquared(nodes_[b], p);
    if (da <= db) {
      if (db < best.distanceSquared) stack[top++] = {b, db};
      if (da < best.distanceSquared) stack[top++] = {a, da};
    } else {
      if (da < best.distanceSquared) stack[top++] = {a, da};
      if (db < best.distanceSquared) stack[top++] = {b, db};
    }
  }
  return best;
}

}  // namespace inertia
