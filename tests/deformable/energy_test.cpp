// Energy: symplectic Euler's bounded error on an undamped linear system, and the implicit
// step's stability where the explicit ones blow up.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "../sanitizer.h"
#include "deformable/spring_forces.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

// A free chain along x, stretched unevenly and released from rest, moves along x only, where
// its springs (neighbour and skip-one, all along the line) are exactly linear: M x'' = -K x.
// Symplectic Euler conserves H~ = E - (h/2) x^T K v exactly on it, and
// |x^T K v| <= omega_max E (Cauchy-Schwarz in the mass-weighted norm), so from rest (H~ = E0)
// E stays in [E0 / (1 + a), E0 / (1 - a)] with a = h omega_max / 2. Gershgorin bounds
// omega_max^2 by the largest row sum of |M^-1 K|: 2 (2 k_stretch + 2 k_bend) / m.
TEST(DeformableEnergy, SymplecticEulerStaysWithinItsModifiedEnergyBound) {
  const int segments = 12;
  const Real mass = 1.3f, ks = 400, kb = 50;
  MassSpringModel m = rope({.from = {0, 0, 0},
                            .to = {Real(segments) * Real(0.1), 0, 0},
                            .segments = segments,
                            .mass = mass,
                            .stiffness = {.stretch = ks, .bend = kb}});
  for (std::size_t i = 0; i < m.vertexCount(); ++i)
    m.positions[i].x() += Real(0.02) * std::sin(Real(i) * Real(1.3)) + Real(0.01) * Real(i % 3);
  Deformable d({.integrator = ode::Method::SymplecticEuler}, m);
  const double mi = double(mass) / double(m.vertexCount());
  const double omegaMax = std::sqrt(4 * (double(ks) + double(kb)) / mi);
  const double h = 0.6 / omegaMax, a = h * omegaMax / 2;
  const double e0 = d.springEnergy() + d.kineticEnergy();
  double lo = e0, hi = e0;
  for (int s = 0; s < 2000; ++s) {
    d.step(Real(h));
    const double e = d.springEnergy() + d.kineticEnergy();
    lo = std::min(lo, e), hi = std::max(hi, e);
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      ASSERT_EQ(d.position(i).y(), 0) << "stays on the line";
  }
  // Float rounding of l - L in the spring energy: relative ~ eps L / (l - L) ~ 1e-5.
  EXPECT_GE(lo, e0 / (1 + a) * (1 - 1e-4));
  EXPECT_LE(hi, e0 / (1 - a) * (1 + 1e-4));
  // Not a bound that nothing reaches: the energy does swing by a fair part of it.
  EXPECT_GT(hi - lo, 0.1 * (e0 / (1 - a) - e0 / (1 + a)));
}

// Total mechanical energy of a deformable under gravity g: kinetic + springs + m g y.
double mechanicalEnergy(const Deformable& d, double g) {
  double e = d.kineticEnergy() + d.springEnergy();
  for (std::size_t i = 0; i < d.vertexCount(); ++i)
    e += double(d.masses()[i]) * g * double(d.position(i).y());
  return e;
}

// How much rounding the state to Real can change the energy: each coordinate moves by at most
// eps |x| (and each velocity by eps |v|), which changes E by at most |dE/dx| eps |x| (and
// m |v| eps |v|), with dE/dx the total force (springs and gravity). Twice that, for the
// rounding of the state the step started from and of the one it ends in.
double roundingBound(const Deformable& d, double g) {
  const std::size_t n = d.vertexCount();
  std::vector<double> x(3 * n), v(3 * n), f(3 * n, 0.0);
  for (std::size_t i = 0; i < 3 * n; ++i)
    x[i] = double(d.positions()[i]), v[i] = double(d.velocities()[i]);
  std::vector<std::uint8_t> broken(d.springs().size(), 0);
  detail::addSpringForces<double>(d.springs(), broken, x.data(), v.data(), f.data());
  double bound = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double m = double(d.masses()[i]);
    f[3 * i + 1] -= m * g;
    for (std::size_t c = 0; c < 3; ++c)
      bound += std::fabs(f[3 * i + c] * x[3 * i + c]) + m * v[3 * i + c] * v[3 * i + c];
  }
  return 2 * double(std::numeric_limits<Real>::epsilon()) * bound + 1e-12;
}

// A 1 m cloth of 11 x 11 vertices (0.01 kg each) with springs of stiffness k (bend k / 100),
// pinned at two corners, released flat and spinning about the pinned edge's normal.
MassSpringModel spinningCloth(Real k) {
  const int n = 10;
  MassSpringModel m = cloth({.size = {1, 1},
                             .resolution = {n, n},
                             .mass = Real(0.01 * (n + 1) * (n + 1)),
                             .stiffness = {.stretch = k, .shear = k, .bend = k / 100}});
  m.pinned = {0, std::uint32_t(n)};
  m.velocities.assign(m.vertexCount(), Vec3::Zero());
  for (std::size_t i = 0; i < m.vertexCount(); ++i)
    m.velocities[i] = Vec3(-m.positions[i].z() * 4, 0, (m.positions[i].x() + Real(0.5)) * 2);
  for (std::uint32_t i : m.pinned) m.velocities[i].setZero();
  return m;
}

// A cloth pinned at two corners, released flat and spinning about its pinned edge's normal so
// that its springs turn fast, with springs from 1e2 to 1e6 N/m (0.01 kg per vertex):
// omega_max h reaches sqrt(4 * 2e6 / 0.01) / 60 ~ 470 at 1/60 s. The implicit step never gains
// energy: at a stationary point of its incremental potential, whose spring term majorises the
// springs' energy and touches it at the step's start, E1 <= E0 - |v1 - v0|_M^2 / 2 exactly, and
// the inexact solve adds at most its reported slack G . v1 <= |G| |v1| (|G| below the Newton
// tolerance); the state's rounding to Real adds what roundingBound says.
TEST(DeformableEnergy, ImplicitEulerNeverGainsEnergyUpToAMillionNewtonsPerMetre) {
  const int n = 10;
  const double g = 9.81;
  // Under the sanitizers, two of them (see sanitizer.h).
  const std::vector<Real> stiffnesses = test::kSanitized
                                            ? std::vector<Real>{1e2f, 1e4f}
                                            : std::vector<Real>{1e2f, 1e3f, 1e4f, 1e5f, 1e6f};
  for (Real k : stiffnesses) {
    const MassSpringModel m = spinningCloth(k);
    Deformable d({.integrator = ode::Method::BackwardEuler, .solverTolerance = 1e-9}, m);
    d.addField({GravityField{Vec3(0, Real(-g), 0)}});
    const double e0 = mechanicalEnergy(d, g);
    double e = e0;
    for (int s = 0; s < 120; ++s) {
      const double allowed = roundingBound(d, g);
      d.step(Real(1) / 60);
      ASSERT_TRUE(d.lastSolve().converged) << "k " << k << " step " << s;
      const double next = mechanicalEnergy(d, g);
      ASSERT_TRUE(std::isfinite(next));
      ASSERT_LE(next - e, d.lastSolve().energySlack + allowed + roundingBound(d, g))
          << "k " << k << " step " << s << " energy " << e;
      e = next;
    }
    // It fell and swung: the free corners hang below the pins; backward Euler damped it.
    EXPECT_LT(d.position(std::size_t(n * (n + 1))).y(), -0.5f) << "k " << k;
    EXPECT_LT(e, e0) << "k " << k;
  }
}

// The test above can fail: one Newton step (as Baraff and Witkin take, linearised here about
// x0 + h v0) gains energy on the same cloth at 1e6 N/m (a spring that turns by h v across it is
// stretched by (h v)^2 / 2L), where the converged step loses some at every step.
TEST(DeformableEnergy, OneNewtonStepGainsEnergyAtAMillionNewtonsPerMetre) {
  const double g = 9.81;
  Deformable d(
      {.integrator = ode::Method::BackwardEuler, .solverTolerance = 1e-9, .newtonMaxIterations = 1},
      spinningCloth(1e6f));
  d.addField({GravityField{Vec3(0, Real(-g), 0)}});
  double e = mechanicalEnergy(d, g), largestRise = 0;
  for (int s = 0; s < 60; ++s) {
    d.step(Real(1) / 60);
    const double next = mechanicalEnergy(d, g);
    largestRise = std::max(largestRise, next - e);
    e = next;
  }
  // Far above what rounding can do (roundingBound is ~1e-5 J here).
  EXPECT_GT(largestRise, 1e-3);
}

// Symplectic Euler on the same stiff cloth blows up (omega_max h ~ 470 >> 2): its energy passes
// what gravity can release, and no NaN or infinity reaches the state: the runaway guard holds
// every vertex's speed to 4e5 m/s (and its motion over a step to h times that), where before
// it the state overflowed within a few steps and each such step was undone and reported.
TEST(DeformableEnergy, SymplecticEulerBlowsUpOnTheStiffCloth) {
  const int n = 10;
  const double g = 9.81;
  MassSpringModel m = cloth({.size = {1, 1},
                             .resolution = {n, n},
                             .mass = Real(0.01 * (n + 1) * (n + 1)),
                             .stiffness = {.stretch = 1e6f, .shear = 1e6f, .bend = 1e3f}});
  m.pinned = {0, std::uint32_t(n)};
  Deformable d({.integrator = ode::Method::SymplecticEuler}, m);
  d.addField({GravityField{Vec3(0, Real(-g), 0)}});
  const double bound = 0.01 * (n + 1) * (n + 1) * g * 1.5;  // what gravity can release
  bool exceeded = false;
  Real fastest = 0;
  for (int s = 0; s < 120; ++s) {
    d.step(Real(1) / 60);
    const double e = d.kineticEnergy() + d.springEnergy();
    exceeded = exceeded || e > bound;
    for (std::size_t i = 0; i < d.vertexCount(); ++i) {
      ASSERT_TRUE(d.position(i).allFinite()) << "step " << s;
      ASSERT_TRUE(d.velocity(i).allFinite()) << "step " << s;
      fastest = std::max(fastest, d.velocity(i).norm());
    }
  }
  EXPECT_TRUE(exceeded);
  EXPECT_GT(fastest, Real(1e5));  // it ran away, up to the guard
  EXPECT_LE(fastest, Real(4e5) * (1 + 1e-6f));
}

}  // namespace
}  // namespace inertia
