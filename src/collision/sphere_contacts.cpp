// Sphere against any convex shape: the closest point of the other shape to the sphere's centre
// (the point query), one contact point. Exact for every convex shape, inside as well as out.
// Two spheres directly from their centres, without going into either's frame.
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

bool collideSpheres(const Collider& a, const Transform& poseA, const Collider& b,
                    const Transform& poseB, const ContactSettings& settings, ContactManifold& m) {
  const Real ra = a.shape().get<Sphere>().radius, rb = b.shape().get<Sphere>().radius;
  const Vec3 d = poseB.p - poseA.p;
  const Real distance = d.norm();
  const Real sep = distance - ra - rb;
  if (sep > settings.speculativeDistance) return false;
  // From A to B. Coincident centres: B's local -y, as the point query makes it.
  const Vec3 n = distance > 0 ? Vec3(d / distance) : Vec3(-poseB.rotate(Vec3::UnitY()));
  m.normal = n;
  m.pointCount = 1;
  ContactPoint& p = m.points[0];
  p.pointA = poseA.p + ra * n;
  p.pointB = poseB.p - rb * n;
  p.separation = sep;
  p.id = 0;
  return true;
}

}  // namespace inertia::detail
