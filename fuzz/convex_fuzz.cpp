// The narrow phase and the convex queries on two random shapes (sphere, capsule, box, cylinder,
// hull) at random poses: zero-thickness and huge or tiny sizes, far and coincident poses.
// Shapes the API refuses throw InvalidArgument; everything else must give finite results with
// unit normals and non-negative depths and distances.
#include <optional>
#include <vector>

#include "fuzz_input.h"
#include "inertia/collision/collider.h"
#include "inertia/collision/contact.h"
#include "inertia/collision/distance.h"
#include "inertia/collision/queries.h"
#include "inertia/collision/time_of_impact.h"
#include "inertia/core/error.h"
#include "inertia/geometry/geometry.h"
#include "random_shape.h"

using namespace inertia;

namespace {

Shape makeShape(fuzz::Input& in, Real scale) {
  // A size of exactly 0 (zero thickness) is allowed through to test the API's refusal.
  const auto len = [&] { return in.pick(16) == 0 ? Real(0) : scale * in.size(); };
  return fuzz::randomShape(
      in, len, [&] { return 4 + in.pick(12); }, scale);
}

void checkUnit(const Vec3& n) {
  INERTIA_FUZZ_FINITE(n);
  if (std::abs(n.norm() - 1) > Real(1e-3)) {
    std::fprintf(stderr, "normal of length %g\n", double(n.norm()));
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::Input in(data, size);
  const Real scale = Real(std::pow(10.0, int(in.pick(7)) - 3));  // 1e-3 .. 1e3 m
  std::optional<Collider> a, b;
  try {
    a.emplace(makeShape(in, scale));
    b.emplace(makeShape(in, scale * (in.byte() & 1 ? 1 : in.size())));
  } catch (const InvalidArgument&) {
    return 0;
  }
  const Transform poseA = in.pose(scale);
  const Transform poseB = in.pick(4) == 0 ? poseA : in.pose(scale);  // coincident sometimes

  const ClosestPoints c = closestPoints(*a, poseA, *b, poseB);
  INERTIA_FUZZ_FINITE(c.distance);
  INERTIA_FUZZ_FINITE(c.pointA);
  INERTIA_FUZZ_FINITE(c.pointB);
  checkUnit(c.normal);
  if (c.distance < 0) std::abort();

  if (const auto p = penetration(*a, poseA, *b, poseB)) {
    INERTIA_FUZZ_FINITE(p->depth);
    INERTIA_FUZZ_FINITE(p->pointA);
    INERTIA_FUZZ_FINITE(p->pointB);
    checkUnit(p->normal);
    if (!(p->depth > 0)) std::abort();
  }
  (void)overlap(*a, poseA, *b, poseB);

  ContactManifold m;
  if (collideConvex(*a, poseA, *b, poseB, ContactSettings{}, m)) {
    checkUnit(m.normal);
    for (int i = 0; i < m.pointCount; ++i) {
      INERTIA_FUZZ_FINITE(m.points[i].pointA);
      INERTIA_FUZZ_FINITE(m.points[i].pointB);
      INERTIA_FUZZ_FINITE(m.points[i].separation);
    }
  }

  const Ray ray{in.vec(4 * scale), in.vec(scale), Real(in.pick(3))};
  if (const auto hit = castRay(*a, poseA, ray)) {
    INERTIA_FUZZ_FINITE(hit->fraction);
    INERTIA_FUZZ_FINITE(hit->point);
    checkUnit(hit->normal);
  }
  const PointQuery q = queryPoint(*b, poseB, in.vec(2 * scale));
  INERTIA_FUZZ_FINITE(q.distance);
  INERTIA_FUZZ_FINITE(q.point);

  const Vec3 translation = in.vec(4 * scale);
  if (const auto hit = castShape(*a, poseA, translation, *b, poseB)) {
    INERTIA_FUZZ_FINITE(hit->fraction);
    if (hit->fraction < 0 || hit->fraction > 1) std::abort();
    INERTIA_FUZZ_FINITE(hit->point);
    checkUnit(hit->normal);
  }
  return 0;
}
