// A rope's static shape against the exact equilibrium of the discrete chain, computed here
// independently from the balance of forces at each vertex.
#include <gtest/gtest.h>

#include <cmath>

#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

constexpr double kG = 9.81;

// Steps until every vertex is slower than `speed` (m/s), at most `maxSteps`; returns the steps.
// Steps at 1/60 s until every vertex has stayed slower than `speed` for 150 steps in a row
// (2.5 s, longer than the slowest mode's period, about 2 s): one slow step alone may be an
// oscillation's turning point, where the displacement is largest. Returns the steps taken.
int settle(Deformable& d, double speed, int maxSteps) {
  int quiet = 0;
  for (int s = 0; s < maxSteps; ++s) {
    d.step(Real(1) / 60);
    double fastest = 0;
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      fastest = std::max(fastest, double(d.velocity(i).norm()));
    quiet = fastest < speed ? quiet + 1 : 0;
    if (quiet == 150) return s + 1;
  }
  return maxSteps;
}

// Hanging from its top vertex, spring i (from the top) carries the weight of every vertex
// below it, so it is longer than its rest length by that weight over k: each vertex's height is
// exact in closed form. Soft springs (the rope doubles its length), so that the stretch is
// large beside the float positions' resolution.
TEST(DeformableRope, HangingRopeStretchesByTheWeightBelowEachSpring) {
  const int segments = 20;
  const double mass = 0.42, k = 20, length = 2;
  MassSpringModel m = rope({.from = {0, 0, 0},
                            .to = {0, Real(-length), 0},
                            .segments = segments,
                            .mass = Real(mass),
                            .stiffness = {.stretch = Real(k), .bend = 0},
                            .damping = 1});
  m.pinned = {0};
  Deformable d({}, m);
  d.addField({GravityField{Vec3(0, Real(-kG), 0)}});
  ASSERT_LT(settle(d, 1e-5, 6000), 6000);
  const double mi = mass / (segments + 1), rest = length / segments;
  double y = 0;
  for (int i = 1; i <= segments; ++i) {
    y -= rest + (segments - i + 1) * mi * kG / k;
    // Float positions near 4 m resolve to ulp = 4.8e-7 m, and a settling rope stops where a
    // step's motion h v rounds away (h v < ulp / 2), a few ulps from equilibrium per spring,
    // summed over 20 springs: 1e-4 m against a stretch of 2 m.
    EXPECT_NEAR(d.position(std::size_t(i)).y(), y, 1e-4) << "vertex " << i;
    EXPECT_EQ(d.position(std::size_t(i)).x(), 0);
  }
}

struct ChainShape {
  std::vector<Eigen::Vector2d> points;
  double horizontalTension = 0;
};

// The discrete catenary: a chain of n springs (rest L, stiffness k) between pins at (0, 0) and
// (span, 0), n - 1 free vertices of mass m. The horizontal tension H is the same in every
// spring; spring i's vertical force is V_i = -(n - 1) m g / 2 + (i - 1) m g (symmetry), its
// tension T_i = |(H, V_i)|, its length L + T_i / k along (H, V_i) / T_i. H is found by
// bisection so that the lengths' horizontal parts add up to the span.
ChainShape discreteCatenary(int n, double rest, double k, double m, double span) {
  auto shape = [&](double h) {
    ChainShape c{{Eigen::Vector2d::Zero()}, h};
    for (int i = 1; i <= n; ++i) {
      const double v = -(n - 1) * m * kG / 2 + (i - 1) * m * kG, t = std::hypot(h, v);
      c.points.push_back(c.points.back() + (rest + t / k) / t * Eigen::Vector2d(h, v));
    }
    return c;
  };
  double lo = 1e-9, hi = 1e9;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    (shape(mid).points.back().x() < span ? lo : hi) = mid;
  }
  return shape(std::sqrt(lo * hi));
}

// Pinned at both ends 1.5 m apart, 2 m long, stiff (k = 5e4 N/m): the settled rope lies on
// the discrete catenary, and its sag is that of the continuous catenary of the same length to
// about 1% (the discrete chain's masses sit at points, a difference O(1 / n^2)).
TEST(DeformableRope, PinnedAtBothEndsSettlesOnTheCatenary) {
  const int n = 24;
  const double span = 1.5, length = 2, mass = 0.5, k = 5e4;
  MassSpringModel m = rope({.from = {0, 0, 0},
                            .to = {Real(span), 0, 0},
                            .segments = n,
                            .mass = Real(mass),
                            .stiffness = {.stretch = Real(k), .bend = 0},
                            .damping = 2});
  for (Spring& s : m.springs) s.restLength = Real(length / n);
  // Start hanging as a V (springs at rest length), not straight and compressed.
  const double drop = std::sqrt(length * length - span * span) / 2;
  for (int i = 0; i <= n; ++i) {
    const double t = double(i) / n;
    m.positions[std::size_t(i)] = Vec3(Real(span * t), Real(-2 * drop * std::min(t, 1 - t)), 0);
  }
  m.pinned = {0, std::uint32_t(n)};
  Deformable d({}, m);
  d.addField({GravityField{Vec3(0, Real(-kG), 0)}});
  d.addField({LinearDragField{Real(0.05)}});
  ASSERT_LT(settle(d, 1e-5, 6000), 6000);
  const double mi = mass / (n + 1);
  const ChainShape exact = discreteCatenary(n, length / n, k, mi, span);
  for (int i = 0; i <= n; ++i) {
    // At rest to 1e-5 m/s, the slowest (pendulum) mode, omega ~ 3/s, is within 3e-6 m of rest;
    // float rounding of coordinates near 1 m is 1.2e-7.
    EXPECT_NEAR(d.position(std::size_t(i)).x(), exact.points[std::size_t(i)].x(), 1e-5)
        << "vertex " << i;
    EXPECT_NEAR(d.position(std::size_t(i)).y(), exact.points[std::size_t(i)].y(), 1e-5)
        << "vertex " << i;
  }
  // The continuous catenary y = a cosh(x / a) of arc length 2 over the span: 2 a sinh(span / 2a) =
  // length.
  double lo = 0.01, hi = 100;
  for (int it = 0; it < 200; ++it) {
    const double a = (lo + hi) / 2;
    (2 * a * std::sinh(span / (2 * a)) > length ? lo : hi) = a;
  }
  const double a = (lo + hi) / 2, sag = a * (std::cosh(span / (2 * a)) - 1);
  EXPECT_NEAR(-d.position(std::size_t(n / 2)).y(), sag, 0.01 * sag);
}

}  // namespace
}  // namespace inertia
