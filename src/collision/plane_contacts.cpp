// Plane (A) against the convex shapes: the points of the shape's supporting feature that lie
// below the plane + speculativeDistance, reduced to four.
#include <cmath>

#include "contact_pairs.h"
#include "polyhedron.h"

namespace inertia::detail {

namespace {

// The plane in the world and the candidates found so far (world frame); compacted to the four
// best whenever the fixed buffer fills (hulls with many vertices on the plane).
struct PlaneContacts {
  Vec3 n = Vec3::UnitY();
  Real offset = 0;
  Real spec = 0;
  std::array<ContactCandidate, kMaxClipVertices> pts{};
  int count = 0;

  PlaneContacts(const Collider& plane, const Transform& pose, const ContactSettings& s) {
    const Plane& p = plane.shape().get<Plane>();
    n = pose.rotate(p.normal);
    offset = p.offset + n.dot(pose.p);
    spec = s.speculativeDistance;
  }
  // A point of B's surface (world), with B's feature key.
  void add(const Vec3& p, std::uint32_t featureB) {
    const Real sep = n.dot(p) - offset;
    if (sep > spec) return;
    if (count == kMaxClipVertices) {
      std::array<int, 4> keep{};
      const int kept = selectContacts(pts.data(), count, n, keep);
      std::array<ContactCandidate, 4> best{};
      for (int k = 0; k < kept; ++k) best[std::size_t(k)] = pts[std::size_t(keep[std::size_t(k)])];
      for (int k = 0; k < kept; ++k) pts[std::size_t(k)] = best[std::size_t(k)];
      count = kept;
    }
    pts[std::size_t(count++)] = {p - sep * n, p, sep, makeId(featureKey(Feature::Face, 0), featureB)};
  }
  bool finish(ContactManifold& m) const {
    return count > 0 && reduceManifold(pts.data(), count, n, Transform::identity(), m);
  }
};

}  // namespace

bool collidePlaneSphere(const Collider& a, const Transform& poseA, const Collider& b,
                        const Transform& poseB, const ContactSettings& s, ContactManifold& m) {
  PlaneContacts pc(a, poseA, s);
  pc.add(poseB.p - b.shape().get<Sphere>().radius * pc.n, featureKey(Feature::Face, 0));
  return pc.finish(m);
}

bool collidePlaneCapsule(const Collider& a, const Transform& poseA, const Collider& b,
                         const Transform& poseB, const ContactSettings& s, ContactManifold& m) {
  PlaneContacts pc(a, poseA, s);
  const Capsule& c = b.shape().get<Capsule>();
  for (int k = 0; k < 2; ++k) {
    const Vec3 end = poseB.apply(Vec3(0, k ? c.halfHeight : -c.halfHeight, 0));
    pc.add(end - c.radius * pc.n, featureKey(Feature::Vertex, std::uint32_t(k)));
  }
  return pc.finish(m);
}

bool collidePlaneBox(const Collider& a, const Transform& poseA, const Collider& b,
                     const Transform& poseB, const ContactSettings& s, ContactManifold& m) {
  PlaneContacts pc(a, poseA, s);
  const Vec3& h = b.shape().get<Box>().halfExtents;
  for (std::uint32_t k = 0; k < 8; ++k)
    pc.add(poseB.apply(Vec3((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                            (k & 4) ? h.z() : -h.z())),
           featureKey(Feature::Vertex, k));
  return pc.finish(m);
}

bool collidePlaneCylinder(const Collider& a, const Transform& poseA, const Collider& b,
                          const Transform& poseB, const ContactSettings& s, ContactManifold& m) {
  PlaneContacts pc(a, poseA, s);
  std::array<Vec3, kCylinderRimPoints> pts;
  std::array<std::uint32_t, kCylinderRimPoints> features{};
  const int count = cylinderSupportFeature(b.shape().get<Cylinder>(),
                                           poseB.q.conjugate() * (-pc.n), pts.data(),
                                           features.data());
  for (int k = 0; k < count; ++k)
    pc.add(poseB.apply(pts[std::size_t(k)]), features[std::size_t(k)]);
  return pc.finish(m);
}

bool collidePlaneHull(const Collider& a, const Transform& poseA, const Collider& b,
                      const Transform& poseB, const ContactSettings& s, ContactManifold& m) {
  PlaneContacts pc(a, poseA, s);
  const auto& v = b.shape().get<ConvexHull>().vertices();
  for (std::size_t k = 0; k < v.size(); ++k)
    pc.add(poseB.apply(v[k]), featureKey(Feature::Vertex, std::uint32_t(k)));
  return pc.finish(m);
}

}  // namespace inertia::detail
