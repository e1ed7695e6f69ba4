// Particle motion against closed forms and conservation laws.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "inertia/core/error.h"
#include "inertia/particles/particle_system.h"
#include "particle_test_util.h"

using namespace inertia;

namespace {

ParticleSystem systemWith(ode::Method method, std::vector<ForceField> fields, std::size_t capacity = 16) {
  ParticleSystem ps({.capacity = capacity, .integrator = method});
  for (auto& f : fields) ps.addField(f);
  return ps;
}

// The shared immortal particle, with a mass (the closed forms below use 1 kg by default).
ParticlePool::Spawn particleOfMass(const Vec3& x, const Vec3& v, Real m = 1) {
  ParticlePool::Spawn s = test::particle(x, v);
  s.mass = m;
  return s;
}

}  // namespace

TEST(ParticleMotion, FallWithLinearDragMatchesTheClosedForm) {
  // v(t) = v_t + (v0 - v_t) e^{-k t / m}, v_t = m g / k.
  const Real m = 2, k = Real(0.8), g = Real(9.81), T = 3;
  const double vt = -double(m * g / k), v0 = 5;
  const double exact = vt + (v0 - vt) * std::exp(-double(k) * T / double(m));
  auto finalVelocity = [&](ode::Method method, int steps) {
    ParticleSystem ps = systemWith(method, {{GravityField{Vec3(0, -g, 0)}}, {LinearDragField{k}}});
    ps.pool().add(particleOfMass(Vec3::Zero(), Vec3(0, Real(v0), 0), m));
    for (int i = 0; i < steps; ++i) ps.step(T / Real(steps));
    return double(ps.pool().velocity(0).y());
  };
  // RK4: global error ~ (k h / m)^4 |v0 - vt| T: ~1e-9 at 300 steps, below float rounding
  // (~1e-6 per step relative to |v| ~ 12, accumulated over 300 steps: ~4e-4 worst case).
  EXPECT_NEAR(finalVelocity(ode::Method::Rk4, 300), exact, 5e-4);
  // Symplectic Euler is first order: its error halves with the step (ratio 2 within 10%).
  const double e1 = std::fabs(finalVelocity(ode::Method::SymplecticEuler, 100) - exact);
  const double e2 = std::fabs(finalVelocity(ode::Method::SymplecticEuler, 200) - exact);
  EXPECT_NEAR(e1 / e2, 2.0, 0.2);
}

TEST(ParticleMotion, ProjectileIsExactWithRk4AndVelocityVerlet) {
  // Constant acceleration: both methods are exact up to rounding (their error terms involve
  // derivatives of a, which vanish).
  for (ode::Method method : {ode::Method::Rk4, ode::Method::VelocityVerlet}) {
    ParticleSystem ps = systemWith(method, {{GravityField{Vec3(0, -9.81f, 0)}}});
    ps.pool().add(particleOfMass(Vec3::Zero(), Vec3(3, 10, -1)));
    for (int i = 0; i < 120; ++i) ps.step(Real(1.0 / 60));
    const Real t = Real(120.0 / 60);
    const Vec3 expected = Vec3(3, 10, -1) * t + Real(0.5) * Vec3(0, -9.81f, 0) * t * t;
    // 120 steps of float rounding on coordinates of size ~10: 120 * 10 * eps ~ 1.4e-4.
    EXPECT_LE((ps.pool().position(0) - expected).norm(), 3e-4) << ode::methodName(method);
  }
}

TEST(ParticleMotion, VortexGivesThePromisedAngularVelocity) {
  // A particle moving with the flow inside the core circles at omega; after T it has turned by
  // omega T. RK4 at h = 1/240 on a circle: phase error ~ (omega h)^4 omega T ~ 1e-8 rad, so
  // float rounding of the position (~1e-6 over 1000 steps) dominates.
  const Real omega = 3, r = Real(0.8), T = Real(4);
  ParticleSystem ps = systemWith(ode::Method::Rk4, {{VortexField{.angularSpeed = omega, .coreRadius = 2}}});
  ps.pool().add(particleOfMass(Vec3(r, 0, 0), Vec3(0, 0, -omega * r)));
  const int steps = 960;
  for (int i = 0; i < steps; ++i) ps.step(T / Real(steps));
  const Vec3 x = ps.pool().position(0);
  // Counter-clockwise about +y: x = r cos(wt), z = -r sin(wt).
  const Vec3 expected(r * std::cos(omega * T), 0, -r * std::sin(omega * T));
  EXPECT_LE((x - expected).norm(), 1e-3);
  // A particle starting at rest spins up to the flow (tightness 5/s): after 4 s its angular
  // velocity is within e^{-20} of omega, on the same radius (the centripetal term follows its
  // own speed); RK4's error is far below float rounding here.
  ParticleSystem rest = systemWith(ode::Method::Rk4, {{VortexField{.angularSpeed = omega, .coreRadius = 2, .tightness = 5}}});
  rest.pool().add(particleOfMass(Vec3(r, 0, 0), Vec3::Zero()));
  for (int i = 0; i < steps; ++i) rest.step(T / Real(steps));
  const Vec3 p = rest.pool().position(0), v = rest.pool().velocity(0);
  const Real angular = (p.cross(v)).y() / p.squaredNorm();
  EXPECT_NEAR(angular, omega, 1e-3 * omega);
  EXPECT_NEAR(std::hypot(p.x(), p.z()), r, 1e-3 * r);
}

// Found by the hour-long soak (bench/soak.cpp) in scenes/vortex_smoke.json: a particle crossing
// near the axis faster than the flow. Its centripetal term, v_t^2 / r, grows without bound as r
// falls; an explicit step overshot across the axis at a larger v_t, and the particle reached
// 1e19 m/s and NaN within 0.4 s. The scene's vortex and step: omega 2.5 rad/s, core 0.8 m,
// tightness 1.5/s, midpoint at 1/60 s; the particle 1 cm from the axis, 2 m/s across it.
// Oracle: drag towards the flow (rate 1.5/s) settles it on the flow; after 10 s (e^-15 of its
// start left) its angular velocity is the Rankine flow's at its radius, within 1%. On the way
// its kinetic energy per kg never exceeds the larger of its start's and the flow's fastest
// (omega core = 2 m/s), both halved squares, plus the deepest well the centripetal pull can
// make, (omega core)^2 / 2 (a pull of at most omega^2 r inside the core, weaker outside): drag
// towards the flow only removes energy above the flow's. 1% on top for midpoint's O(h^2).
TEST(ParticleMotion, VortexHoldsAParticleCrossingNearItsAxis) {
  const Real omega = Real(2.5), core = Real(0.8), h = Real(1.0 / 60.0);
  ParticleSystem ps = systemWith(
      ode::Method::Midpoint, {{VortexField{.angularSpeed = omega, .coreRadius = core, .tightness = Real(1.5)}}});
  ps.pool().add(particleOfMass(Vec3(Real(0.01), 0, 0), Vec3(0, 0, 2)));
  Real fastest = 0;
  for (int i = 0; i < 600; ++i) {
    ps.step(h);
    const Vec3 v = ps.pool().velocity(0);
    ASSERT_TRUE(v.allFinite() && ps.pool().position(0).allFinite()) << "step " << i;
    fastest = std::max(fastest, v.norm());
  }
  const Real top = std::max(Real(2), omega * core);
  EXPECT_LE(fastest, Real(1.01) * std::sqrt(top * top + omega * core * omega * core));
  const Vec3 p = ps.pool().position(0), v = ps.pool().velocity(0);
  const Real r = std::hypot(p.x(), p.z());
  const Real flow = r <= core ? omega : omega * core * core / (r * r);
  EXPECT_NEAR(p.cross(v).y() / (r * r), flow, Real(0.01) * flow) << "r " << r;
}

// A drag whose time constant m / k is far below the step: a 1 g particle in a drag of 1 kg/s
// (1 ms) at 60 Hz, k h / m = 16.7. An explicit step multiplied v by 1 - 16.7 and diverged to NaN
// within a second; the drag now acts at a rate of at most 1 / h (FieldBatch::step). Oracle: the
// true motion relaxes monotonically to the terminal velocity g m / k; every explicit method's
// speed stays within its start's and g s, the steady state the capped rate 1 / s leaves (s =
// dragStep: h, 2 h for position Verlet; a consistent method keeps the fixed point of
// v' = g - v / s), which it reaches within 0.1% in 60 steps (the amplifications at the capped
// rate are at most 0.64 a step). backward_euler, which holds the drag itself, reaches the true
// g m / k within 1%.
TEST(ParticleMotion, StiffDragRelaxesToItsTerminalVelocity) {
  const Real m = Real(0.001), k = 1, g = Real(9.81), h = Real(1.0 / 60.0);
  for (ode::Method method : ode::kMethods) {
    ParticleSystem ps = systemWith(method, {{GravityField{Vec3(0, -g, 0)}}, {LinearDragField{k}}});
    ps.pool().add(particleOfMass(Vec3::Zero(), Vec3(0, 2, 0), m));
    const bool implicit = method == ode::Method::BackwardEuler;
    const Real terminal = implicit ? g * m / k : g * dragStep(method, h);
    Real fastest = 0;
    for (int i = 0; i < 60; ++i) {
      ps.step(h);
      ASSERT_TRUE(ps.pool().velocity(0).allFinite()) << ode::methodName(method) << " step " << i;
      fastest = std::max(fastest, ps.pool().velocity(0).norm());
    }
    EXPECT_LE(fastest, std::max(Real(2), terminal) * (1 + Real(1e-5))) << ode::methodName(method);
    EXPECT_NEAR(ps.pool().velocity(0).y(), -terminal, (implicit ? Real(1e-2) : Real(1e-3)) * terminal)
        << ode::methodName(method);
  }
}

TEST(ParticleMotion, SpringsConserveEnergyWithSymplecticEuler) {
  // Two particles on an undamped spring. Symplectic Euler keeps a modified energy, so the true
  // energy oscillates with relative amplitude O(omega h) and does not drift: over 10^5 steps
  // the deviation stays below omega h (here 0.1) while explicit Euler's grows without bound.
  auto run = [](ode::Method method, int steps) {
    ParticleSystem ps({.capacity = 4, .integrator = method});
    ps.pool().add(particleOfMass(Vec3(0, 0, 0), Vec3(0, 0, 0)));
    ps.pool().add(particleOfMass(Vec3(1.5f, 0, 0), Vec3(0, 0.3f, 0)));
    ps.addSpring({.a = 0, .b = 1, .restLength = 1, .stiffness = 100});
    const double e0 = ps.kineticEnergy() + ps.springEnergy();
    double worst = 0;
    const Real h = Real(0.01);  // omega = sqrt(2k/m) = 14.1 rad/s: omega h = 0.14
    for (int i = 0; i < steps; ++i) {
      ps.step(h);
      worst = std::max(worst, std::fabs(ps.kineticEnergy() + ps.springEnergy() - e0) / e0);
    }
    return worst;
  };
  EXPECT_LT(run(ode::Method::SymplecticEuler, 100000), 0.15);
  // Explicit Euler multiplies the energy by 1 + (omega h)^2 = 1.02 per step: x10 in 120 steps.
  EXPECT_GT(run(ode::Method::ExplicitEuler, 1000), 10.0);
}

TEST(ParticleMotion, AliveCountSettlesAtRateTimesLifetime) {
  // Emission at r per second, each living L seconds: r L alive at steady state, give or take
  // the particles of one step (r h) since birth and death are counted per step.
  const Real rate = 1000, life = 2, h = Real(1.0 / 60);
  ParticleSystem ps({.capacity = 5000});
  ps.addEmitter({.rate = rate, .lifetime = {life, life}});
  for (int i = 0; i < 300; ++i) ps.step(h);  // 5 s: well past one lifetime
  const ParticleStats s = ps.stats();
  EXPECT_NEAR(double(s.alive), double(rate * life), double(rate * h) + 1);
  EXPECT_EQ(s.emitted, s.alive + s.died);
  EXPECT_NEAR(double(s.emitted), double(rate) * 300 * double(h), 1.0);
}

TEST(ParticleMotion, BackwardEulerWorksOnFieldsWithoutJacobians) {
  // Backward Euler uses finite-difference Jacobian products; on drag alone (linear in v) it
  // is v_{n+1} = v_n / (1 + k h / m) per step: compare with that closed form.
  const Real k = 4, m = 1, h = Real(0.1);
  ParticleSystem ps = systemWith(ode::Method::BackwardEuler, {{LinearDragField{k}}});
  ps.pool().add(particleOfMass(Vec3::Zero(), Vec3(10, 0, 0), m));
  for (int i = 0; i < 10; ++i) ps.step(h);
  const double expected = 10 / std::pow(1 + double(k * h / m), 10);
  // The solve stops at a relative residual sqrt(eps) (3.5e-4 in float) per step.
  EXPECT_NEAR(ps.pool().velocity(0).x(), expected, 10 * 3.5e-4 * 10);
}

TEST(ParticleMotion, StepRejectsBadInput) {
  ParticleSystem ps({.capacity = 4});
  EXPECT_THROW(ps.step(0), InvalidArgument);
  EXPECT_THROW(ps.step(std::nanf("")), InvalidArgument);
  EXPECT_THROW(ParticleSystem({.restitution = 2}), InvalidArgument);
  EXPECT_THROW(ps.addSpring({.a = 1, .b = 1}), InvalidArgument);
}
