// World::saveState / restoreState: every simulated system (bodies, contacts, joints, particle
// systems, deformables, articulations) and the clock; a restored world continues bit-identically.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "../step_constants.h"
#include "inertia/articulation/builders.h"
#include "inertia/core/error.h"
#include "inertia/deformable/generators.h"
#include "inertia/world/builders.h"
#include "inertia/world/world.h"

namespace inertia {

using test::kDt;

namespace {

template <class T>
void appendBytes(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(value));
}
void appendBytes(std::string& out, std::span<const Real> values) {
  out.append(reinterpret_cast<const char*>(values.data()), values.size_bytes());
}

// Every state a step changes, as bytes: bodies, joints' forces, particles, deformables, clock.
std::string stateBytes(const World& world) {
  std::string out;
  const RigidBodySystem& rb = world.rigidBodies();
  for (BodyId b : rb.bodies()) {
    const Transform t = rb.transform(b);
    appendBytes(out, t.p);
    appendBytes(out, t.q.coeffs());
    appendBytes(out, rb.linearVelocity(b));
    appendBytes(out, rb.angularVelocity(b));
  }
  for (JointId j : rb.joints()) {
    appendBytes(out, rb.jointForce(j));
    appendBytes(out, rb.jointTorque(j));
  }
  for (ParticleSystemId id : world.particleSystems()) {
    const ParticlePool& pool = world.particleSystem(id).pool();
    appendBytes(out, pool.positions());
    appendBytes(out, pool.velocities());
    appendBytes(out, pool.ages());
    appendBytes(out, world.particleSystem(id).stats().emitted);
  }
  for (DeformableId id : world.deformables()) {
    appendBytes(out, world.deformable(id).positions());
    appendBytes(out, world.deformable(id).velocities());
  }
  for (ArticulationId id : world.articulations()) {
    const articulation::Articulation<Real>& a = world.articulation(id);
    appendBytes(out, std::span<const Real>(a.q().data(), std::size_t(a.q().size())));
    appendBytes(out, std::span<const Real>(a.qd().data(), std::size_t(a.qd().size())));
  }
  appendBytes(out, world.time());
  appendBytes(out, world.stepCount());
  return out;
}

// A world with something of every kind: falling boxes on a ground, a hanging chain on ball
// joints, a fountain whose particles hit the bodies (random spread: the emitters' random
// streams), a position-Verlet system (its history lives in the step scratch), a cloth
// falling onto the ground box (implicit Euler), and a double pendulum in reduced coordinates
// whose balls swing through the ground (contacts through its mass matrix).
struct Scene {
  World world{{.threads = 1}};
  ParticleSystemId fountain, verlet;
  DeformableId cloth;
  ArticulationId pendulum;

  Scene() {
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Box{Vec3(5, Real(0.5), 5)}, {}, Transform{Vec3(0, Real(-0.5), 0)});
    for (int i = 0; i < 4; ++i) {
      const BodyId b = world.createBody({.position = Vec3(Real(0.3) * i, Real(0.5 + 0.6 * i), 0)});
      world.addShape(b, Box{Vec3::Constant(Real(0.2))}, Material{.restitution = Real(0.3)});
    }
    addChain(world, {.links = 4, .top = Vec3(2, 3, 0), .direction = Vec3(1, 0, 0)});
    fountain = world.createParticleSystem({.capacity = 2000, .collideWithBodies = true});
    world.particleSystem(fountain).addEmitter({.rate = 600,
                                               .direction = Vec3(Real(0.2), 1, 0),
                                               .spread = Real(0.4),
                                               .speed = {3, 5},
                                               .lifetime = {1, 2}});
    world.particleSystem(fountain).addField({GravityField{}});
    verlet = world.createParticleSystem({.capacity = 200, .integrator = ode::Method::Verlet});
    world.particleSystem(verlet).addEmitter({.pose = Transform{Vec3(-2, 1, 0)},
                                             .burst = 100,
                                             .spread = 1,
                                             .speed = {1, 3},
                                             .lifetime = {10, 10}});
    world.particleSystem(verlet).addField({GravityField{}});
    world.particleSystem(verlet).addObstacle({Collider(Plane{Vec3::UnitY(), 0}), Transform{}});
    cloth = world.createDeformable(
        {.name = "sheet"},
        inertia::cloth({.pose = {Vec3(-1, Real(0.6), 1), Quat::Identity()},
                        .size = {1, 1},
                        .resolution = {8, 8},
                        .mass = Real(0.2),
                        .stiffness = {.stretch = 2000, .shear = 200, .bend = 1}}));
    world.deformable(cloth).addField({GravityField{}});
    WorldArticulationSettings arm;
    arm.name = "pendulum";
    arm.model = articulation::pendulumChain<Real>(2, Real(0.4), 1);
    arm.base = {Vec3(0, Real(0.85), -1.5), Quat::Identity()};
    for (int link = 0; link < 2; ++link)
      arm.shapes.push_back({.link = link,
                            .shape = Sphere{Real(0.1)},
                            .pose = {Vec3(0, Real(-0.4), 0), Quat::Identity()},
                            .material = {.friction = Real(0.5)}});
    arm.q = articulation::VectorX<Real>::Zero(2);
    arm.q << Real(1.2), Real(0.3);
    pendulum = world.createArticulation(arm);
  }
};

void steps(World& world, int n) {
  for (int i = 0; i < n; ++i) world.step(kDt);
}

TEST(WorldSnapshot, RestoredWorldContinuesBitIdenticallyWithEverySystem) {
  Scene s;
  steps(s.world, 40);  // bodies landed, particles in flight and on the boxes, cloth falling
  const World::State saved = s.world.saveState();
  const std::string atSave = stateBytes(s.world);
  steps(s.world, 50);
  const std::string continued = stateBytes(s.world);
  ASSERT_NE(continued, atSave);  // the test sees the state move
  ASSERT_GT(s.world.particleSystem(s.fountain).pool().size(), 100u);
  s.world.restoreState(saved);
  EXPECT_EQ(stateBytes(s.world), atSave);
  steps(s.world, 50);
  EXPECT_EQ(stateBytes(s.world), continued);
}

// A state saved by one world, restored in another made the same way, continues the same.
TEST(WorldSnapshot, StateMovesBetweenWorlds) {
  Scene a, b;
  steps(a.world, 30);
  b.world.restoreState(a.world.saveState());
  steps(a.world, 30);
  steps(b.world, 30);
  EXPECT_EQ(stateBytes(a.world), stateBytes(b.world));
}

// Slots and ids: a system destroyed after the save comes back under its old id; one created
// after it is gone (its id stale); a reference to a system alive in both stays valid.
TEST(WorldSnapshot, RestoreBringsBackTheSavedSlots) {
  Scene s;
  steps(s.world, 10);
  const World::State saved = s.world.saveState();
  const std::string atSave = stateBytes(s.world);
  ParticleSystem& fountain = s.world.particleSystem(s.fountain);
  s.world.destroyParticleSystem(s.verlet);
  s.world.destroyDeformable(s.cloth);
  s.world.destroyArticulation(s.pendulum);
  const ParticleSystemId extra = s.world.createParticleSystem({});
  const ParticleSystemId beyond = s.world.createParticleSystem({});  // a slot the State lacks
  steps(s.world, 5);
  s.world.restoreState(saved);
  EXPECT_TRUE(s.world.isValid(s.verlet));
  EXPECT_TRUE(s.world.isValid(s.cloth));
  EXPECT_TRUE(s.world.isValid(s.pendulum));
  EXPECT_EQ(&s.world.particleSystem(s.fountain), &fountain);
  // The new system took the verlet system's free slot with the next generation.
  EXPECT_FALSE(s.world.isValid(extra));
  EXPECT_THROW(s.world.particleSystem(extra), InvalidArgument);
  // Ids handed out since the save stay invalid, also once their slots are taken again.
  EXPECT_FALSE(s.world.isValid(beyond));
  const ParticleSystemId later = s.world.createParticleSystem({});
  const ParticleSystemId later2 = s.world.createParticleSystem({});
  EXPECT_NE(later, beyond);
  EXPECT_NE(later2, beyond);
  EXPECT_FALSE(s.world.isValid(beyond));
  s.world.destroyParticleSystem(later);
  s.world.destroyParticleSystem(later2);
  EXPECT_EQ(stateBytes(s.world), atSave);
}

// A copied particle system and deformable are independent of their originals and step the same.
TEST(WorldSnapshot, CopiedSystemsStepLikeTheirOriginals) {
  Scene s;
  steps(s.world, 20);
  ParticleSystem copy = s.world.particleSystem(s.verlet);
  Deformable clothCopy = s.world.deformable(s.cloth);
  for (int i = 0; i < 20; ++i) {
    copy.step(kDt);
    s.world.particleSystem(s.verlet).step(kDt);
    clothCopy.step(kDt);
    s.world.deformable(s.cloth).step(kDt);
  }
  const ParticlePool& a = copy.pool();
  const ParticlePool& b = s.world.particleSystem(s.verlet).pool();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.positions().data(), b.positions().data(), a.positions().size_bytes()));
  const auto x = clothCopy.positions(), y = s.world.deformable(s.cloth).positions();
  EXPECT_EQ(0, std::memcmp(x.data(), y.data(), x.size_bytes()));
}

}  // namespace
}  // namespace inertia
