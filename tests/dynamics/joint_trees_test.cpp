// The joint trees (src/dynamics/joint_trees.h) against their oracles: a hanging chain's anchors
// meeting to rounding, a free branching tree's momentum and centre of mass, and the
// projection's bound on how far a joint's anchors move in a substep.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "../step_constants.h"
#include "inertia/world/builders.h"
#include "inertia/world/world.h"

using namespace inertia;
using inertia::test::kDt;

namespace {

WorldSettings treeWorld() {
  WorldSettings s;
  s.sleeping = false;
  s.threads = 1;
  return s;
}

// The largest distance between a joint's two anchors (m).
Real worstJointError(const World& world, const std::vector<JointId>& joints) {
  Real worst = 0;
  for (JointId j : joints) worst = std::max(worst, world.rigidBodies().jointError(j).position);
  return worst;
}

}  // namespace

// A chain of plain ball joints is a joint tree (joint_trees.h): its joints are solved exactly
// together and its anchors projected after each position update, so at rest they meet to the
// rounding of float positions: a few ulps of the chain's 10 m (ulp(10 m) = 0.95 um; the
// anchors are each a pose applied to an arm). Solved one by one, the same chain sagged by
// 0.34 to 0.65 mm (Gauss-Seidel leaves the lower links' load short of the top joints).
TEST(JointTree, HangingChainMeetsItsAnchorsToRounding) {
  World world(treeWorld());
  const Chain c = addChain(world, {.links = 20, .top = Vec3(0, 10, 0)});
  for (int i = 0; i < 180; ++i) world.step(kDt);
  EXPECT_LT(worstJointError(world, c.joints), Real(4e-6));
}

namespace {

// A free star in zero gravity: a sphere with three chains of four capsules on ball joints
// (the sphere's three joints make the tree branch), every body set moving and turning.
struct Star {
  World world;
  std::vector<BodyId> bodies;
  std::vector<JointId> joints;
  Star() : world([] {
          WorldSettings s = treeWorld();
          s.gravity = Vec3::Zero();
          return s;
        }()) {
    const BodyId hub = world.createBody({.linearVelocity = Vec3(1, 0, 0)});
    world.addShape(hub, Sphere{Real(0.3)});
    bodies.push_back(hub);
    const Real half = Real(0.2), radius = Real(0.05), span = 2 * (half + radius);
    for (int arm = 0; arm < 3; ++arm) {
      const Real angle = Real(2 * std::numbers::pi) * Real(arm) / 3;
      const Vec3 dir(std::cos(angle), std::sin(angle), 0);
      const Quat along = Quat::FromTwoVectors(Vec3::UnitY(), dir);
      BodyId previous = hub;
      for (int i = 0; i < 4; ++i) {
        const Vec3 at = (Real(0.3) + span * (Real(i) + Real(0.5))) * dir;
        const BodyId link = world.createBody(
            {.position = at,
             .orientation = along,
             .linearVelocity = Vec3(Real(0.5) * Real(arm), Real(i), Real(1) - Real(arm)),
             .angularVelocity = Vec3(Real(i), Real(2) - Real(arm), Real(1))});
        world.addShape(link, Capsule{half, radius});
        const Vec3 joint = at - (half + radius) * dir;  // the link's end nearer the hub
        joints.push_back(world.createJoint(BallJointSettings{
            .bodyA = previous,
            .bodyB = link,
            .anchorA = world.transform(previous).inverse().apply(joint),
            .anchorB = Vec3(0, -(half + radius), 0)}));
        bodies.push_back(link);
        previous = link;
      }
    }
  }
  Vec3 momentum() const {
    Vec3 p = Vec3::Zero();
    for (BodyId b : bodies) p += world.rigidBodies().mass(b) * world.linearVelocity(b);
    return p;
  }
  Vec3 centreOfMass() const {
    Vec3 c = Vec3::Zero();
    Real m = 0;
    for (BodyId b : bodies) {
      c += world.rigidBodies().mass(b) * world.rigidBodies().centerOfMass(b);
      m += world.rigidBodies().mass(b);
    }
    return c / m;
  }
};

}  // namespace

// The joints' impulses and the projection's displacements are internal to the tree (each joint
// pushes its two bodies by M^-1 J^T lambda, equal and opposite), so a free tree keeps its
// momentum and its centre of mass moves in a straight line at P / M, to rounding (1e-5 of the
// momentum and of the 2.8 m the centre travels; measured 2e-7 and 1e-7 m), while its joints
// whip it about. With the branching hub's three joints factored exactly, the anchors stay
// closed to the rounding of float positions of a few metres (5 um is 20 ulps of 4 m; the
// projection's second-order remainder, drift^2 / arm with a drift of (w h)^2 r = 4e-5 m a
// substep, is 1e-8 m). Solved one by one, the same star's joints opened by 0.48 mm.
TEST(JointTree, FreeBranchingTreeKeepsItsMomentumAndItsJointsClosed) {
  Star star;
  const Vec3 p0 = star.momentum(), c0 = star.centreOfMass();
  Real mass = 0;
  for (BodyId b : star.bodies) mass += star.world.rigidBodies().mass(b);
  Real worst = 0;
  const int steps = 120;
  for (int i = 0; i < steps; ++i) {
    star.world.step(kDt);
    worst = std::max(worst, worstJointError(star.world, star.joints));
  }
  EXPECT_LT((star.momentum() - p0).norm(), Real(1e-5) * p0.norm());
  const Vec3 expected = c0 + (p0 / mass) * (Real(steps) * kDt);
  EXPECT_LT((star.centreOfMass() - expected).norm(), Real(1e-5) * (1 + (expected - c0).norm()));
  EXPECT_LT(worst, Real(5e-6));
}

// A tree's projection moves no joint's anchors more in a substep than its bias may
// (kMaxJointBias = 1000 m/s times the substep, 4.2 m at 1/240 s): a joint created between two
// bodies 1 km apart (anchors at their centres, so K is the inverse masses and one unclamped
// projection closes it to rounding) closes over many substeps, not at once. In the first
// step's four substeps the projection and the bias's velocity close at most 4 (4.2 + 4.2) =
// 33 m of it.
TEST(JointTree, ProjectionClosesAFarJointGradually) {
  World world([] {
    WorldSettings s = treeWorld();
    s.gravity = Vec3::Zero();
    return s;
  }());
  const BodyId a = world.createBody({.position = Vec3(0, -1, 0)});
  const BodyId b = world.createBody({.position = Vec3(1000, -1, 0)});
  world.addShape(a, Sphere{Real(0.2)});
  world.addShape(b, Sphere{Real(0.2)});
  world.createJoint(BallJointSettings{.bodyB = a, .anchorA = Vec3::Zero(), .anchorB = Vec3(0, 1, 0)});
  const JointId far = world.createJoint(BallJointSettings{
      .bodyA = a, .bodyB = b, .anchorA = Vec3::Zero(), .anchorB = Vec3::Zero()});
  world.step(kDt);
  const Real error = world.rigidBodies().jointError(far).position;
  EXPECT_TRUE(std::isfinite(error));
  EXPECT_GT(error, Real(1000 - 33));
}

