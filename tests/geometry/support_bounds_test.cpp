// Support functions and bounds against dense samples of each shape's surface.
#include <gtest/gtest.h>

#include "geometry_test_util.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

ConvexHull randomHull(std::mt19937_64& rng) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 25; ++i) pts.push_back(randomVec(rng, -1, 1).cwiseProduct(Vec3(1, 2, 0.5)));
  return ConvexHull(pts);
}

// The support point must (1) beat every sample: d.s >= max d.x (minus Real rounding), and
// (2) be reached by the samples to within their spacing (the surface's maximum is within
// `spacing` of the samples' maximum, d.x being 1-Lipschitz), and (3) lie on the shape, which
// the caller checks by `onShape`.
template <class S, class OnShape>
void checkSupport(const S& shape, const SurfaceSamples& s, std::mt19937_64& rng, OnShape&& onShape,
                  double scale) {
  const double round = 16 * kEps * scale;
  for (int k = 0; k < 200; ++k) {
    const Vec3d d = randomUnit(rng);
    double best = -1e300;
    for (const Vec3d& x : s.points) best = std::max(best, d.dot(x));
    const Vec3 sup = support(shape, d.cast<Real>());
    const double h = d.dot(sup.cast<double>());
    EXPECT_GE(h, best - round);
    EXPECT_LE(h, best + s.spacing + round);
    EXPECT_TRUE(onShape(sup.cast<double>())) << sup.transpose();
    // The Shape dispatcher agrees.
    EXPECT_EQ(support(Shape(shape), d.cast<Real>()), sup);
  }
}

// World bounds contain every transformed sample and are touched on all six sides to within
// the sampling spacing.
void checkBounds(const Shape& shape, const SurfaceSamples& s, std::mt19937_64& rng, double scale) {
  for (int k = 0; k < 30; ++k) {
    const Transform xf{randomVec(rng, -5, 5), randomRotation(rng)};
    const Aabb b = worldBounds(shape, xf);
    // Rotating a sample in Real and the bound's own rounding: ~8 eps (|p| + scale).
    const double round = 8 * kEps * (5 * std::sqrt(3) + scale);
    Vec3d lo = Vec3d::Constant(1e300), hi = Vec3d::Constant(-1e300);
    for (const Vec3d& x : s.points) {
      const Vec3d w = xf.q.cast<double>() * x + xf.p.cast<double>();
      lo = lo.cwiseMin(w);
      hi = hi.cwiseMax(w);
    }
    for (int i = 0; i < 3; ++i) {
      EXPECT_LE(b.lower[i], lo[i] + round) << shapeTypeName(shape.type());
      EXPECT_GE(b.upper[i], hi[i] - round) << shapeTypeName(shape.type());
      EXPECT_GE(b.lower[i], lo[i] - s.spacing - round) << shapeTypeName(shape.type());
      EXPECT_LE(b.upper[i], hi[i] + s.spacing + round) << shapeTypeName(shape.type());
    }
  }
}

}  // namespace

TEST(Support, SphereMatchesSamples) {
  std::mt19937_64 rng(41);
  const Sphere s{Real(0.8)};
  checkSupport(
      s, samples(s), rng, [&](const Vec3d& x) { return std::abs(x.norm() - 0.8) <= 8 * kEps; }, 1);
}

TEST(Support, CapsuleMatchesSamples) {
  std::mt19937_64 rng(43);
  const Capsule c{Real(0.3), Real(0.9)};
  // On the surface: at distance r from the core segment.
  auto onShape = [&](const Vec3d& x) {
    const Vec3d core(0, std::clamp(x.y(), -0.9, 0.9), 0);
    return std::abs((x - core).norm() - 0.3) <= 8 * kEps;
  };
  checkSupport(c, samples(c), rng, onShape, 1.2);
}

TEST(Support, BoxMatchesSamples) {
  std::mt19937_64 rng(47);
  const Box b{Vec3(Real(0.2), 1, Real(0.6))};
  auto onShape = [&](const Vec3d& x) {  // a corner
    return (x.cwiseAbs() - b.halfExtents.cast<double>()).norm() == 0;
  };
  checkSupport(b, samples(b), rng, onShape, 1.2);
}

TEST(Support, CylinderMatchesSamples) {
  std::mt19937_64 rng(53);
  const Cylinder c{Real(0.7), Real(0.4)};
  auto onShape = [&](const Vec3d& x) {  // on a rim
    return std::abs(std::hypot(x.x(), x.z()) - 0.7) <= 8 * kEps &&
           std::abs(x.y()) == double(Real(0.4));
  };
  checkSupport(c, samples(c), rng, onShape, 1);
}

TEST(Support, HullMatchesSamples) {
  std::mt19937_64 rng(59);
  const ConvexHull hull = randomHull(rng);
  auto onShape = [&](const Vec3d& x) {  // a vertex
    for (const Vec3& v : hull.vertices())
      if (v.cast<double>() == x) return true;
    return false;
  };
  checkSupport(hull, samples(hull), rng, onShape, 2.5);
}

TEST(Support, DegenerateDirectionsGivePointsOfTheShape) {
  EXPECT_TRUE(support(Sphere{2}, Vec3::Zero()).allFinite());
  EXPECT_NEAR(support(Sphere{2}, Vec3::Zero()).norm(), 2, 0);
  EXPECT_EQ(support(Cylinder{1, 2}, Vec3(0, 1, 0)), Vec3(0, 2, 0));
  EXPECT_EQ(support(Capsule{1, 2}, Vec3(0, -1, 0)), Vec3(0, -3, 0));
  // Tiny directions still normalise without overflow or NaN.
  const Vec3 tiny = Vec3::Constant(std::numeric_limits<Real>::denorm_min());
  EXPECT_TRUE(support(Sphere{1}, tiny).allFinite());
  EXPECT_TRUE(support(Cylinder{1, 1}, tiny).allFinite());
}

TEST(Support, NonConvexShapesHaveNone) {
  EXPECT_THROW(support(Shape(Plane{}), Vec3(1, 0, 0)), InvalidArgument);
  EXPECT_THROW(support(Shape(Compound({{Sphere{1}, {}}})), Vec3(1, 0, 0)), InvalidArgument);
}

TEST(Bounds, WorldBoundsAreConservativeAndTight) {
  std::mt19937_64 rng(61);
  const Sphere sphere{Real(0.8)};
  const Capsule capsule{Real(0.3), Real(0.9)};
  const Box box{Vec3(Real(0.2), 1, Real(0.6))};
  const Cylinder cylinder{Real(0.7), Real(0.4)};
  const ConvexHull hull = randomHull(rng);
  checkBounds(sphere, samples(sphere), rng, 1);
  checkBounds(capsule, samples(capsule), rng, 1.2);
  checkBounds(box, samples(box), rng, 1.2);
  checkBounds(cylinder, samples(cylinder), rng, 1);
  checkBounds(hull, samples(hull), rng, 2.5);
  // A compound of them: the union of the children's samples, moved by each child's pose.
  const Transform a{Vec3(1, 0, 0), randomRotation(rng)},
      b{Vec3(0, -1, Real(0.5)), randomRotation(rng)};
  const Compound compound({{capsule, a}, {cylinder, b}});
  SurfaceSamples s;
  for (const auto& [child, pose] : {std::pair{samples(capsule), a}, {samples(cylinder), b}}) {
    for (const Vec3d& x : child.points)
      s.points.push_back(pose.q.cast<double>() * x + pose.p.cast<double>());
    s.spacing = std::max(s.spacing, child.spacing);
  }
  checkBounds(compound, s, rng, 2.5);
}

TEST(Bounds, MeshAndHeightFieldBoundsAreConservative) {
  std::mt19937_64 rng(67);
  std::vector<Vec3> v;
  for (int i = 0; i < 20; ++i) v.push_back(randomVec(rng, -1, 1));
  std::vector<Triangle> t;
  for (std::uint32_t i = 0; i + 2 < 20; ++i) t.push_back({i, i + 1, i + 2});
  const Shape mesh = TriangleMesh(v, t);
  const Shape field = HeightField({{0, 1, -1}, {2, 0, 1}, {-2, 0, 3}}, Real(0.5));
  for (int k = 0; k < 20; ++k) {
    const Transform xf{randomVec(rng, -5, 5), randomRotation(rng)};
    const Aabb mb = worldBounds(mesh, xf);
    for (const Vec3& x : v) EXPECT_TRUE(mb.inflated(Real(64 * kEps * 8)).contains(xf.apply(x)));
    const Aabb fb = worldBounds(field, xf);
    const auto& hf = field.get<HeightField>();
    for (std::size_t i = 0; i < hf.rows(); ++i)
      for (std::size_t j = 0; j < hf.cols(); ++j)
        EXPECT_TRUE(fb.inflated(Real(64 * kEps * 8)).contains(xf.apply(hf.point(i, j))));
  }
}

TEST(Bounds, PlaneBoundsAreInfiniteExceptAlongAnAlignedNormal) {
  const Real inf = std::numeric_limits<Real>::infinity();
  const Aabb up =
      worldBounds(Shape(Plane{Vec3(0, 1, 0), 2}), Transform{Vec3(0, 1, 0), Quat::Identity()});
  EXPECT_EQ(up.upper, Vec3(inf, 3, inf));
  EXPECT_EQ(up.lower, Vec3::Constant(-inf));
  const Aabb down = localBounds(Shape(Plane{Vec3(-1, 0, 0), 2}));  // -x <= 2: x >= -2
  EXPECT_EQ(down.lower, Vec3(-2, -inf, -inf));
  const Aabb tilted = localBounds(Shape(Plane{Vec3(1, 1, 0), 0}));
  EXPECT_EQ(tilted.upper, Vec3::Constant(inf));
  EXPECT_TRUE(tilted.overlaps(Aabb{Vec3(5, 5, 5), Vec3(6, 6, 6)}));
  EXPECT_TRUE(up.overlaps(Aabb{Vec3(0, 2, 0), Vec3(1, 3, 1)}));
  EXPECT_FALSE(up.overlaps(Aabb{Vec3(0, Real(3.5), 0), Vec3(1, 4, 1)}));
}

TEST(Aabb, Operations) {
  const Aabb a{Vec3(0, 0, 0), Vec3(1, 2, 3)}, b{Vec3(1, 1, 1), Vec3(2, 2, 2)};
  EXPECT_EQ(a.surfaceArea(), 2 * (2 + 6 + 3));
  EXPECT_EQ(a.volume(), 6);
  EXPECT_TRUE(a.overlaps(b));  // touching at x = 1 counts
  EXPECT_FALSE(a.overlaps(Aabb{Vec3(Real(1.5), 0, 0), Vec3(2, 1, 1)}));
  const Aabb m = a.merged(b);
  EXPECT_EQ(m.lower, Vec3(0, 0, 0));
  EXPECT_EQ(m.upper, Vec3(2, 2, 3));
  EXPECT_TRUE(m.contains(a) && m.contains(b));
  EXPECT_FALSE(a.contains(b));
  EXPECT_TRUE(a.contains(Vec3(1, 2, 3)));
  EXPECT_FALSE(a.contains(Vec3(1, 2, Real(3.01))));
  Aabb e = Aabb::empty();
  EXPECT_FALSE(e.isValid());
  EXPECT_FALSE(e.overlaps(a));
  e.merge(a);
  EXPECT_EQ(e.lower, a.lower);
  EXPECT_EQ(e.upper, a.upper);
  EXPECT_EQ(a.inflated(1).lower, Vec3(-1, -1, -1));
  // transformAabb: a quarter turn about z swaps the x and y extents exactly (up to rounding).
  const Transform quarter{Vec3(10, 0, 0),
                          Quat(Eigen::AngleAxis<Real>(Real(kPi / 2), Vec3::UnitZ()))};
  const Aabb t = transformAabb(a, quarter);
  EXPECT_LE((t.halfExtents() - Vec3(1, Real(0.5), Real(1.5))).norm(), 8 * kEps);
  EXPECT_LE((t.center() - Vec3(9, Real(0.5), Real(1.5))).norm(), 64 * kEps);
}
