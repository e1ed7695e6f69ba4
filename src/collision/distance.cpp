// Public distance queries on colliders: ConvexProxy + GJK/EPA (gjk.h).
#include "inertia/collision/distance.h"

#include "gjk.h"

namespace inertia {

ClosestPoints closestPoints(const Collider& a, const Transform& poseA, const Collider& b,
                            const Transform& poseB) {
  const auto pa = detail::ConvexProxy::fromCollider(a, poseA);
  const auto pb = detail::ConvexProxy::fromCollider(b, poseB);
  const detail::ConvexSeparation s = detail::separation(pa, pb);
  ClosestPoints out;
  out.overlapping = !(s.distance > 0);
  out.distance = out.overlapping ? Real(0) : s.distance;
  out.pointA = s.pointA;
  out.pointB = s.pointB;
  out.normal = s.normal;
  return out;
}

std::optional<Penetration> penetration(const Collider& a, const Transform& poseA, const Collider& b,
                                       const Transform& poseB) {
  const auto pa = detail::ConvexProxy::fromCollider(a, poseA);
  const auto pb = detail::ConvexProxy::fromCollider(b, poseB);
  const detail::ConvexSeparation s = detail::separation(pa, pb);
  if (!(s.distance < 0)) return std::nullopt;
  return Penetration{-s.distance, s.normal, s.pointA, s.pointB};
}

bool overlap(const Collider& a, const Transform& poseA, const Collider& b, const Transform& poseB) {
  const auto pa = detail::ConvexProxy::fromCollider(a, poseA);
  const auto pb = detail::ConvexProxy::fromCollider(b, poseB);
  const detail::GjkResult g = detail::gjk(pa, pb);
  return g.overlapping || g.distance <= pa.radius + pb.radius;
}

}  // namespace inertia
