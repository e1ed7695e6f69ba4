// Moving obstacles (ParticleSystem::setMovingObstacles, the particle side of rigid bodies as
// obstacles) without a World: validation, static ones tested continuously, moving ones with the
// velocity of their surface, emitters with a carrier velocity.
#include <gtest/gtest.h>

#include <cmath>

#include "inertia/core/error.h"
#include "inertia/particles/particle_system.h"
#include "particle_test_util.h"

using namespace inertia;
using inertia::test::particle;


TEST(ParticleMovingObstacles, InvalidObstaclesAreRejected) {
  ParticleSystem ps({.capacity = 4});
  const Collider sphere(Shape(Sphere{1}));
  MovingObstacle none;
  EXPECT_THROW(ps.setMovingObstacles({&none, 1}), InvalidArgument);
  MovingObstacle bad{&sphere, Transform{Vec3::Zero(), Quat(2, 0, 0, 0)}};
  EXPECT_THROW(ps.setMovingObstacles({&bad, 1}), InvalidArgument);
  MovingObstacle nan{&sphere};
  nan.linearVelocity.x() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(ps.setMovingObstacles({&nan, 1}), InvalidArgument);
}

TEST(ParticleMovingObstacles, ObstaclesAtRestAreTestedContinuously) {
  // The thin-plate tunnelling test of ParticleObstacles with the plate given as a moving
  // obstacle at rest (a static body): 1000 m/s particles, 16.7 m per step, none gets through.
  const int n = 2000;
  ParticleSystem ps({.capacity = std::size_t(n), .restitution = Real(0.3)});
  const Collider plate(Shape(Box{Vec3(Real(0.005), 50, 50)}));
  const MovingObstacle obstacle{&plate, Transform{Vec3(5, 0, 0), Quat::Identity()}};
  ps.setMovingObstacles({&obstacle, 1});
  for (int i = 0; i < n; ++i)
    ps.pool().add(particle(Vec3(0, Real(i % 50) * Real(0.3) - 7, Real(i / 50) * Real(0.3) - 6),
                           Vec3(1000, 0, Real(i % 5) - 2)));
  for (int step = 0; step < 10; ++step) {
    ps.step(Real(1.0 / 60));
    for (std::size_t i = 0; i < ps.pool().size(); ++i)
      ASSERT_LT(ps.pool().position(i).x(), Real(4.995)) << "particle " << i << " at step " << step;
  }
}

TEST(ParticleMovingObstacles, ASpinningSphereGivesItsSurfaceVelocity) {
  // A particle touching the equator of a sphere spinning at w about y, e = 0 and friction
  // large enough to stick: the normal velocity goes, and the tangential velocity becomes the
  // surface's, w x r (Coulomb: the tangential change |w R| is below mu times the normal one).
  const Real w = 4, R = 1, r = Real(0.05);
  ParticleSystem ps({.capacity = 2, .restitution = 0, .friction = 100});
  const Collider sphere(Shape(Sphere{R}));
  const MovingObstacle spinning{&sphere, Transform{}, Vec3::Zero(), Vec3(0, w, 0), Vec3::Zero()};
  ps.setMovingObstacles({&spinning, 1});
  // Just inside the particle's reach of the surface, moving into it at 1 m/s.
  ps.pool().add(particle(Vec3(R + r - Real(0.001) + Real(1.0 / 60), 0, 0), Vec3(-1, 0, 0), r));
  ps.step(Real(1.0 / 60));
  const Vec3 v = ps.pool().velocity(0);
  EXPECT_NEAR(v.x(), 0, 1e-5);
  EXPECT_NEAR(v.y(), 0, 1e-5);
  EXPECT_NEAR(v.z(), -w * R, 1e-4);  // (0, w, 0) x (R, 0, 0) = (0, 0, -w R)
  EXPECT_GE(ps.pool().position(0).x(), R + r);
}

TEST(ParticleMovingObstacles, CarrierVelocityIsAddedAtTheEmissionPoint) {
  // An emitter at (2, 0, 0) carried by a frame spinning at w about z through the origin and
  // moving at u: every particle (zero own speed) gets u + w x (2, 0, 0) exactly.
  const Vec3 u(1, 2, 3), w(0, 0, Real(0.5));
  ParticleSystem ps({.capacity = 64});
  ps.addEmitter(
      {.pose = {Vec3(2, 0, 0), Quat::Identity()}, .burst = 50, .speed = {0, 0}, .seed = 1});
  ps.emitter(0).setCarrierVelocity(u, w, Vec3::Zero());
  ps.step(Real(0.01));
  ASSERT_EQ(ps.pool().size(), 50u);
  const Vec3 expected = u + w.cross(Vec3(2, 0, 0));
  for (std::size_t i = 0; i < ps.pool().size(); ++i)
    EXPECT_LE((ps.pool().velocity(i) - expected).norm(), 1e-6);
}
