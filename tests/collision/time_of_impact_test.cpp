// Shape casts against analytic fractions, and conservative advancement checked by sampling:
// at the returned time the shapes are apart by no more than the tolerance, and a dense scan of
// closestPoints over the sweep (refined by bisection) finds no contact before it.
#include "inertia/collision/time_of_impact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "collision_test_util.h"
#include "inertia/collision/distance.h"

using namespace inertia;
using namespace inertia::test;

namespace {

// Distances carry GJK's rounding, a few dozen ulps of coordinates of ~5 m.
const double kRound = 64 * kEps * 5;

// Signed distance of the swept pair at time t: negative (penetration depth) when overlapping.
double separationAt(const Collider& a, const Sweep& sa, const Collider& b, const Sweep& sb,
                    double t) {
  const Transform pa = sa.at(Real(t)), pb = sb.at(Real(t));
  if (const auto p = penetration(a, pa, b, pb)) return -p->depth;
  return closestPoints(a, pa, b, pb).distance;
}

// The first time in [0, end] at which the pair overlaps by more than `slack`: a scan of n
// samples, then bisection on the first bracket. 2 when no sample overlaps.
double firstContact(const Collider& a, const Sweep& sa, const Collider& b, const Sweep& sb,
                    double end, int n, double slack) {
  double prev = 0;
  for (int i = 1; i <= n; ++i) {
    const double t = end * i / n;
    if (separationAt(a, sa, b, sb, t) < -slack) {
      double lo = prev, hi = t;
      for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (lo + hi);
        (separationAt(a, sa, b, sb, mid) < -slack ? hi : lo) = mid;
      }
      return hi;
    }
    prev = t;
  }
  return 2;
}

}  // namespace

TEST(ShapeCast, SphereAgainstSphereAtAnalyticFraction) {
  std::mt19937_64 rng(21);
  int hits = 0, misses = 0;
  double worst = 0;
  const ShapeCastSettings settings;
  for (int k = 0; k < 2000; ++k) {
    const Sphere sa{Real(uniform(rng, 0.1, 0.6))}, sb{Real(uniform(rng, 0.1, 0.6))};
    const Transform pa{randomVec(rng, -3, 3)}, pb{randomVec(rng, -1, 1)};
    const Vec3 r = (pb.p - pa.p) * Real(uniform(rng, 0.5, 2)) + randomVec(rng, -1, 1);
    // |c + s r| = R: the smaller root of a quadratic in s, in double.
    const Vec3d c = toD(pa.p) - toD(pb.p), rd = toD(r);
    const double R = sa.radius + sb.radius;
    if (c.norm() <= R + 1e-3) continue;
    const double qa = rd.squaredNorm(), qb = 2 * c.dot(rd), qc = c.squaredNorm() - R * R;
    const double disc = qb * qb - 4 * qa * qc;
    const double exact = disc >= 0 ? (-qb - std::sqrt(disc)) / (2 * qa) : -1;
    const auto hit = castShape(Collider(sa), pa, r, Collider(sb), pb, settings);
    if (exact < 0 || exact > 1) {
      // Grazing misses may round either way; clear misses must miss.
      if (disc < -1e-2 * qa || exact > 1.01 || exact < 0) {
        EXPECT_FALSE(hit.has_value()) << k;
        ++misses;
      }
      continue;
    }
    ASSERT_TRUE(hit.has_value()) << k;
    // Conservative: never past the exact fraction; short of it by at most the tolerance over
    // the closing speed along the normal (plus rounding).
    const Vec3d n = (toD(pb.p) - (c + toD(pb.p) + exact * rd)).normalized();
    const double closing = rd.dot(n);
    if (closing < 1e-2) continue;  // grazing: the fraction is ill-conditioned
    ++hits;
    ASSERT_LE(hit->fraction, exact + kRound / closing) << k;
    ASSERT_GE(hit->fraction, exact - (settings.tolerance + kRound) / closing) << k;
    worst = std::max(worst, (exact - hit->fraction) * closing);
    // The normal is B's surface normal facing A.
    ASSERT_LE((toD(hit->normal) + n).norm(), 1e-2) << k;
  }
  EXPECT_GT(hits, 300);
  EXPECT_GT(misses, 100);
  std::printf("sphere cast: %d hits, worst gap at the hit %.3g m (tolerance %g)\n", hits, worst,
              double(settings.tolerance));
}

TEST(ShapeCast, SphereAgainstBoxMatchesSphereTracing) {
  std::mt19937_64 rng(22);
  int hits = 0;
  for (int k = 0; k < 1000; ++k) {
    const Box box{randomVec(rng, 0.2, 1)};
    const Sphere sphere{Real(uniform(rng, 0.05, 0.5))};
    const Transform pb = randomPose(rng, 1), ps{randomVec(rng, -4, 4)};
    const Vec3 r = (pb.p + randomVec(rng, -1, 1) - ps.p) * Real(uniform(rng, 0.8, 1.5));
    // Oracle: trace the sphere's centre against the box grown by the radius (exact SDF, double).
    const Vec3d o = toLocal(pb, ps.p), d = pb.q.cast<double>().conjugate() * toD(r);
    if (sdf(box, o).distance - sphere.radius < 1e-2) continue;
    double s = 0, exact = -1;
    for (int it = 0; it < 100000 && s <= 1; ++it) {
      const double dist = sdf(box, o + s * d).distance - sphere.radius;
      if (dist < 1e-12) {
        exact = s;
        break;
      }
      s += dist / d.norm();
    }
    const auto hit = castShape(Collider(sphere), ps, r, Collider(box), pb);
    if (exact < 0) {
      // A miss, unless the path grazes the box (min distance along the path below a margin).
      double closest = 1e9;
      for (int i = 0; i <= 1000; ++i)
        closest = std::min(closest, sdf(box, o + i / 1000.0 * d).distance - sphere.radius);
      if (closest > 1e-2) {
        EXPECT_FALSE(hit.has_value()) << k;
      }
      continue;
    }
    ASSERT_TRUE(hit.has_value()) << k;
    const Vec3d n = sdf(box, o + exact * d).gradient;
    const double closing = -d.dot(n);
    if (closing < 1e-2) continue;
    ++hits;
    // The tracer stops within 1e-12 m of the grown surface, so its fraction is early by that.
    ASSERT_LE(hit->fraction, exact + (kRound + 1e-12) / closing) << k;
    ASSERT_GE(hit->fraction, exact - (ShapeCastSettings{}.tolerance + kRound) / closing) << k;
    // The point lies on the box's surface.
    ASSERT_NEAR(queryPoint(Collider(box), pb, hit->point).distance, 0, 1e-3) << k;
  }
  EXPECT_GT(hits, 200);
}

TEST(ShapeCast, SphereFallingOntoWideBoxLikeAPlane) {
  // 20 m wide: in float, the support planes through corners 10 m away tilt by the rounding of
  // the search direction (~1e-6), which costs ~1e-5 m of gap at the hit; a 100 m box costs
  // ~5e-4 m, over the default tolerance (the cast stays conservative, just stops earlier).
  const Collider ground(Box{Vec3(10, Real(0.5), 10)});
  const Collider ball(Sphere{Real(0.25)});
  for (double h : {1.0, 2.5, 7.0}) {
    const auto hit = castShape(ball, {Vec3(Real(0.3), Real(h), -2)}, Vec3(0, -10, 0), ground, {});
    ASSERT_TRUE(hit.has_value());
    const double exact = (h - 0.25 - 0.5) / 10;
    EXPECT_LE(hit->fraction, exact + kRound);
    EXPECT_GE(hit->fraction, exact - (1e-4 + kRound) / 10);
    EXPECT_NEAR(hit->normal.y(), 1, 1e-5);
    EXPECT_NEAR(hit->point.y(), 0.5, 1e-3);
  }
  // Moving away, or too short: no hit.
  EXPECT_FALSE(castShape(ball, {Vec3(0, 2, 0)}, Vec3(0, 10, 0), ground, {}).has_value());
  EXPECT_FALSE(castShape(ball, {Vec3(0, 2, 0)}, Vec3(0, -1, 0), ground, {}).has_value());
  // Starting inside: fraction 0, normal out of the ground.
  const auto start = castShape(ball, {Vec3(0, Real(0.6), 0)}, Vec3(0, -1, 0), ground, {});
  ASSERT_TRUE(start.has_value());
  EXPECT_EQ(start->fraction, 0);
  EXPECT_NEAR(start->normal.y(), 1, 1e-4);
}

TEST(ShapeCast, HullCastIsConservative) {
  std::mt19937_64 rng(23);
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    const Collider a{Shape(randomHull(rng, 12, 0.6))}, b{Shape(randomHull(rng, 12, 0.8))};
    const Transform pa{randomVec(rng, -4, 4), randomRotation(rng)}, pb = randomPose(rng, 0.5);
    const Vec3 r = (pb.p - pa.p + randomVec(rng, -0.5, 0.5)) * Real(uniform(rng, 0.5, 1.5));
    if (closestPoints(a, pa, b, pb).overlapping) continue;
    const auto hit = castShape(a, pa, r, b, pb);
    const Sweep sa{pa, {pa.p + r, pa.q}}, sb{pb, pb};
    if (!hit) {
      EXPECT_GT(firstContact(a, sa, b, sb, 1, 200, 1e-3), 1) << k;
      continue;
    }
    ++hits;
    const Transform at{pa.p + hit->fraction * r, pa.q};
    const ClosestPoints c = closestPoints(a, at, b, pb);
    ASSERT_LE(c.distance, 1e-4 + kRound) << k;
    ASSERT_FALSE(penetration(a, at, b, pb).has_value() && penetration(a, at, b, pb)->depth > kRound)
        << k;
    ASSERT_GE(firstContact(a, sa, b, sb, hit->fraction, 100, kRound), 1) << k;
  }
  EXPECT_GT(hits, 100);
}

TEST(TimeOfImpact, RotatingPairsAreConservative) {
  std::mt19937_64 rng(24);
  int hits = 0, separated = 0;
  double worstBelow = 0, worstAbove = 0, sumIter = 0;
  int maxIter = 0;
  const ToiSettings settings{.targetSeparation = Real(0.002), .tolerance = Real(1e-3)};
  for (int k = 0; k < 200; ++k) {
    const Collider a =
        k % 2 ? Collider(Box{randomVec(rng, 0.1, 0.6)}) : Collider(Shape(randomHull(rng, 10, 0.6)));
    const Collider b{Shape(randomHull(rng, 14, 0.7))};
    // A flies past or into B while both spin (up to ~2.5 rad over the sweep).
    const Vec3 start = randomVec(rng, -4, 4);
    const Quat turnStart = randomRotation(rng);
    const Vec3 jitter = randomVec(rng, -1, 1);  // before the scale, as GCC drew them
    const Real scale = Real(uniform(rng, 0.2, 1.2));
    const Sweep sa{{start, turnStart}, {-start * scale + jitter, randomRotation(rng)}};
    const Sweep sb{randomPose(rng, 0.3), randomPose(rng, 0.3)};
    if (separationAt(a, sa, b, sb, 0) < 0.01) continue;
    const ToiResult r = timeOfImpact(a, sa, b, sb, settings);
    ASSERT_NE(r.status, ToiStatus::Overlapping);
    ASSERT_NE(r.status, ToiStatus::Failed) << k;
    sumIter += r.iterations;
    maxIter = std::max(maxIter, r.iterations);
    const double contact = firstContact(a, sa, b, sb, 1, 400, 0);
    if (r.status == ToiStatus::Separated) {
      ++separated;
      EXPECT_GT(contact, 1) << k;  // no contact anywhere on the sweep
      continue;
    }
    ++hits;
    // At t: apart, by the target up to the tolerance (GJK on the posed shapes is the judge).
    const double d = separationAt(a, sa, b, sb, r.t);
    ASSERT_GE(d, settings.targetSeparation - kRound) << k;
    ASSERT_LE(d, settings.targetSeparation + settings.tolerance + kRound) << k;
    ASSERT_NEAR(r.separation, d, kRound) << k;
    // No contact before t.
    ASSERT_GE(contact, r.t) << k;
    worstBelow = std::min(worstBelow, d - settings.targetSeparation);
    worstAbove = std::max(worstAbove, d - settings.targetSeparation);
  }
  EXPECT_GT(hits, 40);
  EXPECT_GT(separated, 20);
  std::printf(
      "toi: %d hits, %d separated; separation - target in [%.3g, %.3g] m; iterations "
      "mean %.1f max %d\n",
      hits, separated, worstBelow, worstAbove, sumIter / (hits + separated), maxIter);
}

TEST(TimeOfImpact, TranslationMatchesAnalyticTime) {
  // Pure translation head-on: one advancement step lands on the target.
  const Collider a(Box{Vec3(Real(0.5), Real(0.5), Real(0.5))}), b(Box{Vec3(1, 1, 1)});
  const Sweep sa{{Vec3(-5, 0, 0)}, {Vec3(5, 0, 0)}},
      sb{{Vec3(0, Real(0.2), 0)}, {Vec3(0, Real(0.2), 0)}};
  const ToiSettings settings{.targetSeparation = 0, .tolerance = Real(1e-3)};
  const ToiResult r = timeOfImpact(a, sa, b, sb, settings);
  ASSERT_EQ(r.status, ToiStatus::Hit);
  const double exact = (5 - 1.5) / 10;  // faces meet when the centres are 1.5 apart
  EXPECT_LE(r.t, exact + kRound);
  EXPECT_GE(r.t, exact - (1e-3 + kRound) / 10);
  EXPECT_NEAR(r.normal.x(), 1, 1e-4);
}

TEST(TimeOfImpact, FastThinPlateThatEndPointTestsMiss) {
  // A small box crossing a 2 cm plate in one sweep: apart at t = 0 and t = 1, so a discrete
  // test at the end points sees nothing; conservative advancement finds the crossing.
  const Collider plate(Box{Vec3(2, Real(0.01), 2)}),
      bullet(Box{Vec3(Real(0.05), Real(0.05), Real(0.05))});
  const Sweep sp{{Vec3::Zero()}, {Vec3::Zero()}};
  const Quat spin(Eigen::AngleAxis<Real>(Real(1.2), Vec3(1, 0, 1).normalized()));
  const Sweep sb{{Vec3(Real(0.3), 3, 0)}, {Vec3(Real(0.4), -3, Real(0.1)), spin}};
  ASSERT_FALSE(overlap(plate, sp.start, bullet, sb.start));
  ASSERT_FALSE(overlap(plate, sp.end, bullet, sb.end));
  const ToiResult r = timeOfImpact(plate, sp, bullet, sb);
  ASSERT_EQ(r.status, ToiStatus::Hit);
  const double d = separationAt(plate, sp, bullet, sb, r.t);
  EXPECT_GE(d, -kRound);
  EXPECT_LE(d, 1e-3 + kRound);
  // Roughly when the bullet's centre is ~0.06 m above the plate's top (its half-diagonal or less).
  const double y = sb.at(r.t).p.y();
  EXPECT_GT(y, 0.01 + 0.05 - 1e-3);
  EXPECT_LT(y, 0.01 + 0.05 * std::sqrt(3.0) + 2e-3);
  EXPECT_GE(firstContact(plate, sp, bullet, sb, 1, 2000, 0), r.t);
}

TEST(TimeOfImpact, MissingPairIsSeparated) {
  const Collider a(Box{Vec3(Real(0.5), Real(0.5), Real(0.5))}), b(Sphere{Real(0.5)});
  const Quat q(Eigen::AngleAxis<Real>(Real(2), Vec3::UnitY()));
  const Sweep sa{{Vec3(-5, 0, 0)}, {Vec3(5, 0, 0), q}}, sb{{Vec3(0, 3, 0)}, {Vec3(0, 3, 0)}};
  const ToiResult r = timeOfImpact(a, sa, b, sb);
  EXPECT_EQ(r.status, ToiStatus::Separated);
  EXPECT_EQ(r.t, 1);
}

TEST(TimeOfImpact, OverlappingAtStart) {
  const Collider a(Sphere{1}), b(Box{Vec3(1, 1, 1)});
  const Sweep sa{{Vec3(Real(1.5), 0, 0)}, {Vec3(5, 0, 0)}}, sb{};
  const ToiResult r = timeOfImpact(a, sa, b, sb);
  EXPECT_EQ(r.status, ToiStatus::Overlapping);
  EXPECT_EQ(r.t, 0);
  EXPECT_NEAR(r.separation, -0.5, kRound);
}

TEST(TimeOfImpact, SweepInterpolatesRotationAtConstantRate) {
  const Quat q0(Eigen::AngleAxis<Real>(Real(0.3), Vec3::UnitX()));
  const Quat q1 = Quat(Eigen::AngleAxis<Real>(Real(1.5), Vec3(0, 1, 1).normalized())) * q0;
  const Sweep s{{Vec3::Zero(), q0}, {Vec3(1, 2, 3), q1}};
  EXPECT_NEAR(s.angularVelocity().norm(), 1.5, 1e-5);
  EXPECT_LE((s.at(1).q.coeffs() - q1.coeffs()).norm(), 1e-5);
  EXPECT_LE((toD(s.at(0.5f).p) - Vec3d(0.5, 1, 1.5)).norm(), 1e-6);
  // Half way: half the angle about the same axis.
  EXPECT_NEAR(q0.angularDistance(s.at(0.5f).q), 0.75, 1e-5);
}
