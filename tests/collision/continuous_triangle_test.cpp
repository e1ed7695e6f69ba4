// Continuous vertex-face and edge-edge tests: analytic crossing times, crossings that discrete
// tests at t = 0 and t = 1 miss, a dense-sampling oracle over random motions, and degenerate
// motions (always coplanar, parallel and collinear edges, zero-area triangles, no motion).
#include "inertia/collision/continuous_triangle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "../sanitizer.h"
#include "collision_test_util.h"
#include "inertia/collision/triangle.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

LinearMotion still(const Vec3& x) { return {x, x}; }
LinearMotion move(const Vec3& a, const Vec3& b) { return {a, b}; }

// Time tolerance: the inputs are rounded to Real (relative eps to coordinates of magnitude
// <= ~5); a rounding error e of a coordinate moves a crossing by e / (closing speed), and the
// speeds below are >= 1 per step, so 64 eps covers it (float 7.6e-6, double 1.4e-14).
constexpr double kTimeTol = 64 * kEps;

void expectUnitFinite(const Vec3& n) {
  ASSERT_TRUE(n.allFinite());
  EXPECT_NEAR(n.norm(), 1, 16 * kEps);
}

// Independent oracles in double: distance from a point to a triangle (projection when inside,
// else the nearest edge) and between two segments (interior closest points when both are
// inside, else the nearest end point to the other segment).
double pointSegment(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const Vec3d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}
double pointTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    const Vec3d q = p - n * (n.dot(p - a) / n2);
    const double u = (c - b).cross(q - b).dot(n), v = (a - c).cross(q - c).dot(n),
                 w = (b - a).cross(q - a).dot(n);
    if (u >= 0 && v >= 0 && w >= 0) return std::abs(n.dot(p - a)) / std::sqrt(n2);
  }
  return std::min({pointSegment(p, a, b), pointSegment(p, b, c), pointSegment(p, c, a)});
}
double segmentSegment(const Vec3d& p0, const Vec3d& p1, const Vec3d& q0, const Vec3d& q1) {
  const Vec3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.dot(d1), b = d1.dot(d2), e = d2.dot(d2), c = d1.dot(r), f = d2.dot(r);
  const double den = a * e - b * b;
  if (den > 1e-12 * a * e) {
    const double s = (b * f - c * e) / den, u = (a * f - b * c) / den;
    if (s >= 0 && s <= 1 && u >= 0 && u <= 1) return (p0 + s * d1 - (q0 + u * d2)).norm();
  }
  return std::min({pointSegment(p0, q0, q1), pointSegment(p1, q0, q1), pointSegment(q0, p0, p1),
                   pointSegment(q1, p0, p1)});
}

Vec3d atD(const LinearMotion& m, double t) { return (1 - t) * toD(m.start) + t * toD(m.end); }

// Four moving points, either a vertex and a triangle or two edges.
struct Config {
  std::array<LinearMotion, 4> x;
  bool edges = false;
  // The coplanarity function, evaluated in double from the Real inputs.
  double plane(double t) const {
    const Vec3d a = atD(x[0], t), b = atD(x[1], t), c = atD(x[2], t), d = atD(x[3], t);
    if (edges) return (b - a).cross(d - c).dot(c - a);
    return (c - b).cross(d - b).dot(a - b);  // x[0] the vertex, x[1..3] the triangle
  }
  // Scaled so that a root is a zero of the signed distance.
  double planeDistance(double t) const {
    const Vec3d a = atD(x[0], t), b = atD(x[1], t), c = atD(x[2], t), d = atD(x[3], t);
    const double n = edges ? (b - a).cross(d - c).norm() : (c - b).cross(d - b).norm();
    return n > 0 ? plane(t) / n : 0;
  }
  double distance(double t) const {
    const Vec3d a = atD(x[0], t), b = atD(x[1], t), c = atD(x[2], t), d = atD(x[3], t);
    return edges ? segmentSegment(a, b, c, d) : pointTriangle(a, b, c, d);
  }
  std::optional<double> ccd(Real thickness) const {
    const ContinuousTriangleSettings s{.thickness = thickness};
    if (edges) {
      const auto c = edgeEdgeContinuous(x[0], x[1], x[2], x[3], s);
      if (c) return double(c->time);
      return std::nullopt;
    }
    const auto c = vertexFaceContinuous(x[0], x[1], x[2], x[3], s);
    if (c) return double(c->time);
    return std::nullopt;
  }
};

// The oracle: the signed plane distance sampled at n + 1 equally spaced times; each sign
// change is bisected to 1e-13 and the first root whose proximity distance is within
// `thickness` is the contact. Resolution: two crossings closer than 1/n in time can hide each
// other; grazes that do not change sign are not seen.
struct OracleResult {
  std::optional<double> time;
  double minDistance = 1e300;  // the least sampled proximity distance
};
OracleResult oracle(const Config& c, double thickness, int n) {
  OracleResult r;
  double prevT = 0, prevF = c.planeDistance(0);
  r.minDistance = c.distance(0);
  if (prevF == 0 && r.minDistance <= thickness) r.time = 0;
  for (int k = 1; k <= n; ++k) {
    const double t = double(k) / n, f = c.planeDistance(t);
    r.minDistance = std::min(r.minDistance, c.distance(t));
    if (!r.time && ((prevF < 0 && f >= 0) || (prevF > 0 && f <= 0))) {
      double lo = prevT, hi = t, flo = prevF;
      while (hi - lo > 1e-13) {
        const double mid = 0.5 * (lo + hi), fm = c.planeDistance(mid);
        if ((fm < 0) == (flo < 0) && fm != 0) {
          lo = mid;
          flo = fm;
        } else {
          hi = mid;
        }
      }
      if (c.distance(hi) <= thickness) r.time = hi;
    }
    prevT = t;
    prevF = f;
  }
  return r;
}

}  // namespace

// A vertex falling at 4 m per step through the static triangle y = 0 from y = 1: t = 1/4,
// at the point (0.1, 0, 0.2) of the triangle, normal +y (the side it came from). The same
// after a rigid placement of the whole scene.
TEST(ContinuousTriangle, VertexFallsThroughStaticTriangleAtAnalyticTime) {
  const Vec3 a(-1, 0, -1), b(0, 0, 2), c(2, 0, -1);
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Transform pose = trial == 0 ? Transform{} : randomPose(rng, 2);
    const auto hit = vertexFaceContinuous(
        move(pose.apply(Vec3(Real(0.1), 1, Real(0.2))), pose.apply(Vec3(Real(0.1), -3, Real(0.2)))),
        still(pose.apply(a)), still(pose.apply(b)), still(pose.apply(c)));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->time, 0.25, kTimeTol);
    const Vec3 point = hit->barycentric[0] * a + hit->barycentric[1] * b + hit->barycentric[2] * c;
    EXPECT_NEAR((point - Vec3(Real(0.1), 0, Real(0.2))).norm(), 0, 64 * kEps);
    EXPECT_NEAR(hit->barycentric.sum(), 1, 16 * kEps);
    expectUnitFinite(hit->normal);
    EXPECT_NEAR(hit->normal.dot(pose.rotate(Vec3::UnitY())), 1, 64 * kEps);
    EXPECT_LE(hit->distance, 64 * kEps * 4);
  }
}

// A tilting triangle (c goes from y = 1 to y = -1) and a vertex moving in the x-z plane
// along z = 0 from x = 4 to x = 0: the height difference is (8/3)(t - 0.4)(t - 0.85) by
// construction. The first coplanarity (t = 0.4, x = 2.4) is outside the triangle, the second
// (t = 0.85, x = 0.6) inside: the test must skip the first root and report the second.
TEST(ContinuousTriangle, SkipsCoplanarityOutsideAndReportsLaterRoot) {
  const double y0 = 14.0 / 9 - 68.0 / 75, y1 = 4.0 / 9 - 68.0 / 75;
  const auto hit =
      vertexFaceContinuous(move(Vec3(4, Real(y0), 0), Vec3(0, Real(y1), 0)), still(Vec3(-1, 0, -1)),
                           still(Vec3(0, 0, 2)), move(Vec3(2, 1, -1), Vec3(2, -1, -1)));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->time, 0.85, kTimeTol);
  expectUnitFinite(hit->normal);
  // Without the later root (stop at t = 0.6) nothing is found.
  const Real t = Real(0.6);
  const Vec3 pEnd(4 - 4 * t, Real(y0 + (y1 - y0) * t), 0);
  EXPECT_FALSE(vertexFaceContinuous(move(Vec3(4, Real(y0), 0), pEnd), still(Vec3(-1, 0, -1)),
                                    still(Vec3(0, 0, 2)),
                                    move(Vec3(2, 1, -1), Vec3(2, 1 - 2 * t, -1))));
}

// Edge A on the x axis, edge B from (x0, -1, z0) to (x1, 1, z1) rotating: x0 = 0.5 - t,
// x1 = -0.5 + t, z0 = 1 - 3t, z1 = 0.5 - t. The lines meet when B crosses y = 0 at z = 0:
// z0 + z1 = 1.5 - 4t = 0, t = 3/8, at the middle of both edges (s = u = 1/2). A common
// translation of all four points changes nothing.
TEST(ContinuousTriangle, RotatingEdgePairAtAnalyticTime) {
  for (const Vec3& drift : {Vec3(0, 0, 0), Vec3(3, -2, 5)}) {
    const Vec3 o(1, 2, -1);
    const auto hit = edgeEdgeContinuous(
        move(o + Vec3(-1, 0, 0), o + drift + Vec3(-1, 0, 0)),
        move(o + Vec3(1, 0, 0), o + drift + Vec3(1, 0, 0)),
        move(o + Vec3(Real(0.5), -1, 1), o + drift + Vec3(Real(-0.5), -1, -2)),
        move(o + Vec3(Real(-0.5), 1, Real(0.5)), o + drift + Vec3(Real(0.5), 1, Real(-0.5))));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->time, 0.375, kTimeTol);
    EXPECT_NEAR(hit->s, 0.5, 64 * kEps);
    EXPECT_NEAR(hit->u, 0.5, 64 * kEps);
    expectUnitFinite(hit->normal);
    // n = dA x dB = (0, -0.5, 4) at t = 3/8; B came from +z, so the normal (B to A) is -n/|n|.
    const Vec3 expected = Vec3(0, Real(0.5), -4).normalized();
    EXPECT_NEAR(hit->normal.dot(expected), 1, 64 * kEps);
    EXPECT_LE(hit->distance, 64 * kEps * 8);
  }
}

// A vertex crossing a sliver triangle (2 mm wide) at 20 m per step: at t = 0 and t = 1 it is
// 10 m away, so discrete tests at the step's ends see nothing; the cubic finds t = 1/2.
// Likewise two thin edges crossing fast.
TEST(ContinuousTriangle, FindsFastCrossingsThatDiscreteTestsMiss) {
  const Vec3 a(-1, 0, 0), b(1, 0, 0), c(0, 0, Real(0.002));
  const Vec3 p0(Real(0.3), 10, Real(0.0005)), p1(Real(0.3), -10, Real(0.0005));
  EXPECT_GT((closestPointOnTriangle(p0, a, b, c).point - p0).norm(), 9);
  EXPECT_GT((closestPointOnTriangle(p1, a, b, c).point - p1).norm(), 9);
  const auto hit = vertexFaceContinuous(move(p0, p1), still(a), still(b), still(c));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->time, 0.5, kTimeTol);
  expectUnitFinite(hit->normal);
  EXPECT_NEAR(hit->normal.y(), 1, 64 * kEps);  // came from +y
  // Passing just beside the sliver (z = 0.0015 > 0.0014, the edge at x = 0.3): no contact.
  EXPECT_FALSE(vertexFaceContinuous(
      move(Vec3(Real(0.3), 10, Real(0.0015)), Vec3(Real(0.3), -10, Real(0.0015))), still(a),
      still(b), still(c)));

  // Edge (z = 5 -> -5 along y = 0) crossing a static edge on the x axis at t = 1/2.
  const auto ee = edgeEdgeContinuous(still(Vec3(-1, 0, 0)), still(Vec3(1, 0, 0)),
                                     move(Vec3(Real(0.25), -1, 5), Vec3(Real(0.25), -1, -5)),
                                     move(Vec3(Real(0.25), 1, 5), Vec3(Real(0.25), 1, -5)));
  ASSERT_TRUE(ee);
  EXPECT_NEAR(ee->time, 0.5, kTimeTol);
  EXPECT_NEAR(ee->s, 0.625, 64 * kEps);
  EXPECT_NEAR(ee->u, 0.5, 64 * kEps);
  EXPECT_NEAR(ee->normal.z(), -1, 64 * kEps);  // B came from +z: B-to-A normal is -z
}

// Random motions in [-1, 1]^3 with displacements up to 2 per coordinate, against the oracle
// at n = 4096 samples (1/4096 step resolution). Checked: every reported contact is real
// (independent distance <= thickness + slack, and the plane distance ~ 0 there); every oracle
// contact is reported no later than the oracle's time; and when the sampled proximity never
// comes within thickness + (max relative speed) / (2 n) (so the true minimum cannot be within
// thickness), nothing is reported.
TEST(ContinuousTriangle, RandomMotionsAgreeWithDenseSamplingOracle) {
  std::mt19937_64 rng(11);
  const int n = 4096;
  const Real thickness = Real(1e-3);
  // Times agree to the oracle's bisection (1e-13) and the Real rounding of the reported time.
  const double timeTol = 1e-12 + 4 * kEps;
  const double slack = 16 * kEps * 4;  // the library's rounding allowance for |coordinates| <= 4
  int both = 0, earlier = 0, ccdOnly = 0, clearMisses = 0, total = 0;
  const int cases = test::samplesFor(4000, 1000);
  for (int k = 0; k < cases; ++k) {
    Config c;
    c.edges = k % 2 == 1;
    double maxSpeed = 0;
    for (auto& m : c.x) {
      m.start = randomVec(rng, -1, 1);
      m.end = m.start + randomVec(rng, -2, 2);
    }
    for (auto& m : c.x)
      for (auto& o : c.x)
        maxSpeed = std::max(maxSpeed, (toD(m.end - m.start) - toD(o.end - o.start)).norm());
    const OracleResult o = oracle(c, thickness, n);
    const std::optional<double> t = c.ccd(thickness);
    ++total;
    if (t) {
      ASSERT_LE(c.distance(*t), thickness + slack) << "false positive, case " << k;
      ASSERT_LE(std::abs(c.planeDistance(*t)), thickness + slack) << "not coplanar, case " << k;
      if (o.time) {
        ++both;
        ASSERT_LE(*t, *o.time + timeTol)
            << "later than the oracle (beyond Real rounding of the time), case " << k;
        if (*t < *o.time - timeTol) ++earlier;  // a graze or crossing hidden between samples
      } else {
        ++ccdOnly;
      }
    } else {
      ASSERT_FALSE(o.time) << "missed the oracle's contact at " << *o.time << ", case " << k;
      if (o.minDistance > thickness + maxSpeed / (2 * n)) ++clearMisses;
    }
    if (o.minDistance > thickness + maxSpeed / (2 * n)) {
      ASSERT_FALSE(t) << "case " << k;
    }
  }
  // Both outcomes must be well represented.
  EXPECT_GT(both, cases * 3 / 40);
  EXPECT_GT(clearMisses, cases / 4);
  EXPECT_LT(earlier + ccdOnly, both / 20);  // the oracle's blind spots are rare
  std::printf(
      "random motions: %d cases, %d contacts found by both (%d earlier by the cubic), "
      "%d only by the cubic (grazes or crossings closer than 1/%d), %d clear misses\n",
      total, both, earlier, ccdOnly, n, clearMisses);
}

// Degenerate motions: always coplanar (sliding in the triangle's plane, rotated so that the
// float build sees rounding-level non-coplanarity), parallel and collinear edges, a zero-area
// triangle, no motion at all. Nothing crashes, hangs or returns NaN; the answers where defined.
TEST(ContinuousTriangle, DegenerateMotionsAreHandled) {
  const Vec3 a(-1, 0, -1), b(0, 0, 2), c(2, 0, -1);
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Transform pose = trial == 0 ? Transform{} : randomPose(rng, 1);
    auto P = [&](const Vec3& x) { return pose.apply(x); };
    // Sliding in the plane at z = 0.1 from x = 5 to x = -5: enters across edge bc at
    // x = 2 (2 - 0.1) / 3, t = (5 - x) / 10 = 0.37333...
    const auto in = vertexFaceContinuous(move(P(Vec3(5, 0, Real(0.1))), P(Vec3(-5, 0, Real(0.1)))),
                                         still(P(a)), still(P(b)), still(P(c)));
    ASSERT_TRUE(in) << "trial " << trial;
    EXPECT_NEAR(in->time, (5 - 2 * 1.9 / 3) / 10, 4 * kTimeTol) << "trial " << trial;
    expectUnitFinite(in->normal);
    // Sliding beside it (z = 3): nothing.
    EXPECT_FALSE(vertexFaceContinuous(move(P(Vec3(5, 0, 3)), P(Vec3(-5, 0, 3))), still(P(a)),
                                      still(P(b)), still(P(c))));
  }
  // Parallel edges: B (y = 1) moving down onto A (y = 0) meets it at t = 1/2, normal -y.
  const auto par = edgeEdgeContinuous(still(Vec3(-1, 0, 0)), still(Vec3(1, 0, 0)),
                                      move(Vec3(-1, 1, 0), Vec3(-1, -1, 0)),
                                      move(Vec3(1, 1, 0), Vec3(1, -1, 0)));
  ASSERT_TRUE(par);
  EXPECT_NEAR(par->time, 0.5, kTimeTol);
  expectUnitFinite(par->normal);
  EXPECT_NEAR(par->normal.y(), -1, 64 * kEps);
  // Parallel edges in a plane at z = 1 off A: they pass without meeting.
  EXPECT_FALSE(edgeEdgeContinuous(still(Vec3(-1, 0, 0)), still(Vec3(1, 0, 0)),
                                  move(Vec3(-1, 1, 1), Vec3(-1, -1, 1)),
                                  move(Vec3(1, 1, 1), Vec3(1, -1, 1))));
  // Collinear edges sliding along the x axis: B's end q0 reaches A's end x = 1 at t = 1/4.
  const auto col =
      edgeEdgeContinuous(still(Vec3(-1, 0, 0)), still(Vec3(1, 0, 0)),
                         move(Vec3(3, 0, 0), Vec3(-5, 0, 0)), move(Vec3(5, 0, 0), Vec3(-3, 0, 0)));
  ASSERT_TRUE(col);
  EXPECT_NEAR(col->time, 0.25, kTimeTol);
  expectUnitFinite(col->normal);
  // A zero-area triangle (all three vertices at the origin) and a vertex through it; a
  // zero-length edge through a segment: finite answers.
  const auto dot = vertexFaceContinuous(move(Vec3(0, 1, 0), Vec3(0, -1, 0)), still(Vec3::Zero()),
                                        still(Vec3::Zero()), still(Vec3::Zero()));
  ASSERT_TRUE(dot);
  EXPECT_NEAR(dot->time, 0.5, kTimeTol);
  expectUnitFinite(dot->normal);
  const auto pointEdge =
      edgeEdgeContinuous(move(Vec3(0, 1, 0), Vec3(0, -1, 0)), move(Vec3(0, 1, 0), Vec3(0, -1, 0)),
                         still(Vec3(-1, 0, 0)), still(Vec3(1, 0, 0)));
  ASSERT_TRUE(pointEdge);
  EXPECT_NEAR(pointEdge->time, 0.5, kTimeTol);
  expectUnitFinite(pointEdge->normal);
  // No motion: touching at t = 0, or never.
  const auto rest = vertexFaceContinuous(still(Vec3(0, 0, 0)), still(a), still(b), still(c));
  ASSERT_TRUE(rest);
  EXPECT_EQ(rest->time, 0);
  expectUnitFinite(rest->normal);
  EXPECT_FALSE(vertexFaceContinuous(still(Vec3(0, 1, 0)), still(a), still(b), still(c)));
  // Everything at one point for the whole step.
  const auto same = edgeEdgeContinuous(still(Vec3::Zero()), still(Vec3::Zero()),
                                       still(Vec3::Zero()), still(Vec3::Zero()));
  ASSERT_TRUE(same);
  expectUnitFinite(same->normal);
  // Settings are checked.
  EXPECT_THROW(vertexFaceContinuous(still(a), still(a), still(b), still(c), {.thickness = -1}),
               InvalidArgument);
  EXPECT_THROW(edgeEdgeContinuous(still(a), still(a), still(b), still(c),
                                  {.thickness = std::numeric_limits<Real>::quiet_NaN()}),
               InvalidArgument);
}
