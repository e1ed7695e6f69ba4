// Convex hulls from point clouds, degenerate ones included (duplicates, coplanar, collinear,
// huge and tiny extents): either InvalidArgument or a hull that holds every input point, with
// unit face normals, finite mass properties, and finite support points and ray hits.
#include <vector>

#include "fuzz_input.h"
#include "inertia/collision/collider.h"
#include "inertia/collision/queries.h"
#include "inertia/core/error.h"
#include "inertia/geometry/geometry.h"

using namespace inertia;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::Input in(data, size);
  const Real scale = in.size();
  const unsigned n = 1 + in.pick(48);
  // A lattice of few distinct coordinates makes duplicates and coplanar sets likely.
  const bool lattice = in.byte() & 1;
  std::vector<Vec3> points;
  for (unsigned i = 0; i < n; ++i) {
    if (lattice)
      points.push_back(scale * Vec3{Real(in.pick(3)), Real(in.pick(3)), Real(in.pick(3))});
    else
      points.push_back(in.vec(scale));
  }
  std::optional<ConvexHull> hull;
  try {
    hull.emplace(points);
  } catch (const InvalidArgument&) {
    return 0;  // a flat or too small cloud, refused with a message
  }
  for (const Vec3& v : hull->vertices()) INERTIA_FUZZ_FINITE(v);
  Real extent = 0;
  for (const Vec3& p : points) extent = std::max(extent, p.cwiseAbs().maxCoeff());
  for (const HullFace& f : hull->faces()) {
    INERTIA_FUZZ_FINITE(f.normal);
    INERTIA_FUZZ_FINITE(f.offset);
    if (std::abs(f.normal.norm() - 1) > Real(1e-3)) std::abort();
    // Every input point lies inside each face's plane, up to Qhull's rounding.
    for (const Vec3& p : points)
      if (f.normal.dot(p) > f.offset + Real(1e-3) * extent + Real(1e-30)) std::abort();
  }
  const MassProperties m = massProperties(Shape(*hull), 1000);
  INERTIA_FUZZ_FINITE(m.mass);
  INERTIA_FUZZ_FINITE(m.centerOfMass);
  const Collider c{Shape(*hull)};
  const Transform pose = in.pose(scale);
  const Ray ray{in.vec(4 * scale), in.vec(), 8};
  if (const auto hit = castRay(c, pose, ray)) {
    INERTIA_FUZZ_FINITE(hit->fraction);
    INERTIA_FUZZ_FINITE(hit->normal);
  }
  const PointQuery q = queryPoint(c, pose, in.vec(2 * scale));
  INERTIA_FUZZ_FINITE(q.distance);
  return 0;
}
