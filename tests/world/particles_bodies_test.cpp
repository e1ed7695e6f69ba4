// Particles and rigid bodies in one World: bodies' shapes as particle obstacles (static ones
// continuously, moving ones with the velocity of their surface) and emitters riding on bodies.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../particles/particle_test_util.h"
#include "../step_constants.h"
#include "inertia/collision/queries.h"
#include "inertia/world/world.h"

using namespace inertia;
using inertia::test::kG;
using inertia::test::particle;

TEST(WorldParticlesBodies, RestingParticlesRideAMovingPlatform) {
  // A kinematic box (top at y = 0.5) moving along x at u = 1.5 m/s; particles on its top at rest
  // relative to it. Each step gravity sinks them by g h^2 and the push-out lifts them back to
  // r + skin with the box's velocity, so for 2 s they stay on it at the same offsets: height
  // within [top + r + skin - g h^2, top + r + skin]; horizontal offset unchanged up to float
  // rounding of coordinates ~3 m over 120 steps of 4 body substeps (~3e-7 * 500 ~ 2e-4 m).
  const Real h = Real(1.0 / 60), u = Real(1.5), r = Real(0.01), top = Real(0.5);
  World world({.gravity = Vec3(0, -kG, 0), .threads = 1});
  const BodyId box =
      world.createBody({.type = BodyType::Kinematic, .linearVelocity = Vec3(u, 0, 0)});
  world.addShape(box, Box{Vec3(1, Real(0.5), 1)});
  ParticleSystem& ps = world.particleSystem(world.createParticleSystem(
      {.capacity = 16, .restitution = 0, .friction = Real(0.5), .collideWithBodies = true}));
  ps.addField({GravityField{Vec3(0, -kG, 0)}});
  std::vector<Vec3> offsets = {Vec3(Real(-0.5), 0, Real(0.2)), Vec3(0, 0, 0),
                               Vec3(Real(0.7), 0, Real(-0.6))};
  for (const Vec3& o : offsets)
    ps.pool().add(particle(Vec3(o.x(), top + r + Real(1e-4), o.z()), Vec3(u, 0, 0), r));
  for (int step = 0; step < 120; ++step) {
    world.step(h);
    const Vec3 boxAt = world.transform(box).p;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      const Vec3 x = ps.pool().position(i);
      ASSERT_NEAR(x.y(), top + r + Real(1e-4), kG * h * h + 1e-5)
          << "particle " << i << " step " << step;
      ASSERT_NEAR(x.x() - boxAt.x(), offsets[i].x(), 2e-4) << "particle " << i << " step " << step;
      ASSERT_NEAR(x.z(), offsets[i].z(), 1e-6);
    }
  }
  EXPECT_NEAR(world.transform(box).p.x(), u * 2, 1e-3);  // the box did move 3 m
}

TEST(WorldParticlesBodies, FrictionOfAMovingPlatformDragsParticlesAlongByCoulomb) {
  // Particles at rest in the world dropped onto the platform (e = 0): every step the push-out
  // takes the normal velocity g h away, and Coulomb friction takes at most mu g h off the
  // relative tangential speed, so the particle's speed grows as min(u, mu g t) (to one step).
  const Real h = Real(1.0 / 60), u = 2, mu = Real(0.4), r = Real(0.01), top = Real(0.5);
  World world({.gravity = Vec3(0, -kG, 0), .threads = 1});
  const BodyId box =
      world.createBody({.type = BodyType::Kinematic, .linearVelocity = Vec3(u, 0, 0)});
  world.addShape(box, Box{Vec3(20, Real(0.5), 1)});
  ParticleSystem& ps = world.particleSystem(world.createParticleSystem(
      {.capacity = 4, .restitution = 0, .friction = mu, .collideWithBodies = true}));
  ps.addField({GravityField{Vec3(0, -kG, 0)}});
  ps.pool().add(particle(Vec3(0, top + r + Real(1e-4), 0), Vec3::Zero(), r));
  for (int step = 1; step <= 60; ++step) {
    world.step(h);
    const double expected = std::min(double(u), double(mu * kG) * step * double(h));
    ASSERT_NEAR(ps.pool().velocity(0).x(), expected, double(mu * kG * h) + 1e-5) << "step " << step;
  }
  EXPECT_NEAR(ps.pool().velocity(0).x(), u, 1e-5);  // caught up after u / (mu g) = 0.51 s
}

TEST(WorldParticlesBodies, AMovingBodyPushesParticlesAtOnePlusETimesItsSpeed) {
  // A kinematic box sweeping along x at u = 3 m/s (5 cm per step, less than its half width) into
  // particles at rest, no gravity, no friction: a particle it reaches is pushed out of the front
  // face with the relative velocity reversed and scaled by e, i.e. at (1 + e) u: Newton's impact
  // against an infinitely heavy wall.
  const Real h = Real(1.0 / 60), u = 3, e = Real(0.5);
  World world({.gravity = Vec3::Zero(), .threads = 1});
  const BodyId box = world.createBody(
      {.type = BodyType::Kinematic, .position = Vec3(-1, 0, 0), .linearVelocity = Vec3(u, 0, 0)});
  world.addShape(box, Box{Vec3(Real(0.2), 1, 1)});
  ParticleSystem& ps =
      world.particleSystem(world.createParticleSystem({.capacity = 8,
                                                       .restitution = e,
                                                       .friction = 0,
                                                       .restitutionThreshold = 0,
                                                       .collideWithBodies = true}));
  for (int i = 0; i < 4; ++i)
    ps.pool().add(particle(Vec3(Real(0.5) * Real(i), Real(0.1) * Real(i), 0), Vec3::Zero(), 0));
  for (int step = 0; step < 60; ++step) world.step(h);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(ps.pool().velocity(i).x(), (1 + e) * u, 1e-4) << "particle " << i;
    EXPECT_NEAR(ps.pool().velocity(i).y(), 0, 1e-6);
    EXPECT_GT(ps.pool().position(i).x(), world.transform(box).p.x() + Real(0.2))
        << "ahead of the box";
  }
}

TEST(WorldParticlesBodies, ParticlesNeverEndInsideAStaticBoxBody) {
  // A fountain raining on a static, rotated box body for 20,000 steps: static bodies are tested
  // continuously like obstacles, so after every step no particle centre is inside the box.
  World world({.gravity = Vec3(0, -kG, 0), .threads = 2});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{Vec3::UnitY(), 0});
  const BodyId box = world.createBody(
      {.type = BodyType::Static,
       .position = Vec3(Real(0.3), Real(0.6), 0),
       .orientation = Quat(Eigen::AngleAxis<Real>(Real(0.6), Vec3(1, 0, 1).normalized()))});
  const ShapeId shape = world.addShape(box, Box{Vec3(Real(0.4), Real(0.15), Real(0.5))});
  ParticleSystem& ps =
      world.particleSystem(world.createParticleSystem({.capacity = 400,
                                                       .restitution = Real(0.4),
                                                       .friction = Real(0.2),
                                                       .collideWithBodies = true}));
  ps.addEmitter({.shape = EmitterShape::Cone,
                 .pose = {Vec3(0, Real(0.05), 0), Quat::Identity()},
                 .angle = Real(0.4),
                 .rate = 60,
                 .speed = {4, 6},
                 .lifetime = {3, 5},
                 .size = {Real(0.005), Real(0.02)},
                 .seed = 5});
  ps.addField({GravityField{Vec3(0, -kG, 0)}});
  const Collider& collider = world.rigidBodies().collider(shape);
  const Transform pose = world.rigidBodies().shapeTransform(shape);
  const Aabb bounds = worldBounds(collider.shape(), pose);
  std::int64_t near = 0;
  for (int step = 0; step < 20000; ++step) {
    world.step(Real(1.0 / 60));
    for (std::size_t i = 0; i < ps.pool().size(); ++i) {
      const Vec3 x = ps.pool().position(i);
      ASSERT_GE(x.y(), 0) << "below the ground, step " << step;
      if (!bounds.contains(x)) continue;
      ASSERT_GE(queryPoint(collider, pose, x).distance, 0) << "inside the box, step " << step;
      ++near;
    }
  }
  EXPECT_GT(near, 10000) << "the test must bring many particles close to the box";
}

TEST(WorldParticlesBodies, BounceOnABodysSphereReachesESquaredHeight) {
  // Dropped from 1 m above the top of a static sphere body, straight over its centre, with
  // restitution e: the apex after the bounce is e^2 m above the contact point. Error as in
  // ParticleObstacles.BounceHeightsFollowESquared: relative 2 g h / v_impact (0.44% at
  // h = 1e-3, v = 4.4 m/s); the tolerance is 3 times that.
  const Real e = Real(0.6), h = Real(1e-3), R = Real(0.5);
  World world({.gravity = Vec3(0, -kG, 0), .substeps = 1, .threads = 1});
  const BodyId ball = world.createBody({.type = BodyType::Static, .position = Vec3(0, 2, 0)});
  world.addShape(ball, Sphere{R});
  ParticleSystem& ps =
      world.particleSystem(world.createParticleSystem({.capacity = 4,
                                                       .restitution = e,
                                                       .friction = 0,
                                                       .restitutionThreshold = 0,
                                                       .collideWithBodies = true}));
  ps.addField({GravityField{Vec3(0, -kG, 0)}});
  const Real contact = 2 + R;
  ps.pool().add(particle(Vec3(0, contact + 1, 0), Vec3::Zero(), 0));
  Real previousVy = 0, top = 0;
  bool bounced = false;
  for (int i = 0; i < 3000; ++i) {
    world.step(h);
    const Real y = ps.pool().position(0).y(), vy = ps.pool().velocity(0).y();
    ASSERT_GE(y, contact - Real(1e-6)) << "inside the sphere at step " << i;
    if (vy > 0 && previousVy <= 0) bounced = true, top = y;
    if (bounced) top = std::max(top, y);
    if (bounced && previousVy > 0 && vy <= 0) break;
    previousVy = vy;
  }
  ASSERT_TRUE(bounced);
  const double expected = double(e * e), v = std::sqrt(2 * double(kG));
  EXPECT_NEAR(double(top - contact), expected,
              expected * 3 * (2 * double(kG) * double(h) / v) + 1e-4);
}

TEST(WorldParticlesBodies, EmitterOnAMovingBodyAddsTheBodysVelocity) {
  // A kinematic body moving at v, turned 90 degrees about z, carries a point emitter sending
  // particles along its local y with speeds uniform in [1, 3] and a spread of 0.3 rad: their
  // mean velocity is v + E[speed] E[direction] = v + 2 * q (0, (1 + cos 0.3) / 2, 0). With
  // 20,000 particles the sample mean's standard error is below 0.005 m/s per component; the
  // tolerance is 0.02 (4 sigma).
  const Vec3 v(Real(2), Real(-1), Real(0.5));
  const Quat q(Eigen::AngleAxis<Real>(std::numbers::pi_v<Real> / 2, Vec3::UnitZ()));
  World world({.gravity = Vec3::Zero(), .threads = 2});
  const BodyId cart = world.createBody({.type = BodyType::Kinematic,
                                        .position = Vec3(1, 2, 3),
                                        .orientation = q,
                                        .linearVelocity = v});
  ParticleSystem& ps = world.particleSystem(world.createParticleSystem({.capacity = 20000}));
  ps.addEmitter({.burst = 20000,
                 .spread = Real(0.3),
                 .speed = {1, 3},
                 .lifetime = Range::constant(std::numeric_limits<Real>::infinity()),
                 .seed = 9,
                 .attachTo = cart});
  world.step(Real(1.0 / 60));
  ASSERT_EQ(ps.pool().size(), 20000u);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < ps.pool().size(); ++i) mean += ps.pool().velocity(i).cast<double>();
  mean /= double(ps.pool().size());
  const Vec3 expected = v + 2 * (q * Vec3(0, (1 + std::cos(Real(0.3))) / 2, 0));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], double(expected[k]), 0.02) << "component " << k;
}

TEST(WorldParticlesBodies, EmittedParticlesFollowARotatingBody) {
  // A kinematic body spinning at w = 2 rad/s about y carries an emitter 1 m from the axis that
  // emits at zero speed. A particle leaves the emission point with the point's velocity w x r
  // and moves straight on from where the point was at its emission (the point moved along the
  // tangent w x r until then); after the step it has flown a chord's tangent: its distance from
  // the point's new position is at most R (w h)^2 / 2 (5.6e-4 m here). Its velocity is w x r at
  // the step's start, exactly up to rounding.
  const Real h = Real(1.0 / 60), w = 2, R = 1;
  World world({.gravity = Vec3::Zero(), .threads = 1});
  const BodyId wheel =
      world.createBody({.type = BodyType::Kinematic, .angularVelocity = Vec3(0, w, 0)});
  ParticleSystem& ps = world.particleSystem(world.createParticleSystem({.capacity = 4000}));
  ps.addEmitter({.pose = {Vec3(R, 0, 0), Quat::Identity()},
                 .rate = 600,
                 .speed = {0, 0},
                 .lifetime = {Real(0.05), Real(0.05)},
                 .seed = 2,
                 .attachTo = wheel});
  int checked = 0;
  for (int step = 0; step < 120; ++step) {
    const Transform before = world.transform(wheel);
    world.step(h);
    const Vec3 pointNow = world.transform(wheel).apply(Vec3(R, 0, 0));
    const Vec3 r0 = before.apply(Vec3(R, 0, 0));
    const Vec3 tangential = Vec3(0, w, 0).cross(r0);
    for (std::size_t i = 0; i < ps.pool().size(); ++i) {
      if (ps.pool().ages()[i] > h) continue;  // emitted this step: age in (0, h]
      EXPECT_LE((ps.pool().position(i) - pointNow).norm(),
                Real(0.5) * R * (w * h) * (w * h) + 1e-5);
      EXPECT_LE((ps.pool().velocity(i) - tangential).norm(), 1e-5);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  // The body turned 4 rad: the emission point went most of a circle round.
  EXPECT_NEAR(std::atan2(-world.transform(wheel).apply(Vec3(R, 0, 0)).z(),
                         world.transform(wheel).apply(Vec3(R, 0, 0)).x()),
              std::remainder(double(w) * 120 * double(h), 2 * std::numbers::pi), 1e-3);
}
