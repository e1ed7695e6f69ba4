// Penetration depth (GJK + EPA) against oracles: closed forms for spheres, axis-aligned boxes and
// a sphere in a box, the minimum over the separating-axis candidates for random hull pairs, and
// for every convex pair the defining property: moving B by depth * normal just separates them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "collision/gjk.h"
#include "collision_test_util.h"
#include "inertia/collision/distance.h"

using namespace inertia;
using namespace inertia::test;

namespace {

// EPA ends on an exact face of a polytope difference, so its depth carries only rounding: a few
// dozen roundings of coordinates of size `scale`. Curved cores (cylinders) stop within a
// relative 1e-5 (float) / 1e-7 (double) of the depth (epa.cpp), covered by kCurvedRel.
double depthTol(double scale) { return 64 * kEps * scale; }
constexpr double kCurvedRel = sizeof(Real) == 4 ? 2e-5 : 2e-7;

std::vector<Vec3d> worldVertices(const ConvexHull& h, const Transform& pose) {
  std::vector<Vec3d> v;
  for (const Vec3& x : h.vertices()) v.push_back(rotateD(pose, toD(x)) + toD(pose.p));
  return v;
}

// Overlap of the projections along unit u when B is to be pushed along +u:
// max_A u.x - min_B u.y (the translation of B along u that separates them).
double overlapAlong(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b, const Vec3d& u) {
  double hiA = -std::numeric_limits<double>::infinity(), loB = -hiA;
  for (const Vec3d& x : a) hiA = std::max(hiA, u.dot(x));
  for (const Vec3d& y : b) loB = std::min(loB, u.dot(y));
  return hiA - loB;
}

// The penetration depth of two convex polytopes: the least overlap over the separating-axis
// candidates (face normals of either, crosses of edge pairs), both signs. The Minkowski
// difference's faces have exactly these normals, and the depth is its nearest face.
double satDepth(const ConvexHull& ha, const Transform& pa, const ConvexHull& hb,
                const Transform& pb, Vec3d* axisOut = nullptr) {
  const auto va = worldVertices(ha, pa), vb = worldVertices(hb, pb);
  std::vector<Vec3d> axes;
  for (const HullFace& f : ha.faces()) axes.push_back(rotateD(pa, toD(f.normal)));
  for (const HullFace& f : hb.faces()) axes.push_back(rotateD(pb, toD(f.normal)));
  for (const HullEdge& ea : ha.edges())
    for (const HullEdge& eb : hb.edges()) {
      const Vec3d da = rotateD(pa, toD(ha.vertices()[ea.v1] - ha.vertices()[ea.v0]));
      const Vec3d db = rotateD(pb, toD(hb.vertices()[eb.v1] - hb.vertices()[eb.v0]));
      const Vec3d c = da.cross(db);
      if (c.norm() > 1e-9 * da.norm() * db.norm()) axes.push_back(c.normalized());
    }
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3d& u : axes)
    for (const Vec3d& s : {u, Vec3d(-u)}) {
      const double o = overlapAlong(va, vb, s);
      if (o < best) {
        best = o;
        if (axisOut) *axisOut = s;
      }
    }
  return best;
}

// Moving B by (depth +- margin) * normal must separate / keep overlapping.
void expectMinimalTranslation(const Collider& a, const Transform& pa, const Collider& b,
                              const Transform& pb, const Penetration& p, double margin) {
  Transform out = pb, in = pb;
  out.p += Real(p.depth + margin) * p.normal;
  in.p += Real(std::max(p.depth - margin, 0.0)) * p.normal;
  EXPECT_FALSE(closestPoints(a, pa, b, out).overlapping) << "depth " << p.depth;
  if (p.depth > 2 * margin) {
    EXPECT_TRUE(overlap(a, pa, b, in)) << "depth " << p.depth;
  }
}

}  // namespace

TEST(Epa, OverlappingSpheres) {
  std::mt19937_64 rng(11);
  for (int k = 0; k < 2000; ++k) {
    const Sphere sa{Real(uniform(rng, 0.2, 1))}, sb{Real(uniform(rng, 0.2, 1))};
    const Transform pa = randomPose(rng, 1), pb = randomPose(rng, 1);
    const Vec3d d = toD(pb.p) - toD(pa.p);
    const double exact = sa.radius + sb.radius - d.norm();
    if (exact < 1e-3 || d.norm() < 1e-3) continue;
    const auto p = penetration(Collider(sa), pa, Collider(sb), pb);
    ASSERT_TRUE(p.has_value());
    ASSERT_NEAR(p->depth, exact, depthTol(4));
    ASSERT_LE((toD(p->normal) - d.normalized()).norm(), depthTol(4) / d.norm() + 1e-6);
    ASSERT_LE((toD(p->pointA) - (toD(pa.p) + sa.radius * d.normalized())).norm(), depthTol(4));
    ASSERT_LE((toD(p->pointA) - toD(p->pointB) - exact * toD(p->normal)).norm(), 2 * depthTol(4));
  }
}

TEST(Epa, ConcentricSpheresHaveFiniteNormal) {
  const auto p = penetration(Collider(Sphere{1}), {Vec3(1, 2, 3)}, Collider(Sphere{Real(0.5)}),
                             {Vec3(1, 2, 3)});
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->depth, 1.5, depthTol(4));
  EXPECT_NEAR(p->normal.norm(), 1, 1e3 * kEps);
}

TEST(Epa, AxisAlignedBoxesMinimumOverlapAxis) {
  std::mt19937_64 rng(12);
  int checked = 0, maxIter = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 ha = randomVec(rng, 0.2, 1), hb = randomVec(rng, 0.2, 1);
    const Vec3 ca = randomVec(rng, -1, 1), cb = randomVec(rng, -1, 1);
    const Vec3d dc = toD(cb) - toD(ca);
    const Vec3d o = toD(ha) + toD(hb) - dc.cwiseAbs();
    if (o.minCoeff() <= 1e-3) continue;
    std::array<double, 3> sorted{o.x(), o.y(), o.z()};
    std::sort(sorted.begin(), sorted.end());
    if (sorted[1] - sorted[0] < 1e-3) continue;  // the axis must be unique
    int axis;
    const double exact = o.minCoeff(&axis);
    Vec3d n = Vec3d::Zero();
    n[axis] = dc[axis] >= 0 ? 1 : -1;
    const Collider a(Box{ha}), b(Box{hb});
    const Transform pa{ca, Quat::Identity()}, pb{cb, Quat::Identity()};
    const auto p = penetration(a, pa, b, pb);
    ASSERT_TRUE(p.has_value());
    ASSERT_NEAR(p->depth, exact, depthTol(4)) << k;
    ASSERT_LE((toD(p->normal) - n).norm(), 1e3 * kEps) << k;
    expectMinimalTranslation(a, pa, b, pb, *p, 1e3 * kEps * 4);
    const auto x = detail::ConvexProxy::fromCollider(a, pa),
               y = detail::ConvexProxy::fromCollider(b, pb);
    maxIter = std::max(maxIter, detail::separation(x, y).epaIterations);
    ++checked;
  }
  EXPECT_GT(checked, 500);
  std::printf("axis-aligned boxes: %d cases, max EPA iterations %d\n", checked, maxIter);
}

TEST(Epa, SphereInsideBox) {
  std::mt19937_64 rng(13);
  int inside = 0;
  for (int k = 0; k < 3000; ++k) {
    const Box box{randomVec(rng, 0.3, 1.2)};
    const Sphere sphere{Real(uniform(rng, 0.05, 0.6))};
    const Transform pb = randomPose(rng, 1),
                    ps{pb.apply(randomVec(rng, -1.5, 1.5)), Quat::Identity()};
    const Sdf s = sdf(box, toLocal(pb, ps.p));
    const double exact = sphere.radius - s.distance;
    if (exact < 1e-3) continue;
    if (s.distance < 0) {
      // The nearest face must be unique for a unique normal.
      const Vec3d gaps = toD(box.halfExtents) - toLocal(pb, ps.p).cwiseAbs();
      std::array<double, 3> g{gaps.x(), gaps.y(), gaps.z()};
      std::sort(g.begin(), g.end());
      if (g[1] - g[0] < 1e-3) continue;
      ++inside;
    }
    const Collider cs(sphere), cb(box);
    const auto p = penetration(cs, ps, cb, pb);
    ASSERT_TRUE(p.has_value());
    ASSERT_NEAR(p->depth, exact, depthTol(4)) << k;
    // Moving the box (B) along the normal pushes the sphere out through the nearest face.
    const Vec3d n = -rotateD(pb, s.gradient);
    ASSERT_LE((toD(p->normal) - n).norm(), 1e-3) << k;
    ASSERT_LE((toD(p->pointA) - toD(p->pointB) - p->depth * toD(p->normal)).norm(),
              2 * depthTol(4));
  }
  EXPECT_GT(inside, 300);
}

// A case clang's draw order gave SphereInsideBox (k = 1819, before tests/draws.h), bit for bit:
// the centre lies 11.5 mm outside the box's +z face and 0.74 mm inside the plane of its -y
// face. GJK's normal looked inaccurate, and the fallback (EPA on the box moved into the sphere's
// centre by a thousandth of the size, 2.2 mm) found the -y face shallower: a normal a right angle
// off with the right depth. The normal must be the distance field's gradient.
TEST(Epa, SphereCentreJustOutsideOneFaceKeepsThatFacesNormal) {
  const Box box{Vec3(Real(0x1.0a796cp+0), Real(0x1.759eeap-2), Real(0x1.1d4f22p-1))};
  const Sphere sphere{Real(0x1.ef50fp-2)};
  // The rotation as drawn (its depth is then exact to double's precision in double).
  const Transform pb{Vec3(Real(0x1.48305cp-1), Real(-0x1.f26462p-2), Real(0x1.a95e5p-1)),
                     unitAsDrawn(Quat(Real(0x1.1c5c48p-3), Real(-0x1.c0daaap-1),
                                      Real(-0x1.447102p-2), Real(0x1.565f1cp-2)))};
  const Transform ps{Vec3(Real(0x1.c72f4p-2), Real(0x1.ab345cp-3), Real(0x1.13b638p-2)),
                     Quat::Identity()};
  const Sdf s = sdf(box, toLocal(pb, ps.p));
  ASSERT_NEAR(s.distance, 0.0115, 1e-4);  // outside, through the +z face
  const auto p = penetration(Collider(sphere), ps, Collider(box), pb);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->depth, sphere.radius - s.distance, depthTol(4));
  const Vec3d n = -rotateD(pb, s.gradient);
  EXPECT_LE((toD(p->normal) - n).norm(), 1e-3)
      << "normal (box frame) " << (pb.q.conjugate() * p->normal).transpose();
}

TEST(Epa, RandomHullsMatchSeparatingAxisMinimum) {
  std::mt19937_64 rng(14);
  double worst = 0;
  int maxIter = 0, cases = 0;
  for (int k = 0; k < 400; ++k) {
    const ConvexHull ha = randomHull(rng, 6 + k % 20, 1), hb = randomHull(rng, 6 + (k * 3) % 17, 1);
    const Transform pa = randomPose(rng, 0.3), pb = randomPose(rng, 0.6);
    const Collider a{Shape(ha)}, b{Shape(hb)};
    Vec3d axis;
    const double exact = satDepth(ha, pa, hb, pb, &axis);
    if (exact < 1e-3) continue;  // apart or grazing
    ++cases;
    const auto p = penetration(a, pa, b, pb);
    ASSERT_TRUE(p.has_value()) << k;
    ASSERT_NEAR(p->depth, exact, depthTol(4) + 1e-6 * exact) << k;
    // EPA's normal is an axis achieving the depth.
    const double along = overlapAlong(worldVertices(ha, pa), worldVertices(hb, pb), toD(p->normal));
    ASSERT_NEAR(along, p->depth, depthTol(4)) << k;
    worst = std::max(worst, std::abs(p->depth - exact) / exact);
    const auto x = detail::ConvexProxy::fromCollider(a, pa),
               y = detail::ConvexProxy::fromCollider(b, pb);
    maxIter = std::max(maxIter, detail::separation(x, y).epaIterations);
  }
  EXPECT_GT(cases, 200);
  std::printf("hull-hull EPA: %d cases, max relative error %.3g, max EPA iterations %d\n", cases,
              worst, maxIter);
}

TEST(Epa, CylinderOnBoxAnalyticDepth) {
  // An upright cylinder sunk into a wide box: the depth is the vertical overlap (the sides are
  // far away), normal +y from the box (A) up to the cylinder (B).
  std::mt19937_64 rng(15);
  for (int k = 0; k < 300; ++k) {
    const Cylinder cyl{Real(uniform(rng, 0.2, 0.8)), Real(uniform(rng, 0.2, 0.8))};
    const Box box{Vec3(3, Real(uniform(rng, 0.5, 1)), 3)};
    const double sink = uniform(rng, 0.01, 0.15);
    const Vec3 c(Real(uniform(rng, -1, 1)), Real(box.halfExtents.y() + cyl.halfHeight - sink),
                 Real(uniform(rng, -1, 1)));
    const Real spin = Real(uniform(rng, 0, 6));
    const Transform pc{c, Quat(Eigen::AngleAxis<Real>(spin, Vec3::UnitY()))};
    const double exact = box.halfExtents.y() + cyl.halfHeight - double(c.y());
    const auto p = penetration(Collider(box), {}, Collider(cyl), pc);
    ASSERT_TRUE(p.has_value());
    ASSERT_NEAR(p->depth, exact, depthTol(4) + kCurvedRel * exact) << k;
    ASSERT_LE((toD(p->normal) - Vec3d::UnitY()).norm(), 1e-3) << k;
  }
}

TEST(Epa, EveryConvexPairIsSeparatedByItsMinimalTranslation) {
  // The defining property of (depth, normal) for any pair, curved ones included: B moved by
  // slightly more than depth along normal is apart, by slightly less still overlaps. And the
  // normal achieves (nearly) the least overlap of many sampled directions.
  std::mt19937_64 rng(16);
  const std::vector<Shape> shapes = {Sphere{Real(0.6)}, Capsule{Real(0.3), Real(0.7)},
                                     Box{Vec3(0.5f, 0.3f, 0.8f)}, Cylinder{Real(0.5), Real(0.6)},
                                     Shape(randomHull(rng, 20, 0.8))};
  std::vector<Vec3d> dirs;
  for (int i = 0; i < 4000; ++i) dirs.push_back(toD(randomVec(rng, -1, 1)).normalized());
  int checked = 0;
  int unconverged = 0;
  for (int k = 0; k < 1500; ++k) {
    const Collider a(shapes[k % 5]), b(shapes[(k / 5) % 5]);
    const Transform pa = randomPose(rng, 0.4), pb = randomPose(rng, 0.4);
    const auto p = penetration(a, pa, b, pb);
    if (!p || p->depth < 1e-3) continue;
    ++checked;
    ASSERT_TRUE(toD(p->pointA).allFinite() && toD(p->pointB).allFinite());
    ASSERT_NEAR(p->normal.norm(), 1, 1e3 * kEps);
    const double margin = 2e-3 * p->depth + 1e-4;
    expectMinimalTranslation(a, pa, b, pb, *p, margin);
    // No sampled direction separates with a (meaningfully) shorter translation: the support
    // overlap along d, h_A(d) + h_B(-d), bounds the depth from above.
    const auto x = detail::ConvexProxy::fromCollider(a, pa),
               y = detail::ConvexProxy::fromCollider(b, pb);
    double least = std::numeric_limits<double>::infinity();
    for (const Vec3d& d : dirs) {
      const Vec3 dr = d.cast<Real>();
      const double o = d.dot(toD(x.support(dr)) - toD(y.support(-dr))) + x.radius + y.radius;
      least = std::min(least, o);
    }
    ASSERT_LE(p->depth, least + depthTol(4)) << k;
    const auto g = detail::gjk(x, y);
    if (g.overlapping && !detail::epa(x, y, g.simplex).converged) ++unconverged;
  }
  EXPECT_GT(checked, 600);
  std::printf("all convex pairs: %d overlapping cases, EPA not converged in %d\n", checked,
              unconverged);
}

TEST(Epa, FlatDifferencesGiveTheRadii) {
  // Capsules whose core segments cross: the segments' difference is a flat parallelogram, the
  // cores touch with depth 0, and the depth is the sum of the radii along the common normal.
  const Collider a(Capsule{Real(0.3), 1}), b(Capsule{Real(0.2), 1});
  const Transform pa{};
  const Transform pb{Vec3::Zero(), Quat(Eigen::AngleAxis<Real>(Real(M_PI / 2), Vec3::UnitX()))};
  const auto p = penetration(a, pa, b, pb);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->depth, 0.5, depthTol(2));
  EXPECT_NEAR(std::abs(p->normal.x()), 1, 1e-5);  // the segments span y and z
  // A sphere centred on a triangle: depth = radius along the triangle's normal.
  const auto tri = detail::ConvexProxy::triangle(Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1));
  const auto ball = detail::ConvexProxy::point(Vec3(0, 0, 0), Real(0.25));
  const detail::ConvexSeparation s = detail::separation(tri, ball);
  EXPECT_NEAR(s.distance, -0.25, depthTol(2));
  EXPECT_NEAR(std::abs(s.normal.y()), 1, 1e-5);
  // A capsule core piercing a triangle: a 3D difference, depth from EPA; B's segment along y
  // through the triangle: pushing it sideways out of the triangle's plane costs nothing,
  // so the least translation is sideways (x or z) to clear an edge, or along y to clear the
  // plane... the segment passes through (0, 0, 0); it must move by at least the distance to
  // the nearest edge (0.447) or up/down by its half length (1), plus the radius 0.1.
  const auto seg = detail::ConvexProxy::segment(Vec3(0, -1, 0), Vec3(0, 1, 0), Real(0.1));
  const detail::ConvexSeparation q = detail::separation(tri, seg);
  EXPECT_NEAR(q.distance, -(1 / std::sqrt(5.0) + 0.1), depthTol(2) + 1e-6);
  EXPECT_TRUE(toD(q.normal).allFinite());
}
