// Sphere against any convex shape: the closest point of the other shape to the sphere's centre
// (the point query), one contact point. Exact for every convex shape, inside as well as out.
#include "contact_pairs.h"
#include "local_queries.h"

namespace inertia::detail {

bool collideSphereConvex(const Collider& a, const Transform& poseA, const Collider& b,
                         const Transform& poseB, const ContactSettings& settings,
                         ContactManifold& m) {
  const Real r = a.shape().get<Sphere>().radius;
  const Vec3 centre = poseB.applyInverse(poseA.p);  // in B's frame
  const PointQuery q = queryPointLocal(b, centre);
  const Real sep = q.distance - r;
  if (sep > settings.speculativeDistance) return false;
  // q.normal leaves B at the closest point, towards the centre: from B to A.
  const Vec3 n = -poseB.rotate(q.normal);
  m.normal = n;
  m.pointCount = 1;
  ContactPoint& p = m.points[0];
  p.pointB = poseB.apply(q.point);
  p.pointA = poseA.p + r * n;
  p.separation = sep;
  p.id = 0;
  return true;
}

}  // namespace inertia::detail
