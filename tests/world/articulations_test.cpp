// Articulations in the World: links collide with bodies and the ground, their contacts solved in
// the bodies' substeps through the articulation's mass matrix. Checked against conservation of
// angular momentum about a pivot, the closed form of a plastic impact, a resting height, a
// static torque balance, and byte-identical results at 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <tuple>
#include <vector>

#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"
#include "inertia/core/math.h"
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

TEST(WorldArticulations, RejectsBadSettings) {
  World world;
  WorldArticulationSettings s = pendulum(1, 1, 0);
  s.shapes[0].link = 3;
  EXPECT_THROW(world.createArticulation(s), InvalidArgument);
  s = pendulum(1, 1, 0);
  s.q = art::VectorX<Real>::Zero(5);
  EXPECT_THROW(world.createArticulation(s), InvalidArgument);
  const ArticulationId p = world.createArticulation(pendulum(1, 1, 0));
  EXPECT_EQ(world.rigidBodies().name(world.linkBody(p, 0)), "pendulum/l1");
  world.destroyArticulation(p);
  EXPECT_FALSE(world.isValid(p));
  EXPECT_EQ(world.bodyCount(), 0);
}

// ---- Loops: ball joints on links (multibody_contacts.h) ------------------------------------

namespace {

// A crank of length a about z at the origin, a coupler of length b and a rocker of length c,
// revolute about z in a chain: uniform rods of mass m (inertia m l^2 / 12 across, a tenth of
// that along). Its rocker's tip is at (c, 0, 0) of its frame.
WorldArticulationSettings chain3(Real a, Real b, Real c, Real m) {
  WorldArticulationSettings s;
  s.name = "linkage";
  int parent = -1;
  Real offset = 0;
  for (const auto& [name, l] :
       {std::pair{"crank", a}, std::pair{"coupler", b}, std::pair{"rocker", c}}) {
    const Real across = m * l * l / 12;
    s.model.addLink(
        {.name = name,
         .parent = parent,
         .joint = {.type = art::JointType::Revolute,
                   .originPosition = Vec3(offset, 0, 0),
                   .axis = Vec3::UnitZ()},
         .inertia = {m, Vec3(l / 2, 0, 0), Vec3(across / 10, across, across).asDiagonal()}});
    parent = s.model.linkCount() - 1;
    offset = l;
  }
  return s;
}

// The rod of `rod` whose tip at (L1, 0, 0) carries a sphere of radius r and mass m2 at L2 beyond
// it: as a second link on a spherical joint (`tree`), or as a free body on a ball joint.
WorldArticulationSettings rodAndSphere(bool tree, Real L1, Real m1, Real L2, Real m2, Real r) {
  WorldArticulationSettings s;
  s.name = "rod";
  const Real across = m1 * L1 * L1 / 12;
  s.model.addLink(
      {.name = "rod",
       .joint = {.type = art::JointType::Revolute, .axis = Vec3::UnitZ()},
       .inertia = {m1, Vec3(L1 / 2, 0, 0), Vec3(across / 10, across, across).asDiagonal()}});
  if (tree)
    s.model.addLink({.name = "sphere",
                     .parent = 0,
                     .joint = {.type = art::JointType::Spherical, .originPosition = Vec3(L1, 0, 0)},
                     .inertia = {m2, Vec3(L2, 0, 0), Mat3::Identity() * (Real(0.4) * m2 * r * r)}});
  return s;
}

}  // namespace

// A sphere hung from a rod's tip by a ball joint is a double pendulum; so is the same sphere as
// a second link of the rod's tree on a spherical joint. Independent implementations (maximal
// coordinates with a soft point constraint through the rod's articulated response; reduced
// coordinates) of one motion, released from horizontal. Both are first order in the step (the
// tree's response to the joint is made once per step), so they agree to O(dt): over 1 s of the
// swing, measured 2.08 cm at dt 1/60 s and 0.53 cm at 1/240 s, 4 substeps each (the ratio,
// 3.9, is the first order). Asserted: within 3 cm at 1/60 s, and at least 2.5 times closer at
// 1/240 s.
TEST(WorldArticulations, SphereOnABallJointSwingsAsTheTreeWithASphericalJoint) {
  const Real L1 = 1, m1 = 2, L2 = Real(0.6), m2 = 1, r = Real(0.1);
  double gap[2] = {0, 0};
  for (int pass = 0; pass < 2; ++pass) {
    const int substeps = 4, steps = pass == 0 ? 60 : 240;
    World tree({.substeps = substeps, .threads = 1});
    const ArticulationId t = tree.createArticulation(rodAndSphere(true, L1, m1, L2, m2, r));
    World hung({.substeps = substeps, .threads = 1});
    const ArticulationId h = hung.createArticulation(rodAndSphere(false, L1, m1, L2, m2, r));
    const BodyId sphere = hung.createBody({.position = Vec3(L1 + L2, 0, 0)});
    const Real volume = Real(4.0 / 3.0 * 3.14159265358979) * r * r * r;
    hung.addShape(sphere, Sphere{r}, Material{.density = m2 / volume});
    hung.createJoint(BallJointSettings{.bodyA = hung.linkBody(h, 0),
                                       .bodyB = sphere,
                                       .anchorA = Vec3(L1, 0, 0),
                                       .anchorB = Vec3(-L2, 0, 0)});
    Real lowest = 0;
    for (int i = 0; i < steps; ++i) {
      tree.step(Real(1) / Real(steps));
      hung.step(Real(1) / Real(steps));
      const Vec3 a = tree.transform(tree.linkBody(t, 1)).apply(Vec3(L2, 0, 0));
      const Vec3 b = hung.transform(sphere).p;
      ASSERT_TRUE(b.allFinite()) << "step " << i << " substeps " << substeps;
      gap[pass] = std::max(gap[pass], double((a - b).norm()));
      lowest = std::min(lowest, b.y());
    }
    // It swung: the sphere passed well below the pivot.
    EXPECT_LT(lowest, -Real(1)) << substeps;
  }
  std::printf("tree vs ball joint: %.4f m at dt 1/60 s, %.4f m at 1/240 s\n", gap[0], gap[1]);
  EXPECT_LT(gap[0], 0.03);
  EXPECT_LT(gap[1] * 2.5, gap[0]);
}

// A parallelogram four-bar linkage: crank and rocker of length a, coupler and ground of length
// b, closed by a ball joint from the rocker's tip to the world at (b, 0, 0). The tree alone
// would fold (its coupler swings); closed, it keeps one degree of freedom, whose kinematics are
// exact: the coupler stays parallel to the ground (absolute angle q1 + q2 = 0) and the closure
// stays shut. It swings under gravity for 2 s from 1 rad off hanging, so its bars never line up
// (where a parallelogram may flip into its crossed branch). Asserted: the closure within 1 mm
// (the soft rows' sag under the links' weight, g / (2 pi f)^2 = 0.07 mm at the joints' 60 Hz,
// plus O(h) drift), the coupler within 2 mrad of level (that gap over the crank's length); and
// without the closure the coupler tilts by half a radian and more.
TEST(WorldArticulations, FourBarLinkageClosedByABallJointKeepsItsKinematics) {
  const Real pi = Real(3.14159265358979);
  const Real a = Real(0.5), b = 1, m = 1, theta = -pi / 2 + 1;
  for (bool closed : {true, false}) {
    World world({.threads = 1});
    WorldArticulationSettings s = chain3(a, b, a, m);
    s.q = art::VectorX<Real>(3);
    s.q << theta, -theta, theta + pi;
    const ArticulationId id = world.createArticulation(s);
    JointId closure;
    if (closed)
      closure = world.createJoint(BallJointSettings{
          .bodyB = world.linkBody(id, 2), .anchorA = Vec3(b, 0, 0), .anchorB = Vec3(a, 0, 0)});
    Real worstGap = 0, worstTilt = 0, lowest = theta;
    for (int i = 0; i < 120; ++i) {
      world.step(Real(1) / 60);
      const art::Articulation<Real>& art = world.articulation(id);
      worstTilt = std::max(worstTilt, std::abs(art.q()(0) + art.q()(1)));
      lowest = std::min(lowest, art.q()(0));
      if (closed) worstGap = std::max(worstGap, world.rigidBodies().jointError(closure).position);
    }
    if (closed) {
      std::printf("four-bar: closure %.2e m, coupler tilt %.2e rad\n", double(worstGap),
                  double(worstTilt));
      EXPECT_LT(worstGap, Real(1e-3));
      EXPECT_LT(worstTilt, Real(2e-3));
      EXPECT_LT(lowest, -pi / 2 - Real(0.5));  // it swung through the bottom
    } else {
      EXPECT_GT(worstTilt, Real(0.5));
    }
  }
}

// What a link may not be joined by: a joint with limits, a motor, a spring or friction (only a
// joint's locked rows go through the tree's response). Any joint's locked rows between links of
// two trees, or of one, are a loop and are accepted. A joint that breaks lets go of its link.
TEST(WorldArticulations, LinkJointsTakeLockedRowsAndBreak) {
  World world({.threads = 1});
  const ArticulationId p = world.createArticulation(pendulum(1, 1, 0));
  const ArticulationId q = world.createArticulation(chain3(1, 1, 1, 1));
  const BodyId link = world.linkBody(p, 0);
  const BodyId box = world.createBody({.position = Vec3(0, -1, 0)});
  world.addShape(box, Box{Vec3::Constant(Real(0.1))});
  const auto refused = [](auto&& create, const char* field) {
    try {
      create();
      ADD_FAILURE() << "accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  refused(
      [&] {
        world.createJoint(HingeJointSettings{
            .bodyA = box, .bodyB = link, .limits = JointLimits{.lower = -1, .upper = 1}});
      },
      "HingeJointSettings::bodyB is an articulation's link");
  refused(
      [&] { world.createJoint(BallJointSettings{.bodyA = link, .bodyB = box, .coneLimit = 1}); },
      "BallJointSettings::bodyA is an articulation's link");
  refused(
      [&] {
        world.createJoint(
            WeldJointSettings{.bodyA = link, .bodyB = box, .spring = JointSpring{.frequency = 2}});
      },
      "WeldJointSettings::bodyA is an articulation's link");
  // Nor can one be given them later: the change is refused and undone.
  const JointId hinge = world.createJoint(HingeJointSettings{.bodyA = box, .bodyB = link});
  refused([&] { world.rigidBodies().setJointLimits(hinge, JointLimits{.lower = -1, .upper = 1}); },
          "setJointLimits: the joint joins an articulation's link");
  refused([&] { world.rigidBodies().setJointMotor(hinge, JointMotor{.speed = 1, .maxForce = 1}); },
          "setJointMotor: the joint joins an articulation's link");
  world.destroyJoint(hinge);
  // The chain's rocker tip (3, 0, 0) held to the pendulum's link at the same point.
  world.createJoint(BallJointSettings{.bodyA = link,
                                      .bodyB = world.linkBody(q, 2),
                                      .anchorA = Vec3(3, 0, 0),
                                      .anchorB = Vec3(1, 0, 0)});
  // The box hangs 1 m below the pendulum's pivot (which cannot move) by a joint that holds
  // 5 N: its 8 kg weigh 78 N.
  const JointId weak = world.createJoint(BallJointSettings{.bodyA = link,
                                                           .bodyB = box,
                                                           .anchorA = Vec3::Zero(),
                                                           .anchorB = Vec3(0, 1, 0),
                                                           .breakForce = 5});
  world.step(Real(1) / 60);
  EXPECT_TRUE(world.rigidBodies().isJointBroken(weak));
  ASSERT_EQ(world.rigidBodies().jointEvents().size(), 1u);
  EXPECT_GT(world.rigidBodies().jointEvents()[0].force.norm(), 5);
}

namespace {

// chain3's crank of length 2 and coupler and rocker of length 1 with their joints at 2 pi / 3:
// an equilateral triangle on the crank's outer half, whose rocker tip meets the crank's middle.
// `rigid`: the coupler's and rocker's joints fixed at those angles, one rigid body.
WorldArticulationSettings triangle(bool rigid) {
  const Real turn = Real(2 * 3.14159265358979 / 3);
  WorldArticulationSettings s = chain3(2, 1, 1, 1);
  if (rigid) {
    art::Model<Real> model;
    for (int i = 0; i < 3; ++i) {
      const art::Link<Real>& l = s.model.link(i);
      art::JointSettings<Real> joint{
          .type = art::JointType::Revolute, .originPosition = l.Xtree.r, .axis = Vec3::UnitZ()};
      if (i > 0) {
        joint.type = art::JointType::Fixed;
        joint.originOrientation = Quat(Eigen::AngleAxis<Real>(turn, Vec3::UnitZ()));
      }
      const Vec3 c = l.centerOfMass;
      const Mat3 Ic = l.I.topLeftCorner<3, 3>() + l.mass * skew(c) * skew(c);
      model.addLink(
          {.name = l.name, .parent = l.parent, .joint = joint, .inertia = {l.mass, c, Ic}});
    }
    s.model = model;
    s.q = art::VectorX<Real>::Zero(1);
  } else {
    s.q = art::VectorX<Real>(3);
    s.q << 0, turn, turn;
  }
  return s;
}

}  // namespace

// A loop within one tree: chain3's rocker tip joined by a ball joint to its own crank's middle
// closes a rigid triangle, which must swing about the crank's pivot as the same three rods
// welded (the tree's coupler and rocker joints fixed): a loop closed in maximal coordinates
// against reduced ones. The joint's rows act between two links of one branch, so their
// effective mass needs the tree's cross response (J_a H^-1 J_b^T). Released from horizontal
// under gravity for 1 s, at dt 1/60 s and 1/240 s. What separates the two is the closure's give:
// its soft rows (120 Hz) yield under the swing's load by about 0.1 mm, 1e-4 rad over the 1 m
// bars (measured: crank 1e-5 and 4e-5 rad, triangle's angles 1e-4 rad); bound 1e-3 rad on the
// crank's angle and on the triangle's. With pgs and one iteration a step, the closure's rows
// are one Gauss-Seidel pass with their effective mass: exact, it sets the anchors' relative
// velocity to zero, which for a rigid triangle stops the coupler's and rocker's joints, so the
// triangle's angles change by rounding only (measured 5e-7 rad; 1e-5 with the cross term left
// out); bound 2e-6 rad.
TEST(WorldArticulations, LoopWithinOneTreeSwingsAsTheWeldedTree) {
  const Real turn = Real(2 * 3.14159265358979 / 3);
  double gap[2] = {0, 0}, shape[2] = {0, 0};
  double rigidShape = 0;
  for (int pass = 0; pass < 3; ++pass) {
    const int steps = pass == 1 ? 240 : 60;
    SolverSettings solver;
    if (pass == 2) solver = {.type = SolverType::Pgs, .iterations = 1, .relaxIterations = 0};
    World loop({.solver = solver, .threads = 1});
    const ArticulationId l = loop.createArticulation(triangle(false));
    const JointId closure = loop.createJoint(BallJointSettings{.bodyA = loop.linkBody(l, 0),
                                                               .bodyB = loop.linkBody(l, 2),
                                                               .anchorA = Vec3(1, 0, 0),
                                                               .anchorB = Vec3(1, 0, 0)});
    World welded({.threads = 1});
    const ArticulationId w = welded.createArticulation(triangle(true));
    Real lowest = 0;
    for (int i = 0; i < steps; ++i) {
      loop.step(Real(1) / Real(steps));
      welded.step(Real(1) / Real(steps));
      const art::VectorX<Real>& q = loop.articulation(l).q();
      ASSERT_TRUE(q.allFinite()) << "step " << i;
      lowest = std::min(lowest, q(0));
      if (pass == 2) {
        rigidShape =
            std::max(rigidShape, double(std::max(std::abs(q(1) - turn), std::abs(q(2) - turn))));
        continue;
      }
      gap[pass] = std::max(gap[pass], double(std::abs(q(0) - welded.articulation(w).q()(0))));
      shape[pass] =
          std::max(shape[pass], double(std::max(std::abs(q(1) - turn), std::abs(q(2) - turn))));
    }
    EXPECT_FALSE(loop.rigidBodies().isJointBroken(closure));
    EXPECT_LT(lowest, Real(-1)) << "it swung down";
  }
  std::printf(
      "loop in one tree vs welded: crank %.2e rad at 1/60 s, %.2e at 1/240 s; shape "
      "%.2e, %.2e rad; pgs, one iteration: shape %.2e rad\n",
      gap[0], gap[1], shape[0], shape[1], rigidShape);
  EXPECT_LT(rigidShape, 2e-6);
  for (int pass = 0; pass < 2; ++pass) {
    EXPECT_LT(gap[pass], 1e-3) << pass;
    EXPECT_LT(shape[pass], 1e-3) << pass;
  }
}

namespace {

// A floating 1 x 0.2 x 0.2 m box with an arm (a 0.4 m capsule) hinged about z at its +x end,
// standing up, held there by its limits (both 0), and a forearm (a 0.6 m capsule) hinged about z at
// the arm's tip, folded back over the box, 0.25 m above its top, and swinging down at w rad/s.
// Capsules lie along their links' y, radius 0.05 m; rods' inertias (m l^2 / 12 across).
constexpr Real kForearmRadius = Real(0.05);

WorldArticulationSettings foldingArm(bool selfCollision, Real w) {
  WorldArticulationSettings s;
  s.name = "folding";
  s.selfCollision = selfCollision;
  const auto rod = [](Real m, Real l) {
    const Real across = m * l * l / 12;
    return art::LinkInertia<Real>{m, Vec3(0, l / 2, 0),
                                  Vec3(across, m * Real(0.00125), across).asDiagonal()};
  };
  s.model.addLink(
      {.name = "box",
       .joint = {.type = art::JointType::Floating},
       .inertia = {2, Vec3::Zero(), Vec3(Real(0.0133), Real(0.1733), Real(0.1733)).asDiagonal()}});
  s.model.addLink({.name = "arm",
                   .parent = 0,
                   .joint = {.type = art::JointType::Revolute,
                             .originPosition = Vec3(Real(0.5), 0, 0),
                             .axis = Vec3::UnitZ(),
                             .lower = 0,
                             .upper = 0},
                   .inertia = rod(Real(0.5), Real(0.4))});
  s.model.addLink({.name = "forearm",
                   .parent = 1,
                   .joint = {.type = art::JointType::Revolute,
                             .originPosition = Vec3(0, Real(0.4), 0),
                             .axis = Vec3::UnitZ()},
                   .inertia = rod(Real(0.75), Real(0.6))});
  s.shapes.push_back({.link = 0, .shape = Box{Vec3(Real(0.5), Real(0.1), Real(0.1))}});
  s.shapes.push_back({.link = 1,
                      .shape = Capsule{kForearmRadius, Real(0.15)},
                      .pose = {Vec3(0, Real(0.2), 0), Quat::Identity()}});
  s.shapes.push_back({.link = 2,
                      .shape = Capsule{kForearmRadius, Real(0.25)},
                      .pose = {Vec3(0, Real(0.3), 0), Quat::Identity()}});
  s.q = s.model.neutralConfiguration();
  s.q(1) = Real(0.1005);  // the box 0.5 mm above the ground
  s.q(8) = Real(3.14159265358979 / 2);
  s.qd = art::VectorX<Real>::Zero(s.model.nv());
  s.qd(7) = w;
  return s;
}

// How deep the forearm's capsule reaches below the box's top face (m; negative: above it),
// over the face: its core segment's ends in the box's frame.
Real forearmDepth(const World& world, ArticulationId id) {
  const Transform box = world.transform(world.linkBody(id, 0));
  const Transform forearm = world.transform(world.linkBody(id, 2));
  Real depth = -1;
  for (Real y : {Real(0.05), Real(0.55)}) {
    const Vec3 end = box.applyInverse(forearm.apply(Vec3(0, y, 0)));
    if (std::abs(end.x()) < Real(0.5))
      depth = std::max(depth, Real(0.1) - (end.y() - kForearmRadius));
  }
  return depth;
}

}  // namespace

// Self-collision: the forearm of a folding arm on a floating box swings down onto the box (two
// links apart) and rests on it; the box lies on the ground, so both links of the contact move
// and answer through the tree (pairResponse's cross term). At rest the forearm's far cap lies on
// the box's top: its core segment's end, 0.55 m from the hinge 0.25 m above the top, sits one
// radius above it, so the forearm hangs at asin(0.25 / 0.55) below horizontal, a joint angle of
// pi/2 + that. The contact between two moving links is soft at 60 Hz: under the forearm's
// load it gives g / (2 pi 60)^2 = 0.07 mm, 1.3e-4 rad at that lever; the bound, 2e-3 rad, also
// holds the give of the arm's limits (asserted within it too). While it lands it may sink by at
// most a fifth of its radius (1 cm; speculative contacts stop it at the surface). Without
// self-collision the forearm passes into the box, deeper than its radius: the test can fail.
TEST(WorldArticulations, SelfCollisionRestsAFoldingArmOnItsOwnBase) {
  Real depth[2] = {-1, -1};
  for (bool self : {true, false}) {
    World world({.threads = 1});
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0});
    const ArticulationId id = world.createArticulation(foldingArm(self, 3));
    const art::Articulation<Real>& a = world.articulation(id);
    for (int i = 0; i < 120; ++i) {
      world.step(Real(1) / 60);
      ASSERT_TRUE(a.q().allFinite() && a.qd().allFinite()) << "step " << i;
      depth[self] = std::max(depth[self], forearmDepth(world, id));
    }
    if (self) {
      const Real rest = Real(3.14159265358979 / 2) + std::asin(Real(0.25) / Real(0.55));
      std::printf(
          "folding arm at rest: forearm %.5f rad (closed form %.5f), arm %.2e rad, "
          "speeds %.2e\n",
          double(a.q()(8)), double(rest), double(a.q()(7)), double(a.qd().cwiseAbs().maxCoeff()));
      EXPECT_NEAR(a.q()(8), rest, Real(2e-3));
      EXPECT_NEAR(a.q()(7), 0, Real(2e-3));
      EXPECT_LT(a.qd().cwiseAbs().maxCoeff(), Real(1e-2));
    }
  }
  std::printf("folding arm: deepest %.4f m with self-collision, %.4f without\n", double(depth[1]),
              double(depth[0]));
  EXPECT_LT(depth[1], kForearmRadius / 5);
  EXPECT_GT(depth[0], kForearmRadius);
}

// A hinge closes the parallelogram four-bar as the ball joint above does: its locked rows (the
// anchors, and the two angular rows keeping its axis along z) go through the tree's response;
// the angular rows and the out-of-plane anchor row are redundant with the tree's z hinges
// (K singular there; its pseudo-inverse leaves them alone). The same bounds as the ball joint's.
TEST(WorldArticulations, FourBarLinkageClosedByAHingeKeepsItsKinematics) {
  const Real pi = Real(3.14159265358979);
  const Real a = Real(0.5), b = 1, theta = -pi / 2 + 1;
  World world({.threads = 1});
  WorldArticulationSettings s = chain3(a, b, a, 1);
  s.q = art::VectorX<Real>(3);
  s.q << theta, -theta, theta + pi;
  const ArticulationId id = world.createArticulation(s);
  const JointId closure = world.createJoint(HingeJointSettings{
      .bodyB = world.linkBody(id, 2), .anchorA = Vec3(b, 0, 0), .anchorB = Vec3(a, 0, 0)});
  Real worstGap = 0, worstTilt = 0, lowest = theta;
  for (int i = 0; i < 120; ++i) {
    world.step(Real(1) / 60);
    const art::Articulation<Real>& art = world.articulation(id);
    ASSERT_TRUE(art.q().allFinite()) << "step " << i;
    worstTilt = std::max(worstTilt, std::abs(art.q()(0) + art.q()(1)));
    lowest = std::min(lowest, art.q()(0));
    worstGap = std::max(worstGap, world.rigidBodies().jointError(closure).position);
  }
  std::printf("four-bar on a hinge: closure %.2e m, coupler tilt %.2e rad\n", double(worstGap),
              double(worstTilt));
  EXPECT_LT(worstGap, Real(1e-3));
  EXPECT_LT(worstTilt, Real(2e-3));
  EXPECT_LT(lowest, -pi / 2 - Real(0.5));
}

namespace {

// A rod of length 1 m and mass 1 kg on a z hinge at the origin, as a one-link tree.
WorldArticulationSettings rodOf(Real mass, const Vec3& com, const Mat3& inertia) {
  WorldArticulationSettings s;
  s.name = "rod";
  s.model.addLink({.name = "rod",
                   .joint = {.type = art::JointType::Revolute, .axis = Vec3::UnitZ()},
                   .inertia = {mass, com, inertia}});
  return s;
}

}  // namespace

// A box welded to a pendulum's link is part of the link: the pendulum swings as one link that
// carries the box's mass properties too (reduced coordinates alone), released from horizontal
// for 1 s. The weld's six locked rows go through the tree's response, made once per step at its
// start (as for the sphere on a ball joint above): within a step the link turns by w h (0.08 rad
// at 5 rad/s and 1/60 s), and the heavy box (8 kg on a 1 kg rod) lags the one-link swing by an
// amount first order in the step. Measured: 0.056 rad at 1/60 s, 0.015 at 1/240 s (ratio 3.8),
// 0.0039 at 1/960 s. Asserted: within 0.08 rad at 1/60 s and at least 2.5 times closer at
// 1/240 s. The box keeps its place on the link within 3 mm at 1/60 s and 1 mm at 1/240 s
// (measured 2.1 and 0.4 mm) and its orientation within 2e-3 rad (the soft rows' give, 1e-3).
TEST(WorldArticulations, BodyWeldedToALinkSwingsAsPartOfIt) {
  const Real L = 1, m1 = 1, half = Real(0.1), density = 1000;
  const Real m2 = density * 8 * half * half * half;  // 8 kg
  const Mat3 I2 = Mat3::Identity() * (m2 / 3 * 2 * half * half);
  const Vec3 c1(L / 2, 0, 0), c2(L, 0, 0);
  const Mat3 I1 = Vec3(m1 * L * L / 120, m1 * L * L / 12, m1 * L * L / 12).asDiagonal();
  // The combined link: both about the joint's origin, then about the joint centre of mass.
  const Real M = m1 + m2;
  const Vec3 c = (m1 * c1 + m2 * c2) / M;
  const Mat3 Io = I1 - m1 * skew(c1) * skew(c1) + I2 - m2 * skew(c2) * skew(c2);
  double gap[2] = {0, 0}, drift[2] = {0, 0}, turn[2] = {0, 0};
  for (int pass = 0; pass < 2; ++pass) {
    const int steps = pass == 0 ? 60 : 240;
    World welded({.threads = 1});
    const ArticulationId w = welded.createArticulation(rodOf(m1, c1, I1));
    const BodyId box = welded.createBody({.position = c2});
    welded.addShape(box, Box{Vec3::Constant(half)}, Material{.density = density});
    ASSERT_NEAR(welded.rigidBodies().mass(box), m2, m2 * Real(1e-5));
    welded.createJoint(
        WeldJointSettings{.bodyA = welded.linkBody(w, 0), .bodyB = box, .anchorA = c2});
    World one({.threads = 1});
    const ArticulationId o = one.createArticulation(rodOf(M, c, Io + M * skew(c) * skew(c)));
    Real lowest = 0;
    for (int i = 0; i < steps; ++i) {
      welded.step(Real(1) / Real(steps));
      one.step(Real(1) / Real(steps));
      const Real q = welded.articulation(w).q()(0);
      ASSERT_TRUE(std::isfinite(q)) << "step " << i;
      gap[pass] = std::max(gap[pass], double(std::abs(q - one.articulation(o).q()(0))));
      const Transform link = welded.transform(welded.linkBody(w, 0));
      const Transform b = welded.transform(box);
      drift[pass] = std::max(drift[pass], double((b.p - link.apply(c2)).norm()));
      turn[pass] =
          std::max(turn[pass], double(2 * std::acos(std::min(Real(1), std::abs(link.q.dot(b.q))))));
      lowest = std::min(lowest, q);
    }
    EXPECT_LT(lowest, Real(-1)) << "it swung down";
  }
  std::printf(
      "welded box: swing %.2e rad (1/60 s) and %.2e (1/240 s) from the one-link "
      "pendulum; box %.2e and %.2e m, %.2e and %.2e rad off its place\n",
      gap[0], gap[1], drift[0], drift[1], turn[0], turn[1]);
  EXPECT_LT(gap[0], 0.08);
  EXPECT_LT(gap[1] * 2.5, gap[0]);
  EXPECT_LT(drift[0], 3e-3);
  EXPECT_LT(drift[1], 1e-3);
  EXPECT_LT(std::max(turn[0], turn[1]), 2e-3);
}

// A 1 mm box welded to a pendulum's tip stays there. Its linear rows (1/m = 1e6 per kg) and
// angular ones (6 / (m e^2) = 6e12) differ by e^2 / 6; unscaled, the linear ones fell under the
// pseudo-inverse's relative cut (1e-6), and the box fell away from the tip. What remains is the
// lag of a response made once per step behind a tip moving at up to 4 m/s: first order in the
// step (measured 3.1 mm at 1/60 s, 0.57 mm at 1/240 s). Asserted: within 5 mm at 1/60 s and at
// least 2.5 times closer at 1/240 s.
TEST(WorldArticulations, TinyBodyWeldedToALinkStaysInPlace) {
  const Vec3 tip(1, 0, 0);
  double worst[2] = {0, 0};
  for (int pass = 0; pass < 2; ++pass) {
    const int steps = pass == 0 ? 60 : 240;
    World world({.threads = 1});
    const ArticulationId rod = world.createArticulation(
        rodOf(1, Vec3(Real(0.5), 0, 0), Vec3(Real(0.01), Real(0.1), Real(0.1)).asDiagonal()));
    const BodyId bead = world.createBody({.position = tip});
    world.addShape(bead, Box{Vec3::Constant(Real(0.0005))}, Material{.density = 1000});
    world.createJoint(
        WeldJointSettings{.bodyA = world.linkBody(rod, 0), .bodyB = bead, .anchorA = tip});
    for (int i = 0; i < steps; ++i) {
      world.step(Real(1) / Real(steps));
      const Vec3 place = world.transform(world.linkBody(rod, 0)).apply(tip);
      worst[pass] = std::max(worst[pass], double((world.transform(bead).p - place).norm()));
    }
  }
  std::printf("1 mm box welded to a link: %.2e m off its place at 1/60 s, %.2e at 1/240 s\n",
              worst[0], worst[1]);
  EXPECT_LT(worst[0], 5e-3);
  EXPECT_LT(worst[1] * 2.5, worst[0]);
}
