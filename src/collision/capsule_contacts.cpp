// Capsule against capsule (closest points of the core segments; two points when parallel and
// overlapping) and against a box or hull (the polyhedron-segment SAT of polyhedron_contacts).
#include <algorithm>
#include <cmath>

#include "contact_pairs.h"
#include "local_queries.h"
#include "polyhedron.h"

namespace inertia::detail {

namespace {

// Segments whose directions differ by less than this sine count as parallel: their overlap
// gives two points (a capsule lying on a capsule) rather than one that slides along it.
constexpr Real kParallelCapsuleSine = Real(0.02);

}  // namespace

bool collideCapsules(const Collider& a, const Transform& poseA, const Collider& b,
                     const Transform& poseB, const ContactSettings& settings,
                     ContactManifold& m) {
  const Capsule& ca = a.shape().get<Capsule>();
  const Capsule& cb = b.shape().get<Capsule>();
  const Real spec = settings.speculativeDistance, radii = ca.radius + cb.radius;
  const Vec3 a0 = poseA.apply(Vec3(0, -ca.halfHeight, 0)), a1 = poseA.apply(Vec3(0, ca.halfHeight, 0));
  const Vec3 b0 = poseB.apply(Vec3(0, -cb.halfHeight, 0)), b1 = poseB.apply(Vec3(0, cb.halfHeight, 0));
  const Vec3 da = a1 - a0, db = b1 - b0;
  const Real la = da.norm(), lb = db.norm();
  Real s, t;
  closestSegmentPoints(a0, a1, b0, b1, &s, &t);
  const Vec3 pa = a0 + s * da, pb = b0 + t * db;
  const Real dist = (pb - pa).norm();
  if (dist - radii > spec) return false;
  // Crossing cores (dist 0): the common perpendicular, else any perpendicular of A's axis.
  Vec3 fallback = normalizedOr(da.cross(db), poseA.rotate(Vec3::UnitX()));
  if (fallback.dot(poseB.p - poseA.p) < 0) fallback = -fallback;
  const Vec3 n = normalizedOr(pb - pa, fallback);
  m.normal = n;

  // Surface points: along n from an end, perpendicular to the axis from inside the segment.
  const auto setPoint = [&](int k, const Vec3& onA, Real sa, const Vec3& onB, Real sb,
                            std::uint32_t id) {
    ContactPoint& c = m.points[std::size_t(k)];
    c.pointA = onA - ca.radius * capsuleOffset(-n, da, sa);
    c.pointB = onB - cb.radius * capsuleOffset(n, db, sb);
    c.separation = (c.pointB - c.pointA).dot(n);
    c.id = id;
  };
  if (da.cross(db).norm() < kParallelCapsuleSine * la * lb) {
    // Parallel: the overlap of B's projection on A's axis, each end with its own closest point.
    const Vec3 ua = da / la;
    const Real tb0 = ua.dot(b0 - a0), tb1 = ua.dot(b1 - a0);
    const Real lo = std::max(Real(0), std::min(tb0, tb1)), hi = std::min(la, std::max(tb0, tb1));
    if (hi - lo > Real(1e-3) * la) {
      int count = 0;
      const Real ends[2] = {lo, hi};
      for (int k = 0; k < 2; ++k) {
        const Vec3 onA = a0 + ends[k] * ua;
        const Real tt = std::clamp((onA - b0).dot(db) / (lb * lb), Real(0), Real(1));
        const Vec3 onB = b0 + tt * db;
        setPoint(count, onA, ends[k] / la, onB, tt, makeId(featureKey(Feature::Vertex, std::uint32_t(k)),
                                         featureKey(Feature::Edge, 0)));
        if (m.points[std::size_t(count)].separation <= spec) ++count;
      }
      if (count > 0) {
        m.pointCount = count;
        return true;
      }
    }
  }
  setPoint(0, pa, s, pb, t, makeId(featureKey(Feature::Edge, 0), featureKey(Feature::Edge, 0)));
  m.pointCount = 1;
  return true;
}

bool collideCapsulePolyhedron(const Collider& a, const Transform& poseA, const Collider& b,
                              const Transform& poseB, const ContactSettings& settings,
                              ContactManifold& m) {
  PolyStorage storage;
  const PolyView view = b.type() == ShapeType::Box
                            ? makePolyView(b.shape().get<Box>(), storage)
                            : makePolyView(b.shape().get<ConvexHull>());
  if (!collidePolyhedronCapsule(view, poseB, a.shape().get<Capsule>(), poseA, settings, m))
    return false;
  flipManifold(m);
  return true;
}

}  // namespace inertia::detail
