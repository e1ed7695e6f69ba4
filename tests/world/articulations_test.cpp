// Articulations in the World: links collide with bodies and the ground, their contacts solved in
// the bodies' substeps through the articulation's mass matrix. Checked against conservation of
// angular momentum about a pivot, the closed form of a plastic impact, a resting height, a
// static torque balance, and byte-identical results at 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>
#include <vector>

#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"
#include "inertia/world/world.h"

using namespace inertia;
namespace art = inertia::articulation;

namespace {

constexpr Real kRadius = Real(0.1);

// A one-link pendulum about z at the origin: a ball of mass m at (L, 0, 0) of the link's frame
// (inertia 2/5 m r^2 about its centre).
WorldArticulationSettings pendulum(Real L, Real m, Real friction) {
  WorldArticulationSettings s;
  s.name = "pendulum";
  const Real Ic = Real(0.4) * m * kRadius * kRadius;
  s.model.addLink({.name = "l1",
                   .joint = {.type = art::JointType::Revolute, .axis = Vec3::UnitZ()},
                   .inertia = {m, Vec3(L, 0, 0), Mat3::Identity() * Ic}});
  s.shapes.push_back({.link = 0,
                      .shape = Sphere{kRadius},
                      .pose = {Vec3(L, 0, 0), Quat::Identity()},
                      .material = {.friction = friction, .restitution = 0}});
  return s;
}

BodyId ball(World& world, const Vec3& at, Real mass, Real friction) {
  const BodyId b = world.createBody({.position = at, .name = "ball"});
  const Real volume = Real(4.0 / 3.0 * 3.14159265358979) * kRadius * kRadius * kRadius;
  world.addShape(b, Sphere{kRadius},
                 Material{.density = mass / volume, .friction = friction, .restitution = 0});
  return b;
}

// The pendulum's angular momentum about its pivot (z), H(q) qd.
Real pendulumMomentum(const World& world, ArticulationId id) {
  const art::Articulation<Real>& a = world.articulation(id);
  return art::momentum(a.model(), a.q(), a.qd())(2);
}

}  // namespace

// Zero gravity. The pendulum's ball swings at w0 into a free ball at rest, touching it along
// +y, with a lever arm L about the pivot. The pivot's impulse has no moment about the pivot, so
// the angular momentum about it, the pendulum's H w plus the ball's x × M v, is conserved
// through the impact: every contact impulse acts on both sides at one point, and free flight
// keeps x × v. Only rounding changes it: 1e-4 relative (float, a few hundred operations).
// Plastic and frictionless, the ball leaves with the pendulum's speed at the lever arm:
// w1 = Ip w0 / (Ip + M L^2), v = w1 L. The impact takes one substep, in which the contact
// normal turns with the pendulum by w0 h = 0.004 rad: the lever arm changes by r theta / L,
// 4e-4 relative; 1e-3 covers it (measured: 5e-5).
TEST(WorldArticulations, PlasticImpactOfAPendulumConservesAngularMomentumAboutThePivot) {
  const Real L = 1, m = 1, M = Real(0.5), w0 = 1;
  for (Real friction : {Real(0), Real(0.5)}) {
    World world({.gravity = Vec3::Zero(), .threads = 1});
    WorldArticulationSettings s = pendulum(L, m, friction);
    s.qd = art::VectorX<Real>::Constant(1, w0);
    s.q = art::VectorX<Real>::Zero(1);
    const ArticulationId p = world.createArticulation(s);
    const BodyId b = ball(world, Vec3(L, 2 * kRadius + Real(0.001), 0), M, friction);
    const Vec3 pivot = Vec3::Zero();
    const Real before = pendulumMomentum(world, p) + world.rigidBodies().angularMomentum(pivot).z();
    for (int i = 0; i < 10; ++i) world.step(Real(1) / 60);
    const Real after = pendulumMomentum(world, p) + world.rigidBodies().angularMomentum(pivot).z();
    EXPECT_NEAR(after, before, Real(1e-4) * std::abs(before)) << "friction " << friction;
    const Real Ip = m * L * L + Real(0.4) * m * kRadius * kRadius;
    const Real w1 = Ip * w0 / (Ip + M * L * L);
    if (friction == 0) {
      EXPECT_NEAR(world.linearVelocity(b).y(), w1 * L, Real(1e-3) * w1 * L);
      EXPECT_NEAR(world.articulation(p).qd()(0), w1, Real(1e-3) * w1);
    }
    EXPECT_GT(world.linearVelocity(b).y(), Real(0.5) * w1 * L);  // it was hit
  }
}

// The same impact, elastic (restitution 1, frictionless, w0 L = 2 m/s above the restitution
// threshold): the relative normal speed reverses and angular momentum about the pivot is kept,
// so w1 = w0 (Ip - M L^2) / (Ip + M L^2) and v = 2 Ip w0 L / (Ip + M L^2), kinetic energy kept.
// Restitution takes the approach speed at the step's start, exact here (no gravity); the normal's
// turn during the impact (w0 h = 0.008 rad, lever arm 8e-4 relative) bounds the error: 2e-3.
TEST(WorldArticulations, ElasticImpactOfAPendulumFollowsTheClosedForm) {
  const Real L = 1, m = 1, M = Real(0.5), w0 = 2;
  World world({.gravity = Vec3::Zero(), .threads = 1});
  WorldArticulationSettings s = pendulum(L, m, 0);
  s.shapes[0].material.restitution = 1;
  s.qd = art::VectorX<Real>::Constant(1, w0);
  const ArticulationId p = world.createArticulation(s);
  const BodyId b = ball(world, Vec3(L, 2 * kRadius + Real(0.001), 0), M, 0);
  for (int i = 0; i < 10; ++i) world.step(Real(1) / 60);
  const Real Ip = m * L * L + Real(0.4) * m * kRadius * kRadius;
  const Real v = 2 * Ip * w0 * L / (Ip + M * L * L);
  const Real w1 = w0 * (Ip - M * L * L) / (Ip + M * L * L);
  EXPECT_NEAR(world.linearVelocity(b).y(), v, Real(2e-3) * v);
  EXPECT_NEAR(world.articulation(p).qd()(0), w1, Real(2e-3) * w0);
}

// Link against link: two equal pendulums, pivots 2r + 1 mm apart along y, balls touching along
// y with lever arms L. A swings at w0 into B at rest; plastic and frictionless, equal and
// opposite impulses P L on equal Ip leave both at w0 / 2 (the normal's turn bounds the error as
// in the ball's case: 1e-3).
TEST(WorldArticulations, TwoPendulumsShareTheirSwingInAPlasticImpact) {
  const Real L = 1, m = 1, w0 = 1;
  World world({.gravity = Vec3::Zero(), .threads = 1});
  WorldArticulationSettings a = pendulum(L, m, 0);
  a.qd = art::VectorX<Real>::Constant(1, w0);
  WorldArticulationSettings b = pendulum(L, m, 0);
  b.name = "second";
  b.base.p = Vec3(0, 2 * kRadius + Real(0.001), 0);
  const ArticulationId pa = world.createArticulation(a), pb = world.createArticulation(b);
  for (int i = 0; i < 10; ++i) world.step(Real(1) / 60);
  EXPECT_NEAR(world.articulation(pa).qd()(0), w0 / 2, Real(1e-3) * w0);
  EXPECT_NEAR(world.articulation(pb).qd()(0), w0 / 2, Real(1e-3) * w0);
}

// In gravity, the pendulum (horizontal, its ball at x = L) rests on a box on the ground: the
// frictionless contact's normal force N balances the link's weight about the pivot,
// N L = m g L: N = m g.
// The contact's impulse is the last substep's, N h. The soft contact settles in a few hundred
// steps; 2% covers its residual oscillation and the contact point's offset (the lever arm of a
// ball touching a face below it is L exactly).
TEST(WorldArticulations, PendulumRestingOnABoxPressesWithItsWeight) {
  const Real L = 1, m = 2, g = Real(9.81);
  World world({.threads = 1});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{Vec3::UnitY(), 0});
  const BodyId box = world.createBody({.position = Vec3(L, Real(0.5), 0), .name = "box"});
  world.addShape(box, Box{Vec3(Real(0.3), Real(0.5), Real(0.3))}, Material{.friction = 0.5f});
  // Frictionless: a tangential force at the contact, r below the pivot's height, would carry
  // part of the torque and leave N statically indeterminate.
  WorldArticulationSettings s = pendulum(L, m, Real(0));
  s.base.p = Vec3(0, 1 + kRadius, 0);
  const ArticulationId p = world.createArticulation(s);
  for (int i = 0; i < 300; ++i) world.step(Real(1) / 60);
  const BodyId link = world.linkBody(p, 0);
  Real impulse = 0;
  for (const ContactInfo& c : world.rigidBodies().contacts())
    if ((c.bodyA == link && c.bodyB == box) || (c.bodyA == box && c.bodyB == link))
      for (int k = 0; k < c.manifold.pointCount; ++k) impulse += c.normalImpulses[std::size_t(k)];
  const Real h = Real(1) / 60 / Real(world.settings().substeps);
  EXPECT_NEAR(impulse / h, m * g, Real(0.02) * m * g);
  EXPECT_NEAR(world.articulation(p).q()(0), 0, Real(0.01));  // resting on the box, not through
  EXPECT_LT(std::abs(world.articulation(p).qd()(0)), Real(0.01));
}

// A floating base (a box of half height 0.25) with a hinged arm (a capsule) is dropped from 1 m
// and comes to rest: the base at its half height above the ground, less the soft contact's
// overlap (within the linear slop, 0.005 m, and a margin of 0.005 m for the soft spring), and
// every link still.
// Every contact solver takes the links' contacts (the LCP solvers by pgs passes after their
// islands' LCPs).
class FloatingChain : public testing::TestWithParam<SolverType> {};

TEST_P(FloatingChain, DroppedOnTheGroundComesToRestAtItsShapesHeight) {
  World world({.solver = {.type = GetParam()}, .threads = 1});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{Vec3::UnitY(), 0});
  WorldArticulationSettings s;
  s.name = "walker";
  const Real hx = Real(0.4), hy = Real(0.25), hz = Real(0.3), mb = 5;
  s.model.addLink({.name = "base",
                   .joint = {.type = art::JointType::Floating},
                   .inertia = {mb, Vec3::Zero(),
                               Vec3(mb / 3 * (hy * hy + hz * hz), mb / 3 * (hx * hx + hz * hz),
                                    mb / 3 * (hx * hx + hy * hy))
                                   .asDiagonal()}});
  s.model.addLink({.name = "arm",
                   .parent = 0,
                   .joint = {.type = art::JointType::Revolute,
                             .originPosition = Vec3(hx, 0, 0),
                             .axis = Vec3::UnitZ(),
                             .damping = Real(0.5)},
                   .inertia = {1, Vec3(Real(0.3), 0, 0), Mat3::Identity() * Real(0.01)}});
  s.shapes.push_back({.link = 0, .shape = Box{Vec3(hx, hy, hz)}});
  s.shapes.push_back({.link = 1,
                      .shape = Capsule{Real(0.05), Real(0.25)},
                      .pose = {Vec3(Real(0.3), 0, 0),
                               Quat(Eigen::AngleAxis<Real>(Real(M_PI / 2), Vec3::UnitZ()))}});
  s.q = s.model.neutralConfiguration();
  s.q(1) = 1;  // the base 1 m up
  const ArticulationId w = world.createArticulation(s);
  for (int i = 0; i < 240; ++i) world.step(Real(1) / 60);
  const art::Articulation<Real>& a = world.articulation(w);
  EXPECT_NEAR(a.q()(1), hy, Real(0.01));
  EXPECT_LT(a.qd().norm(), Real(0.05));
  // The arm fell until its capsule met the ground: its end no lower than the ground.
  const BodyId arm = world.linkBody(w, 1);
  EXPECT_GT(world.transform(arm).p.y(), 0);
  for (int i = 0; i < 2; ++i)
    EXPECT_LT(world.linearVelocity(world.linkBody(w, i)).norm(), Real(0.05));
}

INSTANTIATE_TEST_SUITE_P(Solvers, FloatingChain,
                         testing::Values(SolverType::SoftStep, SolverType::Pgs,
                                         SolverType::LcpDantzig));

namespace {

// A two-link planar arm about vertical axes sweeps a box across the ground (friction 0.3): the
// shoulder's velocity drive turns it at 1 rad/s.
struct PushScene {
  World world;
  BodyId box;
  ArticulationId arm;
  explicit PushScene(int threads) : world({.threads = threads}) {
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0}, Material{.friction = Real(0.3)});
    box = world.createBody({.position = Vec3(Real(0.9), Real(0.15), Real(0.4)), .name = "box"});
    world.addShape(box, Box{Vec3::Constant(Real(0.15))},
                   Material{.density = 300, .friction = Real(0.3)});
    WorldArticulationSettings s;
    s.name = "arm";
    s.base.p = Vec3(0, Real(0.15), 0);
    for (int i = 0; i < 2; ++i) {
      art::JointSettings<Real> j{.type = art::JointType::Revolute,
                                 .originPosition = Vec3(i == 0 ? 0 : Real(0.6), 0, 0),
                                 .axis = Vec3::UnitY()};
      if (i == 0)
        j.drive = {.damping = 200, .targetVelocity = -1, .maxForce = 500};
      else
        j.drive = {.stiffness = 200, .damping = 20};
      s.model.addLink({.name = "l" + std::to_string(i + 1),
                       .parent = i - 1,
                       .joint = j,
                       .inertia = {2, Vec3(Real(0.3), 0, 0), Mat3::Identity() * Real(0.06)}});
      s.shapes.push_back({.link = i,
                          .shape = Box{Vec3(Real(0.3), Real(0.08), Real(0.05))},
                          .pose = {Vec3(Real(0.3), 0, 0), Quat::Identity()}});
    }
    arm = world.createArticulation(s);
  }
};

}  // namespace

// The arm, turning clockwise seen from above (-1 rad/s about y), sweeps from +x towards +z: the
// box in its way is pushed away, and is not gone through: its centre stays farther from each
// link's mid-plane than its half size plus the link's half thickness (0.15 + 0.05 m) less the
// allowed overlap (linear slop 0.005 m and the soft contact's give, 0.015 m in all).
TEST(WorldArticulations, RobotArmPushesABox) {
  PushScene scene(1);
  const Vec3 start = scene.world.transform(scene.box).p;
  for (int i = 0; i < 90; ++i) {
    scene.world.step(Real(1) / 60);
    const Vec3 c = scene.world.transform(scene.box).p;
    for (int l = 0; l < 2; ++l) {
      const Vec3 local = scene.world.transform(scene.world.linkBody(scene.arm, l)).applyInverse(c);
      if (local.x() >= 0 && local.x() <= Real(0.6)) {
        ASSERT_GT(std::abs(local.z()), Real(0.2 - 0.015)) << "step " << i << " link " << l;
      }
    }
  }
  const Vec3 end = scene.world.transform(scene.box).p;
  EXPECT_GT(end.z() - start.z(), Real(0.2));  // pushed along the arm's travel
  // The shoulder turned by about 1.5 rad (the drive's -1 rad/s for 1.5 s, slowed by the box).
  EXPECT_LT(scene.world.articulation(scene.arm).q()(0), Real(-0.8));
  EXPECT_NEAR(end.y(), Real(0.15), Real(0.02));  // still on the ground
}

// The same scene at 1 and 2 threads: the same bytes.
TEST(WorldArticulations, DeterministicAtOneAndTwoThreads) {
  PushScene one(1), two(2);
  for (int i = 0; i < 60; ++i) {
    one.world.step(Real(1) / 60);
    two.world.step(Real(1) / 60);
  }
  for (BodyId b : one.world.rigidBodies().bodies()) {
    const Transform t1 = one.world.transform(b), t2 = two.world.transform(b);
    EXPECT_EQ(std::memcmp(t1.p.data(), t2.p.data(), sizeof(Real) * 3), 0);
    EXPECT_EQ(std::memcmp(t1.q.coeffs().data(), t2.q.coeffs().data(), sizeof(Real) * 4), 0);
  }
  const art::VectorX<Real>& q1 = one.world.articulation(one.arm).q();
  const art::VectorX<Real>& q2 = two.world.articulation(two.arm).q();
  EXPECT_EQ(std::memcmp(q1.data(), q2.data(), sizeof(Real) * std::size_t(q1.size())), 0);
}

namespace {

// A planar "table": a trunk (the floating base) on two legs, front and back, each a thigh and a
// shin on hinges about z with a flat box foot (wide along z, so it cannot tip sideways). Hips
// at +theta, knees at -2 theta: each shin comes back under its hip, the foot flat on the
// ground. `locked`: every hinge's limits are [q, q], no drives, so the table is one rigid body.
struct Table {
  static constexpr Real theta = Real(0.5), leg = Real(0.2), trunkHalfHeight = Real(0.05),
                        footHalfHeight = Real(0.02);
  // The kinematic height of the trunk's centre: foot, shin and thigh straight below the hip.
  static Real height() { return footHalfHeight + 2 * leg * std::cos(theta) + trunkHalfHeight; }
  World world;
  ArticulationId table;
  Table(int substeps, SolverType solver)
      : world({.substeps = substeps, .solver = {.type = solver}, .threads = 1}) {
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0}, Material{.friction = Real(0.8)});
    WorldArticulationSettings s;
    s.name = "table";
    const Real mt = 4, ml = Real(0.5);
    s.model.addLink({.name = "trunk",
                     .joint = {.type = art::JointType::Floating},
                     .inertia = {mt, Vec3::Zero(), Mat3::Identity() * Real(0.05)}});
    s.shapes.push_back({.link = 0, .shape = Box{Vec3(Real(0.3), trunkHalfHeight, Real(0.2))}});
    const art::LinkInertia<Real> rod{ml, Vec3(0, -leg / 2, 0), Mat3::Identity() * Real(0.002)};
    for (const Real x : {Real(0.25), Real(-0.25)}) {
      const int thigh = s.model.linkCount();
      s.model.addLink({.name = x > 0 ? "front_thigh" : "back_thigh",
                       .parent = 0,
                       .joint = {.originPosition = Vec3(x, -trunkHalfHeight, 0),
                                 .lower = theta,
                                 .upper = theta},
                       .inertia = rod});
      s.model.addLink(
          {.name = x > 0 ? "front_shin" : "back_shin",
           .parent = thigh,
           .joint = {.originPosition = Vec3(0, -leg, 0), .lower = -2 * theta, .upper = -2 * theta},
           .inertia = rod});
      // The shin leans by theta - 2 theta = -theta: its foot turned back by +theta lies flat.
      s.shapes.push_back(
          {.link = thigh + 1,
           .shape = Box{Vec3(Real(0.06), footHalfHeight, Real(0.2))},
           .pose = {Vec3(0, -leg, 0), Quat(Eigen::AngleAxis<Real>(theta, Vec3::UnitZ()))},
           .material = {.friction = Real(0.8)}});
    }
    s.base.p = Vec3(0, height(), 0);
    s.q = s.model.neutralConfiguration();
    for (int k : {7, 9}) s.q(k) = theta;
    for (int k : {8, 10}) s.q(k) = -2 * theta;
    table = world.createArticulation(s);
  }
};

}  // namespace

// Regression (the quadruped's glide, issue 18): a robot standing on legs locked by their limits
// glided along the ground, because its joint rows were solved after the contacts (and the
// contacts' relax pass after them), so that each substep ended with velocities that one side
// had never answered: legs sweeping back at a constant rate that the feet's friction did not
// see as slip. Solved in the same iterations, the table, one rigid body on two flat feet with
// no horizontal force on it, is at rest: after 2 s, over the next second no link moves.
// Tolerances: the trunk's height within the contacts' linear slop (0.005 m) and a margin of
// 0.005 m for the soft contacts' overlap, as FloatingChain; speeds below 1e-3 m/s, a tenth of
// kStickSpeed (0.01 m/s, where friction begins to treat a contact as sliding); the drift over
// the second below 1e-3 m. The defect glided at about 0.1 m/s, and a soft contact at rest
// moves only by its solver's residual (measured about 1e-6 m/s).
class LockedTable : public testing::TestWithParam<std::tuple<int, SolverType>> {};

TEST_P(LockedTable, StandsStillWithoutGliding) {
  const auto [substeps, solver] = GetParam();
  Table scene(substeps, solver);
  World& world = scene.world;
  const Real dt = Real(1) / 60;
  for (int i = 0; i < 120; ++i) world.step(dt);
  std::vector<Vec3> before;
  for (int l = 0; l < 5; ++l) before.push_back(world.transform(world.linkBody(scene.table, l)).p);
  Real fastest = 0;
  for (int i = 0; i < 60; ++i) {
    world.step(dt);
    for (int l = 0; l < 5; ++l)
      fastest = std::max(fastest, world.linearVelocity(world.linkBody(scene.table, l)).norm());
  }
  Real drift = 0;
  for (int l = 0; l < 5; ++l)
    drift = std::max(
        drift, (world.transform(world.linkBody(scene.table, l)).p - before[std::size_t(l)]).norm());
  const art::Articulation<Real>& a = world.articulation(scene.table);
  EXPECT_NEAR(world.transform(world.linkBody(scene.table, 0)).p.y(), Table::height(), Real(0.01));
  EXPECT_LT(fastest, Real(1e-3));
  EXPECT_LT(drift, Real(1e-3));
  EXPECT_LT(a.qd().cwiseAbs().maxCoeff(), Real(1e-3));
}

INSTANTIATE_TEST_SUITE_P(SubstepsAndSolvers, LockedTable,
                         testing::Combine(testing::Values(4, 8),
                                          testing::Values(SolverType::SoftStep, SolverType::Pgs)));

TEST(WorldArticulations, RejectsBadSettingsAndLinkJoints) {
  World world;
  WorldArticulationSettings s = pendulum(1, 1, 0);
  s.shapes[0].link = 3;
  EXPECT_THROW(world.createArticulation(s), InvalidArgument);
  s = pendulum(1, 1, 0);
  s.q = art::VectorX<Real>::Zero(5);
  EXPECT_THROW(world.createArticulation(s), InvalidArgument);
  const ArticulationId p = world.createArticulation(pendulum(1, 1, 0));
  const BodyId b = world.createBody({});
  EXPECT_THROW(world.createJoint(BallJointSettings{.bodyA = b, .bodyB = world.linkBody(p, 0)}),
               InvalidArgument);
  EXPECT_EQ(world.rigidBodies().name(world.linkBody(p, 0)), "pendulum/l1");
  world.destroyArticulation(p);
  EXPECT_FALSE(world.isValid(p));
  EXPECT_EQ(world.bodyCount(), 1);
}
