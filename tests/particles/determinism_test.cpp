// The same system gives the same bytes whatever the thread count.
#include <gtest/gtest.h>

#include <cstring>

#include "inertia/core/thread_pool.h"
#include "inertia/particles/particle_system.h"

using namespace inertia;

namespace {

ParticleSystem makeSystem(bool granular) {
  ParticleSystem ps({.capacity = 8000, .restitution = Real(0.3), .particleCollisions = granular});
  ps.addEmitter({.shape = EmitterShape::Sphere, .pose = {Vec3(0, 2, 0), Quat::Identity()},
                 .radius = 1, .rate = 3000, .burst = 5000, .spread = Real(0.4), .speed = {0, 3},
                 .lifetime = {1, 3}, .size = {Real(0.02), Real(0.05)}, .seed = 3});
  ps.addField({GravityField{}});
  ps.addField({TurbulenceField{.amplitude = 2}});
  ps.addField({VortexField{.angularSpeed = 2}});
  ps.addObstacle({Collider(Shape(Plane{Vec3::UnitY(), 0})), Transform{}});
  ps.addObstacle({Collider(Shape(Sphere{Real(0.5)})), Transform{Vec3(0, Real(0.5), 0), Quat::Identity()}});
  return ps;
}

bool samePoolBytes(const ParticlePool& a, const ParticlePool& b) {
  auto same = [](auto x, auto y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size_bytes()) == 0;
  };
  return a.size() == b.size() && same(a.positions(), b.positions()) &&
         same(a.velocities(), b.velocities()) && same(a.ages(), b.ages()) && same(a.ids(), b.ids());
}

}  // namespace

TEST(ParticleDeterminism, SameBytesAtOneAndTwoThreads) {
  for (bool granular : {false, true}) {
    ThreadPool one(1), two(2);
    ParticleSystem a = makeSystem(granular), b = makeSystem(granular);
    for (int step = 0; step < 30; ++step) {
      a.step(Real(1.0 / 60), &one);
      b.step(Real(1.0 / 60), &two);
    }
    ASSERT_GT(a.pool().size(), 3 * 2048u) << "the test needs several batches of 2048";
    EXPECT_TRUE(samePoolBytes(a.pool(), b.pool())) << (granular ? "granular" : "plain");
  }
}

TEST(ParticleDeterminism, GranularCollisionsConserveMomentum) {
  // Particle-particle impulses come in equal and opposite pairs only when both partners see
  // each other; the Jacobi pass computes each side from the same snapshot, so momentum is
  // conserved up to rounding. Two equal particles head-on with e = 1 swap velocities.
  ParticleSystem ps({.capacity = 4, .restitution = 1, .particleCollisions = true});
  ParticlePool::Spawn s;
  s.radius = Real(0.1);
  s.lifetime = std::numeric_limits<Real>::infinity();
  s.position = Vec3(0, 0, 0);
  s.velocity = Vec3(1, 0, 0);
  ps.pool().add(s);
  s.position = Vec3(Real(0.25), 0, 0);
  s.velocity = Vec3(-1, 0, 0);
  ps.pool().add(s);
  for (int i = 0; i < 10; ++i) ps.step(Real(0.01));
  const Vec3 p = ps.pool().velocity(0) * ps.pool().masses()[0] + ps.pool().velocity(1) * ps.pool().masses()[1];
  EXPECT_LE(p.norm(), 1e-9);
  EXPECT_NEAR(ps.pool().velocity(0).x(), -1, 1e-6);
  EXPECT_NEAR(ps.pool().velocity(1).x(), 1, 1e-6);
}
