// Distance between two triangle meshes: a branch-and-bound traversal of both BVHs at once
// (the dual-tree nearest-pair search of Larsen, Gottschalk, Lin and Manocha, "Fast proximity
// queries with swept sphere volumes", 1999, with AABBs instead of swept spheres), and the exact
// triangle-triangle distance at the leaves.
#include <algorithm>
#include <cmath>
#include <limits>

#include "inertia/collision/distance.h"
#include "inertia/collision/mesh_bvh.h"
#include "inertia/collision/triangle.h"
#include "inertia/core/error.h"
#include "inertia/geometry/bounds.h"
#include "polyhedron.h"

namespace inertia {

namespace {

struct TrianglePair {
  Real distanceSquared = 0;
  Vec3 pointA = Vec3::Zero();
  Vec3 pointB = Vec3::Zero();
};

/// The signed distances (times |n|) of t's corners to the plane of (p0, p1, p2); returns |n|^2.
Real planeSides(const Vec3 (&p)[3], const Vec3 (&t)[3], Real (&side)[3]) {
  const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
  for (int k = 0; k < 3; ++k) side[k] = n.dot(t[k] - p[0]);
  return n.squaredNorm();
}

bool strictlyOneSide(const Real (&side)[3]) {
  return (side[0] > 0 && side[1] > 0 && side[2] > 0) || (side[0] < 0 && side[1] < 0 && side[2] < 0);
}

/// When all of t's corners lie strictly on one side of the plane: the squared distance of the
/// nearest to it, a lower bound of the triangles' distance; else 0.
Real planeGapSquared(const Real (&side)[3], Real normSquared) {
  const Real lo = std::min({std::abs(side[0]), std::abs(side[1]), std::abs(side[2])});
  return strictlyOneSide(side) && normSquared > 0 ? lo * lo / normSquared : Real(0);
}

/// A point where an edge of `e` crosses triangle `t` (edges straddling t's plane only), if any.
bool edgeThroughTriangle(const Vec3 (&e)[3], const Real (&sideOfE)[3], const Vec3 (&t)[3],
                         Vec3* point) {
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    if ((sideOfE[k] > 0 && sideOfE[j] > 0) || (sideOfE[k] < 0 && sideOfE[j] < 0)) continue;
    const Vec3 d = e[j] - e[k];
    const Real s = intersectRayTriangle(e[k], d, 1, t[0], t[1], t[2]);
    if (s >= 0) {
      *point = e[k] + s * d;
      return true;
    }
  }
  return false;
}

/// Two disjoint triangles are closest at a pair of edges or at a vertex and the other's face;
/// crossing triangles meet where an edge of one passes through the other (for coplanar ones,
/// where their edges cross or a vertex lies inside the other, both among the features).
/// Pairs whose plane gap exceeds `cut2` (squared, m^2) are left at an infinite distance.
TrianglePair trianglePair(const Vec3 (&a)[3], const Vec3 (&b)[3], Real cut2) {
  TrianglePair out;
  Real sideB[3], sideA[3];
  const Real nA2 = planeSides(a, b, sideB), nB2 = planeSides(b, a, sideA);
  const Real gap2 = std::max(planeGapSquared(sideB, nA2), planeGapSquared(sideA, nB2));
  if (gap2 > cut2) {
    out.distanceSquared = std::numeric_limits<Real>::infinity();
    return out;
  }
  if (!strictlyOneSide(sideB) && !strictlyOneSide(sideA)) {
    Vec3 x = Vec3::Zero();
    if (edgeThroughTriangle(b, sideB, a, &x) || edgeThroughTriangle(a, sideA, b, &x)) {
      out.pointA = out.pointB = x;
      return out;
    }
  }
  out.distanceSquared = std::numeric_limits<Real>::infinity();
  const auto consider = [&](const Vec3& x, const Vec3& y) {
    const Real d2 = (y - x).squaredNorm();
    if (d2 < out.distanceSquared) out.distanceSquared = d2, out.pointA = x, out.pointB = y;
  };
  for (int k = 0; k < 3; ++k) {
    consider(closestPointOnTriangle(b[k], a[0], a[1], a[2]).point, b[k]);
    consider(a[k], closestPointOnTriangle(a[k], b[0], b[1], b[2]).point);
    const Vec3 &a0 = a[k], &a1 = a[(k + 1) % 3];
    for (int j = 0; j < 3; ++j) {
      const Vec3 &b0 = b[j], &b1 = b[(j + 1) % 3];
      Real s = 0, t = 0;
      detail::closestSegmentPoints(a0, a1, b0, b1, &s, &t);
      consider(a0 + s * (a1 - a0), b0 + t * (b1 - b0));
    }
  }
  return out;
}

/// Squared distance between two boxes: a lower bound of the distance of anything inside them.
Real boxDistanceSquared(const Aabb& x, const Aabb& y) {
  return (y.lower - x.upper).cwiseMax(x.lower - y.upper).cwiseMax(Vec3::Zero()).squaredNorm();
}

Aabb triangleBox(const Vec3 (&t)[3]) {
  return {t[0].cwiseMin(t[1]).cwiseMin(t[2]), t[0].cwiseMax(t[1]).cwiseMax(t[2])};
}

}  // namespace

TriangleDistance triangleDistance(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                                  const Vec3& b1, const Vec3& b2) {
  const Vec3 a[3] = {a0, a1, a2}, b[3] = {b0, b1, b2};
  const TrianglePair p = trianglePair(a, b, std::numeric_limits<Real>::infinity());
  return {std::sqrt(p.distanceSquared), p.pointA, p.pointB};
}

namespace {

/// The branch-and-bound search itself, both colliders already checked to be meshes.
std::optional<MeshDistance> searchMeshes(const Collider& a, const Transform& poseA,
                                         const Collider& b, const Transform& poseB,
                                         Real maxDistance) {
  const MeshBvh& ta = *a.meshBvh();
  const MeshBvh& tb = *b.meshBvh();
  const Transform bToA = poseA.inverse() * poseB;
  const auto boxA = [&](std::uint32_t n) { return Aabb{ta.nodes()[n].lower, ta.nodes()[n].upper}; };
  const Transform aToB = bToA.inverse();
  const auto boxB = [&](std::uint32_t n) {
    return transformAabb(Aabb{tb.nodes()[n].lower, tb.nodes()[n].upper}, bToA);
  };
  // A lower bound of the distance between nodes i of A and j of B: the larger of the box gaps
  // seen in each tree's frame (B's box carried into A's frame, and A's into B's); each frame's
  // rotated box is loose along the other's axes, so the larger is usually much tighter.
  const auto lowerBound = [&](const Aabb& iInA, std::uint32_t j, const Aabb& jInA) {
    return std::max(boxDistanceSquared(iInA, jInA),
                    boxDistanceSquared(transformAabb(iInA, aToB),
                                       Aabb{tb.nodes()[j].lower, tb.nodes()[j].upper}));
  };

  // Everything in A's frame. best2 is the squared distance to beat; a pair no nearer is pruned
  // once something was found (before that, pairs at exactly maxDistance still count).
  Real best2 = maxDistance * maxDistance;
  bool found = false;
  MeshDistance result;
  const auto pruned = [&](Real lower2) { return lower2 > best2 || (found && lower2 >= best2); };

  // Each pop pushes at most two pairs and one of the two nodes is a level deeper, so the stack
  // never holds more than depthA + depthB + 2 pairs (as collideMeshes).
  struct Pair {
    std::uint32_t a = 0, b = 0;
    Real lower2 = 0;
  };
  Pair stack[2 * MeshBvh::kMaxDepth + 4];
  int top = 0;
  stack[top++] = {0, 0, boxDistanceSquared(boxA(0), boxB(0))};
  while (top > 0) {
    const Pair pr = stack[--top];
    if (pruned(pr.lower2)) continue;
    const MeshBvh::Node& na = ta.nodes()[pr.a];
    const MeshBvh::Node& nb = tb.nodes()[pr.b];
    if (na.isLeaf() && nb.isLeaf()) {
      Vec3 triB[MeshBvh::kMaxLeafSize][3];
      Aabb boxTriB[MeshBvh::kMaxLeafSize];
      for (std::uint32_t r = 0; r < nb.count; ++r) {
        const auto& cb = tb.slotCorners(nb.index + r);
        for (int k = 0; k < 3; ++k) triB[r][k] = bToA.apply(cb[std::size_t(k)]);
        boxTriB[r] = triangleBox(triB[r]);
      }
      for (std::uint32_t s = na.index; s < na.index + na.count; ++s) {
        const auto& ca = ta.slotCorners(s);
        const Vec3 triA[3] = {ca[0], ca[1], ca[2]};
        const Aabb boxTriA = triangleBox(triA);
        for (std::uint32_t r = 0; r < nb.count; ++r) {
          if (pruned(boxDistanceSquared(boxTriA, boxTriB[r]))) continue;
          const TrianglePair p = trianglePair(triA, triB[r], best2);
          if (pruned(p.distanceSquared)) continue;
          best2 = p.distanceSquared;
          found = true;
          result.pointA = p.pointA;
          result.pointB = p.pointB;
          result.triangleA = ta.slotTriangles()[s];
          result.triangleB = tb.slotTriangles()[nb.index + r];
          if (best2 == 0) break;
        }
        if (found && best2 == 0) break;
      }
      if (found && best2 == 0) break;  // intersecting: nothing is nearer
      continue;
    }
    // Split the leaf-less side, or the larger box when both are inner nodes; visit the nearer
    // child pair first (pushed last).
    const Aabb ba = boxA(pr.a), bb = boxB(pr.b);
    const bool splitA = nb.isLeaf() || (!na.isLeaf() && ba.surfaceArea() >= bb.surfaceArea());
    Pair first, second;
    if (splitA) {
      first = {pr.a + 1, pr.b, lowerBound(boxA(pr.a + 1), pr.b, bb)};
      second = {na.index, pr.b, lowerBound(boxA(na.index), pr.b, bb)};
    } else {
      first = {pr.a, pr.b + 1, lowerBound(ba, pr.b + 1, boxB(pr.b + 1))};
      second = {pr.a, nb.index, lowerBound(ba, nb.index, boxB(nb.index))};
    }
    if (first.lower2 > second.lower2) std::swap(first, second);
    if (!pruned(second.lower2)) stack[top++] = second;
    if (!pruned(first.lower2)) stack[top++] = first;
  }
  if (!found) return std::nullopt;
  result.distance = std::sqrt(best2);
  result.pointA = poseA.apply(result.pointA);
  result.pointB = poseA.apply(result.pointB);
  return result;
}

void checkMeshes(const Collider& a, const Collider& b) {
  if (a.type() != ShapeType::Mesh || b.type() != ShapeType::Mesh)
    throw InvalidArgument("meshDistance: both colliders must be triangle meshes");
}

}  // namespace

std::optional<MeshDistance> meshDistance(const Collider& a, const Transform& poseA,
                                         const Collider& b, const Transform& poseB,
                                         Real maxDistance) {
  checkMeshes(a, b);
  if (!(maxDistance >= 0)) throw InvalidArgument("meshDistance: maxDistance must be >= 0");
  // Intersecting meshes first, with a zero bound: it visits only pairs of touching boxes and
  // stops at the first crossing pair, where the nearest-first search would first work through
  // the many nearly-touching pairs around it.
  if (auto hit = searchMeshes(a, poseA, b, poseB, 0)) return hit;
  if (maxDistance == 0) return std::nullopt;
  return searchMeshes(a, poseA, b, poseB, maxDistance);
}

bool meshesOverlap(const Collider& a, const Transform& poseA, const Collider& b,
                   const Transform& poseB) {
  checkMeshes(a, b);
  return searchMeshes(a, poseA, b, poseB, 0).has_value();
}

}  // namespace inertia
