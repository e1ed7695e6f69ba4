// Shape casts on colliders, and the time of impact of rotating and translating convex shapes
// by conservative advancement (Mirtich 1996).
#include "inertia/collision/time_of_impact.h"

#include <algorithm>
#include <cmath>

#include "gjk.h"
#include "inertia/core/math.h"

namespace inertia {

std::optional<ShapeCastHit> castShape(const Collider& a, const Transform& poseA,
                                      const Vec3& translationA, const Collider& b,
                                      const Transform& poseB, const ShapeCastSettings& settings) {
  const auto pa = detail::ConvexProxy::fromCollider(a, poseA);
  const auto pb = detail::ConvexProxy::fromCollider(b, poseB);
  const auto cast = detail::shapeCast(pa, translationA, pb, settings.tolerance);
  if (!cast) return std::nullopt;
  return ShapeCastHit{cast->fraction, cast->pointB, -cast->normal};
}

Transform Sweep::at(Real t) const {
  return {(1 - t) * start.p + t * end.p,
          (quatFromRotationVector(t * angularVelocity()) * start.q).normalized()};
}

Vec3 Sweep::angularVelocity() const { return rotationVector(end.q * start.q.conjugate()); }

namespace {

// The farthest point of a convex shape from its frame's origin (m): the lever arm of Mirtich's
// bound on the speed of a rotating shape's points.
Real farthestPoint(const Collider& c) {
  const Shape& s = c.shape();
  switch (s.type()) {
    case ShapeType::Sphere:
      return s.get<Sphere>().radius;
    case ShapeType::Capsule:
      return s.get<Capsule>().halfHeight + s.get<Capsule>().radius;
    case ShapeType::Box:
      return s.get<Box>().halfExtents.norm();
    case ShapeType::Cylinder:
      return std::hypot(s.get<Cylinder>().radius, s.get<Cylinder>().halfHeight);
    case ShapeType::Hull: {
      Real r = 0;
      for (const Vec3& v : s.get<ConvexHull>().vertices()) r = std::max(r, v.norm());
      return r;
    }
    default:
      return 0;  // fromCollider rejects the others first
  }
}

ToiResult fill(ToiStatus status, Real t, const detail::ConvexSeparation& s, int iterations) {
  return {status, t, s.distance, s.normal, s.pointA, s.pointB, iterations};
}

}  // namespace

ToiResult timeOfImpact(const Collider& a, const Sweep& sweepA, const Collider& b,
                       const Sweep& sweepB, const ToiSettings& settings) {
  // Validate the shapes before the loop (fromCollider throws for non-convex ones).
  detail::ConvexProxy pa = detail::ConvexProxy::fromCollider(a, sweepA.start);
  detail::ConvexProxy pb = detail::ConvexProxy::fromCollider(b, sweepB.start);
  const Vec3 vA = sweepA.linearVelocity(), vB = sweepB.linearVelocity();
  const Real spin = sweepA.angularVelocity().norm() * farthestPoint(a) +
                    sweepB.angularVelocity().norm() * farthestPoint(b);
  const Real target = std::max(settings.targetSeparation, Real(0));
  const Real tolerance = settings.tolerance > 0 ? settings.tolerance : Real(1e-3);
  // Aim a quarter of the tolerance above the target, so rounding in the distance cannot push
  // a step past it; accept anything up to target + tolerance.
  const Real aim = target + Real(0.25) * tolerance;

  Real t = 0;
  Vec3 guess = Vec3::Zero();
  detail::ConvexSeparation s;
  for (int iter = 1; iter <= settings.maxIterations; ++iter) {
    if (iter > 1) {
      pa = detail::ConvexProxy::fromCollider(a, sweepA.at(t));
      pb = detail::ConvexProxy::fromCollider(b, sweepB.at(t));
    }
    s = detail::separation(pa, pb, guess);
    guess = s.normal;
    if (iter == 1 && s.distance < 0) return fill(ToiStatus::Overlapping, 0, s, iter);
    if (s.distance <= target + tolerance) return fill(ToiStatus::Hit, t, s, iter);
    // Mirtich's bound on how fast the gap along the current normal n can close: points of A move
    // along n at most at vA.n + |wA| rA, points of B at least at vB.n - |wB| rB. The signed
    // projection (not |(vA - vB).n|) is still a bound, and lets receding pairs stop at once.
    const Real mu = (vA - vB).dot(s.normal) + spin;
    if (!(mu > 0)) return fill(ToiStatus::Separated, 1, s, iter);
    t += (s.distance - aim) / mu;
    if (!(t < 1)) return fill(ToiStatus::Separated, 1, s, iter);
  }
  return fill(ToiStatus::Failed, t, s, settings.maxIterations);
}

}  // namespace inertia
