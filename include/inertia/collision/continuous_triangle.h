// Continuous collision between moving triangle features, for deformables (cloth, soft bodies):
// vertex-face and edge-edge tests over one step with every point moving linearly from its start
// to its end position, t in [0, 1] (Provot, "Collision and self-collision handling in cloth
// model dedicated to design garments", 1997; Bridson, Fedkiw and Anderson, "Robust treatment
// of collisions, contact and friction for cloth animation", SIGGRAPH 2002).
//
// The four points can only meet when they are coplanar, which is a cubic in t: for a vertex p
// and triangle (a, b, c),  f(t) = ((b - a)(t) x (c - a)(t)) . (p - a)(t) = 0;  for edges
// (p0, p1) and (q0, q1),  f(t) = ((p1 - p0)(t) x (q1 - q0)(t)) . (q0 - p0)(t) = 0.
// The roots in [0, 1] are found in order: the cubic's critical points split [0, 1] into
// monotone pieces, each sign change is refined by safeguarded Newton (bisection whenever a
// Newton step leaves the bracket), and lower-degree cases (quadratic, linear, constant) fall out
// of the same code. At each root the proximity test decides: the vertex within `thickness` of
// the triangle, or the two segments within `thickness` of each other. Local minima of |f| that
// come within thickness of coplanarity without crossing (grazing) are tested too.
//
// When f is zero for all t (the points stay coplanar: motion within a plane), the plane test
// says nothing; the candidate times are then t = 0, t = 1, the times at which a point crosses
// the line of an edge of the other feature, and the times of closest approach of pairs of
// points, each checked by the proximity test. This is exact for rigid in-plane motions and
// best-effort otherwise.
//
// All arithmetic inside runs in double, whatever Real is: a float build's inputs convert
// exactly and the cubic's coefficients (products of three differences) keep 53 bits.
// Never NaN, never loops unboundedly, for finite input.
#pragma once

#include <optional>

#include "inertia/core/types.h"

namespace inertia {

/// A point moving linearly over a step: x(t) = (1 - t) start + t end, t in [0, 1] (m).
struct LinearMotion {
  Vec3 start = Vec3::Zero();  ///< Position at t = 0 (m).
  Vec3 end = Vec3::Zero();    ///< Position at t = 1 (m).

  /// Position at t (m).
  Vec3 at(Real t) const { return (1 - t) * start + t * end; }
};

/// Settings of the continuous triangle tests.
struct ContinuousTriangleSettings {
  /// Proximity (m, >= 0, finite) within which coplanar features count as touching: cloth
  /// thickness in Bridson et al. A small positive value also absorbs rounding on edges.
  Real thickness = Real(1e-5);
};

/// The earliest contact of a vertex with a triangle.
struct VertexFaceContact {
  Real time = 0;  ///< Fraction of the step at contact, in [0, 1].
  /// Barycentric coordinates (w0, w1, w2) of the triangle point closest to the vertex at `time`:
  /// closest = w0 a + w1 b + w2 c, each in [0, 1], summing to 1.
  Vec3 barycentric = Vec3(1, 0, 0);
  /// Unit triangle normal at `time`, on the side the vertex came from (from the triangle
  /// towards the vertex before contact); for a zero-area triangle, against the vertex's
  /// relative velocity.
  Vec3 normal = Vec3::UnitY();
  Real distance = 0;  ///< Distance (m) from the vertex to the triangle at `time`.
};

/// The earliest contact of two edges.
struct EdgeEdgeContact {
  Real time = 0;  ///< Fraction of the step at contact, in [0, 1].
  Real s = 0;     ///< Closest point on edge A at `time`: p0 + s (p1 - p0), s in [0, 1].
  Real u = 0;     ///< Closest point on edge B at `time`: q0 + u (q1 - q0), u in [0, 1].
  /// Unit normal at `time`, from edge B towards edge A on the side A came from: the normalised
  /// cross product of the edge directions; for parallel edges, against A's velocity relative to
  /// B (across the edges), else the direction between the closest points, else any
  /// perpendicular.
  Vec3 normal = Vec3::UnitY();
  Real distance = 0;  ///< Distance (m) between the edges at `time`.
};

/// Earliest time in [0, 1] at which the moving vertex `p` comes within settings.thickness of
/// the moving triangle (a, b, c) while coplanar with it (see the file comment), or nothing.
/// Throws InvalidArgument for a negative or non-finite thickness.
std::optional<VertexFaceContact> vertexFaceContinuous(
    const LinearMotion& p, const LinearMotion& a, const LinearMotion& b, const LinearMotion& c,
    const ContinuousTriangleSettings& settings = {});

/// Earliest time in [0, 1] at which the moving edges (p0, p1) and (q0, q1) come within
/// settings.thickness of each other while coplanar (see the file comment), or nothing.
/// Throws InvalidArgument for a negative or non-finite thickness.
std::optional<EdgeEdgeContact> edgeEdgeContinuous(const LinearMotion& p0, const LinearMotion& p1,
                                                  const LinearMotion& q0, const LinearMotion& q1,
                                                  const ContinuousTriangleSettings& settings = {});

}  // namespace inertia
