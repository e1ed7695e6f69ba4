// The particle system's fast paths against the general ones they stand for: the fused
// symplectic Euler kernel against ode::step, the single-plane collision path against the full
// obstacle loop. Both must give the same bits, not merely close values.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "inertia/ode/step.h"
#include "inertia/particles/particle_system.h"

using namespace inertia;

namespace {

// A user field: a spring towards the origin plus a velocity-dependent swirl, per particle.
ForceField customField() {
  return {CustomField{[](const FieldBatch& b) {
    for (std::size_t i = 0; i < b.masses.size(); ++i) {
      const Real* x = &b.positions[3 * i];
      const Real* v = &b.velocities[3 * i];
      b.accelerations[3 * i] += Real(-0.5) * x[0] + Real(0.2) * v[2];
      b.accelerations[3 * i + 1] += Real(-0.5) * x[1];
      b.accelerations[3 * i + 2] += Real(-0.5) * x[2] - Real(0.2) * v[0];
    }
  }}};
}

std::vector<ForceField> someFields() {
  return {{GravityField{}},
          {LinearDragField{Real(0.02)}},
          {LinearDragField{Real(0.05)}, Aabb{Vec3(-1, -1, -1), Vec3(1, 3, 1)}},
          {QuadraticDragField{Real(0.001)}},
          {WindField{Vec3(2, 0, 1), Real(0.01)}},
          {VortexField{.angularSpeed = 3}},
          customField()};
}

ParticlePool::Spawn randomParticle(std::uint64_t& state) {
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return Real(double(state >> 11) * 0x1.0p-53);
  };
  ParticlePool::Spawn s;
  s.position = Vec3(4 * next() - 2, 4 * next(), 4 * next() - 2);
  s.velocity = Vec3(2 * next() - 1, 2 * next() - 1, 2 * next() - 1);
  s.mass = Real(0.001) + Real(0.01) * next();
  s.radius = Real(0.02) * next();
  s.lifetime = std::numeric_limits<Real>::infinity();
  return s;
}

template <class Span>
bool sameBytes(Span a, Span b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

}  // namespace

TEST(ParticleFastPaths, FusedSymplecticEulerIsTheOdeMethodBitForBit) {
  // 5000 particles (3 batches, the last partial) under every built-in field kind and a user
  // field: the system's fused kernel against ode::step(SymplecticEuler) over the whole pool
  // with the same acceleration callback. Fields act per particle, so batching changes nothing.
  const std::size_t n = 5000;
  ParticleSystem ps({.capacity = n, .integrator = ode::Method::SymplecticEuler});
  for (const ForceField& f : someFields()) ps.addField(f);
  std::uint64_t state = 7;
  for (std::size_t i = 0; i < n; ++i) ps.pool().add(randomParticle(state));
  std::vector<Real> x(ps.pool().positions().begin(), ps.pool().positions().end());
  std::vector<Real> v(ps.pool().velocities().begin(), ps.pool().velocities().end());
  std::vector<Real> m(ps.pool().masses().begin(), ps.pool().masses().end());
  const std::vector<ForceField> fields = someFields();
  auto accel = [&](Real t, ode::ConstView<Real> xs, ode::ConstView<Real> vs, ode::View<Real> a) {
    a.setZero();
    applyFields(fields, FieldBatch{t,
                                   {xs.data(), std::size_t(xs.size())},
                                   {vs.data(), std::size_t(vs.size())},
                                   m,
                                   {a.data(), std::size_t(a.size())}});
  };
  ode::Workspace<Real> ws;
  double time = 0;
  const Real h = Real(1.0 / 60);
  for (int step = 0; step < 20; ++step) {
    ps.step(h);
    ode::step(ode::Method::SymplecticEuler, accel, Real(time), h, std::span<Real>(x),
              std::span<Real>(v), ws);
    time += double(h);
    ASSERT_TRUE(sameBytes(ps.pool().positions(), std::span<Real>(x))) << "positions, step " << step;
    ASSERT_TRUE(sameBytes(ps.pool().velocities(), std::span<Real>(v)))
        << "velocities, step " << step;
  }
}

TEST(ParticleFastPaths, SinglePlanePathIsTheFullObstacleLoopBitForBit) {
  // The short path runs when a system has exactly one plane. The same system with the ground
  // plane given twice (one right after the other) takes the full loop everywhere; the duplicate
  // changes nothing there (its hit is never strictly earlier, and after the first one's push-out
  // the particle is r + skin away from it), so both must agree to the bit: bouncing, resting,
  // sliding, and near the sphere and the box.
  auto make = [](bool twice) {
    ParticleSystem ps({.capacity = 6000, .restitution = Real(0.6), .friction = Real(0.3)});
    ps.addEmitter({.shape = EmitterShape::Sphere,
                   .pose = {Vec3(0, 2, 0), Quat::Identity()},
                   .radius = 1,
                   .rate = 4000,
                   .burst = 3000,
                   .spread = Real(0.5),
                   .speed = {0, 4},
                   .lifetime = {1, 4},
                   .size = {Real(0.005), Real(0.05)},
                   .seed = 11});
    ps.addField({GravityField{}});
    ps.addObstacle(
        {Collider(Shape(Plane{Vec3(Real(0.1), 1, 0).normalized(), Real(-0.1)})), Transform{}});
    if (twice)
      ps.addObstacle(
          {Collider(Shape(Plane{Vec3(Real(0.1), 1, 0).normalized(), Real(-0.1)})), Transform{}});
    ps.addObstacle({Collider(Shape(Sphere{Real(0.4)})),
                    Transform{Vec3(Real(0.5), Real(0.3), 0), Quat::Identity()}});
    ps.addObstacle({Collider(Shape(Box{Vec3(Real(0.3), Real(0.2), Real(0.5))})),
                    Transform{Vec3(-1, Real(0.1), 0),
                              Quat(Eigen::AngleAxis<Real>(Real(0.4), Vec3::UnitY()))}});
    return ps;
  };
  ParticleSystem fast = make(false), full = make(true);
  for (int step = 0; step < 240; ++step) {
    fast.step(Real(1.0 / 60));
    full.step(Real(1.0 / 60));
    ASSERT_EQ(fast.pool().size(), full.pool().size());
    ASSERT_TRUE(sameBytes(fast.pool().positions(), full.pool().positions())) << "step " << step;
    ASSERT_TRUE(sameBytes(fast.pool().velocities(), full.pool().velocities())) << "step " << step;
  }
  EXPECT_GT(fast.pool().size(), 3000u);
}
