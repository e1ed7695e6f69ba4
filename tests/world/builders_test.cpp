// The shared scene builders: counts, touching placements, seeded randomness; the jointed ones'
// physics.
#include "inertia/world/builders.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include "../step_constants.h"
#include "inertia/core/error.h"

using namespace inertia;
using inertia::test::kDt;
using inertia::test::kG;

TEST(Builders, PyramidRowsTouch) {
  const auto boxes = pyramid({.base = 40});
  ASSERT_EQ(boxes.size(), 820u);  // 40 * 41 / 2, the peer benchmark's pyramid
  // Row r's boxes rest on row r-1: centres at (2 r + 1) h, neighbours 2 h apart.
  EXPECT_FLOAT_EQ(boxes[0].settings.position.y(), Real(0.5));
  EXPECT_FLOAT_EQ(boxes[1].settings.position.x() - boxes[0].settings.position.x(), 1);
  EXPECT_FLOAT_EQ(boxes.back().settings.position.y(), Real(0.5) * 79);
  EXPECT_FLOAT_EQ(boxes.back().settings.position.x(), 0);
}

TEST(Builders, TowerWallAndGridPlacement) {
  const auto t = tower({.height = 3, .halfExtents = Vec3(1, Real(0.25), 1)});
  ASSERT_EQ(t.size(), 3u);
  EXPECT_FLOAT_EQ(t[2].settings.position.y(), Real(1.25));
  const auto w = wall({.rows = 2, .columns = 4});
  ASSERT_EQ(w.size(), 8u);
  EXPECT_FLOAT_EQ(w[4].settings.position.x() - w[0].settings.position.x(), Real(0.5));  // staggered
  const auto g = grid({.counts = {2, 3, 4}, .spacing = Vec3(1, 2, 3)});
  ASSERT_EQ(g.size(), 24u);
  EXPECT_TRUE(g.back().settings.position.isApprox(Vec3(1, 4, 9)));
}

TEST(Builders, RainIsSeededAndInsideItsBox) {
  const RainSettings s{.count = 500, .lower = Vec3(-1, 2, -3), .upper = Vec3(1, 4, 3), .seed = 9};
  const auto a = rain(s), b = rain(s);
  auto other = s;
  other.seed = 10;
  const auto c = rain(other);
  ASSERT_EQ(a.size(), 500u);
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3& p = a[i].settings.position;
    EXPECT_TRUE((p.array() >= s.lower.array()).all() && (p.array() <= s.upper.array()).all());
    EXPECT_NEAR(a[i].settings.orientation.norm(), 1, 1e-5);
    EXPECT_EQ(p, b[i].settings.position);
    differs = differs || p != c[i].settings.position;
  }
  EXPECT_TRUE(differs);
}

TEST(Builders, BadSettingsThrow) {
  EXPECT_THROW(pyramid({.base = 0}), InvalidArgument);
  EXPECT_THROW(rain({.lower = Vec3(1, 1, 1), .upper = Vec3(0, 0, 0)}), InvalidArgument);
  EXPECT_THROW(grid({.spacing = Vec3(std::numeric_limits<Real>::quiet_NaN(), 1, 1)}), InvalidArgument);
}

// The jointed builders: counts, every joint satisfied where it is built, and the physics each is
// for (a pendulum's swing, a chain's energy, a ragdoll coming to rest within its joints' limits,
// a bridge hanging as the discrete catenary and breaking only above the catenary's tension).

namespace {

Real worstPositionError(const World& world) {
  Real worst = 0;
  for (JointId j : world.rigidBodies().joints())
    worst = std::max(worst, world.rigidBodies().jointError(j).position);
  return worst;
}

bool finiteState(const World& world) {
  for (BodyId b : world.rigidBodies().bodies()) {
    const Transform x = world.transform(b);
    if (!x.p.allFinite() || !x.q.coeffs().allFinite() || !world.linearVelocity(b).allFinite() ||
        !world.angularVelocity(b).allFinite())
      return false;
  }
  return true;
}

// Kinetic plus gravitational potential energy of the dynamic bodies (J), gravity -g along y.
double mechanicalEnergy(const World& world) {
  double e = world.rigidBodies().kineticEnergy();
  for (BodyId b : world.rigidBodies().bodies())
    e += double(world.rigidBodies().mass(b)) * kG * double(world.rigidBodies().centerOfMass(b).y());
  return e;
}

}  // namespace

TEST(JointBuilders, CountsAndEveryJointSatisfiedWhereBuilt) {
  World world;
  const Pendulum hinge = addPendulum(world, {.angle = 1});
  const Pendulum ball = addPendulum(world, {.pivot = Vec3(3, 2, 0),
                                            .angle = Real(0.5),
                                            .axis = Vec3(1, 0, 1),
                                            .joint = JointType::Ball});
  const Chain hung = addChain(
      world,
      {.links = 12, .top = Vec3(5, 10, 0), .direction = Vec3(1, -1, Real(0.5)), .endMass = 10});
  const Chain loose = addChain(world, {.links = 3, .top = Vec3(-5, 10, 0), .hangFromWorld = false});
  const RopeBridge balls = addRopeBridge(world, {.planks = 15, .center = Vec3(0, 20, 0)});
  const RopeBridge hinges = addRopeBridge(
      world,
      {.planks = 15, .center = Vec3(0, 20, 10), .slack = Real(0.2), .joint = JointType::Hinge});
  const Ragdoll doll = addRagdoll(
      world, {.position = Vec3(10, 3, 0),
              .orientation = Quat(Eigen::AngleAxis<Real>(Real(0.7), Vec3(1, 2, 3).normalized())),
              .scale = Real(1.2)});
  const AssemblyIds grid =
      addAssembly(world, jointGrid({.rows = 4, .columns = 5, .top = Vec3(0, 30, 0), .pinned = 1}));

  EXPECT_TRUE(world.isValid(hinge.bob) && world.isValid(ball.joint));
  EXPECT_EQ(hung.links.size(), 12u);
  EXPECT_EQ(hung.joints.size(), 13u);  // the world's, 11 between links, the end sphere's
  EXPECT_TRUE(world.isValid(hung.end));
  EXPECT_FLOAT_EQ(world.rigidBodies().mass(hung.end), 10);
  EXPECT_EQ(loose.joints.size(), 2u);
  EXPECT_TRUE(loose.end.isNull());
  EXPECT_EQ(balls.planks.size(), 15u);
  EXPECT_EQ(balls.joints.size(), 32u);  // two on each of the 16 seams
  EXPECT_EQ(hinges.joints.size(), 16u);
  EXPECT_EQ(world.rigidBodies().type(balls.leftPost), BodyType::Static);
  for (BodyId b : doll.parts) EXPECT_TRUE(world.isValid(b));
  EXPECT_EQ(doll.joints.size(), 10u);
  EXPECT_EQ(grid.bodies.size(), 20u);
  EXPECT_EQ(grid.joints.size(), 4u * 4 + 3 * 5 + 1);
  EXPECT_EQ(world.bodyCount(), 2 + 13 + 3 + 17 + 17 + 11 + 20);
  EXPECT_EQ(world.rigidBodies().jointCount(), 2 + 13 + 2 + 32 + 16 + 10 + 32);

  // Float positions some 20 m from the origin carry about 2e-6 m of rounding.
  for (JointId j : world.rigidBodies().joints()) {
    const JointError e = world.rigidBodies().jointError(j);
    EXPECT_LT(e.position, Real(1e-5)) << world.rigidBodies().jointName(j);
    EXPECT_LT(e.angle, Real(1e-5)) << world.rigidBodies().jointName(j);
    if (world.rigidBodies().jointType(j) == JointType::Hinge) {
      EXPECT_NEAR(world.rigidBodies().jointCoordinate(j), 0, Real(1e-5));
    }
  }
  // The ragdoll's documented build: 1.73 m tall and about 70 kg at scale 1.
  World one;
  const Ragdoll unit = addRagdoll(one, {});
  Real mass = 0;
  for (BodyId b : unit.parts) mass += one.rigidBodies().mass(b);
  EXPECT_NEAR(mass, 70, 1);
  const Transform head = one.transform(unit.part(RagdollPart::Head));
  const Transform shin = one.transform(unit.part(RagdollPart::LowerLegLeft));
  EXPECT_NEAR(head.p.y() + Real(0.1) - (shin.p.y() - Real(0.21)), Real(1.73), Real(1e-4));
}

TEST(JointBuilders, BadSettingsThrow) {
  World world;
  EXPECT_THROW(addChain(world, {.links = 0}), InvalidArgument);
  EXPECT_THROW(addChain(world, {.direction = Vec3::Zero()}), InvalidArgument);
  EXPECT_THROW(addPendulum(world, {.joint = JointType::Weld}), InvalidArgument);
  EXPECT_THROW(addRopeBridge(world, {.slack = -1}), InvalidArgument);
  EXPECT_THROW(addRagdoll(world, {.scale = 0}), InvalidArgument);
  EXPECT_THROW(jointGrid({.spacing = Real(0.5)}), InvalidArgument);
  Assembly bad = chain({.links = 2});
  bad.joints.back().bodyB = 7;
  EXPECT_THROW(addAssembly(world, bad), InvalidArgument);
  EXPECT_EQ(world.bodyCount(), 0);  // checked before anything was added
}

// Joints placed by hand at a world point start satisfied, their angle and position zero, with
// the axis carried into each body's frame: B turns about it (or slides along it) and only that.
TEST(JointBuilders, JointsPlacedAtAWorldPointStartSatisfied) {
  Assembly a;
  const Quat qa(Eigen::AngleAxis<Real>(Real(0.4), Vec3(1, 2, 0).normalized()));
  const Quat qb(Eigen::AngleAxis<Real>(Real(-1.1), Vec3(0, 1, 3).normalized()));
  auto addSphere = [&](const Vec3& p, const Quat& q) {
    BodyDesc& d = a.bodies.emplace_back();
    d.settings.position = p;
    d.settings.orientation = q;
    d.shapes.push_back({Sphere{Real(0.3)}, {}, {}});
  };
  addSphere(Vec3(1, 2, 3), qa);
  addSphere(Vec3(2, 1, 3), qb);
  const Vec3 point(Real(1.5), Real(1.5), 3), axis = Vec3(1, 1, 1).normalized();
  a.joints.push_back({ballJointAt(a, 0, 1, point, axis), 0, 1});
  a.joints.push_back({hingeJointAt(a, 0, 1, point, 3 * axis), 0, 1});
  a.joints.push_back({sliderJointAt(a, -1, 1, point, -axis), -1, 1});
  World world({.gravity = Vec3::Zero()});
  const AssemblyIds ids = addAssembly(world, a);
  const RigidBodySystem& rb = world.rigidBodies();
  for (JointId j : ids.joints) {
    EXPECT_LT(rb.jointError(j).position, Real(1e-5)) << int(rb.jointType(j));
    EXPECT_LT(rb.jointError(j).angle, Real(1e-5)) << int(rb.jointType(j));
    EXPECT_NEAR(rb.jointCoordinate(j), 0, Real(1e-5));
    EXPECT_TRUE(rb.jointAnchorA(j).isApprox(point, Real(1e-5)));
  }
  // The axes in world coordinates: the frames' x.
  EXPECT_TRUE((rb.jointFrameA(ids.joints[0]).q * Vec3::UnitX()).isApprox(axis, Real(1e-5)));
  EXPECT_TRUE((rb.jointFrameB(ids.joints[0]).q * Vec3::UnitX()).isApprox(axis, Real(1e-5)));
  EXPECT_TRUE((rb.jointFrameA(ids.joints[1]).q * Vec3::UnitX()).isApprox(axis, Real(1e-5)));
  EXPECT_TRUE((rb.jointFrameA(ids.joints[2]).q * Vec3::UnitX()).isApprox(-axis, Real(1e-5)));
  // Moving B along the slider's axis reads as its position.
  World slid({.gravity = Vec3::Zero()});
  Assembly justSlider = a;
  justSlider.joints.erase(justSlider.joints.begin(), justSlider.joints.begin() + 2);
  const AssemblyIds s = addAssembly(slid, justSlider);
  slid.rigidBodies().setTransform(s.bodies[1], {Vec3(2, 1, 3) - Real(0.25) * axis, qb});
  EXPECT_NEAR(slid.rigidBodies().jointCoordinate(s.joints[0]), Real(0.25), Real(1e-5));
  EXPECT_LT(slid.rigidBodies().jointError(s.joints[0]).position, Real(1e-5));

  EXPECT_THROW(ballJointAt(a, 0, 2, point), InvalidArgument);
  EXPECT_THROW(ballJointAt(a, -2, 1, point), InvalidArgument);
  EXPECT_THROW(hingeJointAt(a, 1, 1, point, axis), InvalidArgument);
  EXPECT_THROW(hingeJointAt(a, 0, 1, point, Vec3::Zero()), InvalidArgument);
  EXPECT_THROW(ballJointAt(a, 0, 1, point, Vec3::Zero()), InvalidArgument);
  EXPECT_THROW(
      sliderJointAt(a, -1, 0, Vec3::Constant(std::numeric_limits<Real>::quiet_NaN()), axis),
      InvalidArgument);
}

// A hinge pendulum released at 0.5 rad swings through to -0.5 rad on the other side (energy
// conservation: symplectic Euler and the soft joint lose well under 1% in half a swing), with
// the bob staying on its circle.
TEST(JointBuilders, PendulumSwingsToTheMirroredAngle) {
  World world({.sleeping = false});
  const Real theta0 = Real(0.5);
  const PendulumSettings s{.pivot = Vec3(0, 2, 0), .length = Real(1.5), .angle = theta0};
  const Pendulum p = addPendulum(world, s);
  Real lowest = theta0;
  for (int i = 0; i < 90; ++i) {  // 1.5 s, past the half period of 1.25 s
    world.step(kDt);
    const Vec3 r = world.transform(p.bob).p - s.pivot;
    lowest = std::min(lowest, std::atan2(r.x(), -r.y()));
    EXPECT_NEAR(r.norm(), s.length, Real(1e-3));
  }
  EXPECT_NEAR(lowest, -theta0, Real(0.005));
}

// A 20-link chain released horizontally from the world falls and whips. Its joints may only
// remove energy (soft constraints and the relax pass damp, never push). A chain of ball joints
// is a joint tree (joint_trees.h), solved exactly and its anchors projected after each
// position update, so they hold to the projection's second-order remainder through the whip,
// whose tip passes 27 m/s: within 0.1 mm, a tenth of the bound (measured 9.6 um;
// solved one by one, the joints opened by 1.0 cm on the last joint, under 5 mm otherwise).
TEST(JointBuilders, HorizontalChainFallsWithoutGainingEnergy) {
  World world({.sleeping = false});
  const ChainSettings s{.links = 20, .top = Vec3(0, 20, 0), .direction = Vec3::UnitX()};
  const Chain c = addChain(world, s);
  const double e0 = mechanicalEnergy(world);
  double mass = 0;
  for (BodyId b : c.links) mass += world.rigidBodies().mass(b);
  const double scale = mass * kG * 10;  // the energy of dropping the chain by its length
  Real worst = 0, lowestEnd = 20;
  for (int i = 0; i < 180; ++i) {
    world.step(kDt);
    ASSERT_TRUE(finiteState(world)) << "step " << i;
    EXPECT_LT(mechanicalEnergy(world) - e0, 1e-3 * scale) << "step " << i;
    worst = std::max(worst, worstPositionError(world));
    lowestEnd = std::min(lowestEnd, world.transform(c.links.back()).p.y());
  }
  EXPECT_LT(worst, Real(1e-4));
  EXPECT_LT(lowestEnd, Real(20 - 9));  // it swung down to hang nearly straight
}

namespace {

// How far the ragdoll's joints are past their limits (rad): the hinges' angles, the ball joints'
// swing cones and twists.
Real worstLimitExcess(const World& world, const Ragdoll& r) {
  const RigidBodySystem& rb = world.rigidBodies();
  Real worst = 0;
  for (JointId j : r.joints) {
    if (rb.jointType(j) != JointType::Hinge) {
      worst = std::max(worst, rb.jointError(j).angle);
      continue;
    }
    const std::string_view name = rb.jointName(j);
    const JointLimits limits =
        name.find("knee") != std::string_view::npos    ? JointLimits{0, Real(2.6)}
        : name.find("elbow") != std::string_view::npos ? JointLimits{Real(-2.6), 0}
                                                       : JointLimits{Real(-0.3), Real(0.8)};
    const Real a = rb.jointCoordinate(j);
    worst = std::max({worst, limits.lower - a, a - limits.upper});
  }
  return worst;
}

}  // namespace

// A ragdoll dropped tilted onto the ground tumbles and comes to rest: no NaN, lying on the
// ground (not through it), every joint within a millimetre at rest. Through the impacts they
// stay within 2 cm: dropped from 1.2 to 3 m at several tilts, the soft joints' worst was 1.5
// cm, for a frame or two as a straight knee or an arm took the landing (4 substeps, 4
// iterations: the world's defaults). The limits (hinges' angles, the ball joints' cones and
// twists) are soft when passed, at twice the contacts' stiffness: dropped from 2 to 4 m at five
// tilts and two scales, the worst was 0.036 rad past a limit through a landing and 0.014 rad at
// rest, where an arm lies twisted under the torso and the contacts push back on the limit.
TEST(JointBuilders, RagdollDroppedOnTheGroundComesToRest) {
  World world;
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{Vec3::UnitY(), 0});
  const Quat tilt(Eigen::AngleAxis<Real>(Real(0.6), Vec3(1, 0, Real(0.5)).normalized()));
  const Ragdoll r = addRagdoll(world, {.position = Vec3(0, 2, 0), .orientation = tilt});
  Real worst = 0, worstLimit = 0;
  for (int i = 0; i < 360; ++i) {
    world.step(kDt);
    ASSERT_TRUE(finiteState(world)) << "step " << i;
    worst = std::max(worst, worstPositionError(world));
    worstLimit = std::max(worstLimit, worstLimitExcess(world, r));
  }
  EXPECT_LT(worst, Real(0.02));
  EXPECT_LT(worstPositionError(world), Real(0.001));
  EXPECT_LT(worstLimit, Real(0.05));
  EXPECT_LT(worstLimitExcess(world, r), Real(0.02));
  EXPECT_LT(world.rigidBodies().kineticEnergy(), Real(0.01));  // 70 kg at 1.7 cm/s
  Real highest = 0;
  for (BodyId b : r.parts) {
    const Real y = world.transform(b).p.y();
    EXPECT_GT(y, Real(0.03)) << world.rigidBodies().name(b);  // the thinnest part's radius: 0.045
    highest = std::max(highest, y);
  }
  EXPECT_LT(highest, Real(0.5));  // lying down
}

namespace {

JointId named(const World& world, const Ragdoll& r, std::string_view name) {
  for (JointId j : r.joints)
    if (world.rigidBodies().jointName(j) == name) return j;
  ADD_FAILURE() << "no joint " << name;
  return {};
}

}  // namespace

// The limits bend the right way: a shin turned backwards about the knee (its foot towards -z,
// the figure facing +z) reads a positive angle, inside the knee's [0, 2.6]; a forearm turned
// forwards reads a negative one, inside the elbow's [-2.6, 0].
TEST(JointBuilders, RagdollKneesAndElbowsBendTheAnatomicalWay) {
  World world;
  const Ragdoll r = addRagdoll(world, {});
  auto turn = [&](RagdollPart part, const Vec3& pivot, Real angle) {
    const Quat q(Eigen::AngleAxis<Real>(angle, Vec3::UnitX()));
    const Transform x = world.transform(r.part(part));
    world.rigidBodies().setTransform(r.part(part), {pivot + q * (x.p - pivot), q * x.q});
  };
  turn(RagdollPart::LowerLegLeft, Vec3(Real(0.09), Real(1 - 0.53), 0), Real(0.5));
  const Vec3 foot = world.transform(r.part(RagdollPart::LowerLegLeft)).p;
  EXPECT_LT(foot.z(), 0);
  EXPECT_NEAR(world.rigidBodies().jointCoordinate(named(world, r, "ragdoll_knee_left")), Real(0.5),
              Real(1e-4));
  turn(RagdollPart::LowerArmRight, Vec3(Real(-0.23), Real(1 + 0.22), 0), Real(-0.5));
  EXPECT_GT(world.transform(r.part(RagdollPart::LowerArmRight)).p.z(), 0);
  EXPECT_NEAR(world.rigidBodies().jointCoordinate(named(world, r, "ragdoll_elbow_right")),
              Real(-0.5), Real(1e-4));
}

namespace {

// A chain of n rigid links of pitch p and weight w each, hinged at its seams, hanging between
// two seams `span` apart at the same height: the discrete catenary. Moment balance about a
// link's centre makes its slope the mean vertical tension of its ends over the horizontal
// tension H, tan theta_k = (k + 1/2 - n/2) w / H; H follows from the span, which grows with it.
struct DiscreteCatenary {
  double depth = 0;    // of the middle seam below the end ones (m, n even)
  double tension = 0;  // at the end seams (N)
  DiscreteCatenary(int n, double p, double w, double span) {
    auto width = [&](double h) {
      double x = 0;
      for (int k = 0; k < n; ++k) x += p * std::cos(std::atan((k + 0.5 - n / 2.0) * w / h));
      return x;
    };
    double lo = 1e-6 * w, hi = 1e9 * w;
    for (int it = 0; it < 200; ++it) {
      const double mid = std::sqrt(lo * hi);
      (width(mid) < span ? lo : hi) = mid;
    }
    const double h = std::sqrt(lo * hi);
    for (int k = 0; k < n / 2; ++k) depth += p * std::sin(std::atan((n / 2.0 - k - 0.5) * w / h));
    tension = std::hypot(h, n * w / 2);
  }
};

// A bridge whose planks are damped (linear and angular damping, 2/s), so that it settles: the
// damping removes the swing and leaves the static equilibrium as it is.
struct Bridge {
  World world{WorldSettings{.sleeping = false}};
  RopeBridgeSettings settings;
  RopeBridge bridge;
  explicit Bridge(RopeBridgeSettings s) : settings(std::move(s)) {
    Assembly a = ropeBridge(settings);
    for (BodyDesc& d : a.bodies) d.settings.linearDamping = d.settings.angularDamping = 2;
    const AssemblyIds ids = addAssembly(world, a);
    bridge.planks.assign(ids.bodies.begin(), ids.bodies.begin() + settings.planks);
    bridge.joints = ids.joints;
  }
  // The middle seam's depth below the posts' seams (m), from its joints' anchors on A.
  Real depth() const {
    const int perSeam = settings.joint == JointType::Ball ? 2 : 1;
    const JointId j = bridge.joints[std::size_t(settings.planks / 2 * perSeam)];
    return settings.center.y() - world.rigidBodies().jointAnchorA(j).y();
  }
  DiscreteCatenary oracle() const {
    const int n = settings.planks;
    const double p = 2 * double(settings.plankHalfExtents.x()) + double(settings.gap);
    const double w = double(world.rigidBodies().mass(bridge.planks[0])) * kG;
    return DiscreteCatenary(n, p, w, n * p / (1 + double(settings.slack)));
  }
  int broken() const {
    int n = 0;
    for (JointId j : bridge.joints) n += world.rigidBodies().isJointBroken(j) ? 1 : 0;
    return n;
  }
};

}  // namespace

// The planks start on a circular arc, 3.6% shallower than the discrete catenary of the same
// planks and span at this slack, and settle into the catenary: the middle seam's depth within
// 1% (the joints' stretch under the 7.5 kN end tension, a millimetre or less a seam, deepens
// it by about 0.3%; measured: 0.46% on ball joints, 0.25% on hinges), the joints within a
// centimetre throughout.
TEST(JointBuilders, RopeBridgeSagsIntoTheDiscreteCatenary) {
  for (JointType type : {JointType::Ball, JointType::Hinge}) {
    Bridge b({.planks = 20, .slack = Real(0.2), .joint = type});
    const double expected = b.oracle().depth;
    ASSERT_GT(std::abs(b.depth() / expected - 1), 0.03);  // the arc is not the catenary
    Real worst = 0;
    for (int i = 0; i < 480; ++i) {
      b.world.step(kDt);
      ASSERT_TRUE(finiteState(b.world)) << "step " << i;
      worst = std::max(worst, worstPositionError(b.world));
    }
    EXPECT_LT(worst, Real(0.01)) << jointTypeName(type);
    EXPECT_NEAR(b.depth() / expected, 1, 0.01) << jointTypeName(type);
    EXPECT_LT(b.world.rigidBodies().kineticEnergy(), 0.01);
    EXPECT_EQ(b.broken(), 0);
  }
}

// Breakable: a seam's two ball joints share the catenary's end tension. The weight comes on
// the joints at once, and a suddenly applied load brings a spring to at most twice its static
// force, so joints rated at three times their static share hold, and joints rated at half of
// it give way and drop the planks.
TEST(JointBuilders, RopeBridgeBreaksOnlyAboveItsTension) {
  const RopeBridgeSettings s;
  const Real perJoint = Real(Bridge(s).oracle().tension / 2);
  auto with = [&](Real breakForce) {
    RopeBridgeSettings t = s;
    t.breakForce = breakForce;
    return t;
  };
  Bridge weak(with(perJoint / 2)), strong(with(3 * perJoint));
  for (int i = 0; i < 180; ++i) {
    weak.world.step(kDt);
    strong.world.step(kDt);
  }
  EXPECT_GT(weak.broken(), 0);
  EXPECT_LT(weak.world.transform(weak.bridge.planks[10]).p.y(), s.center.y() - 5);
  EXPECT_EQ(strong.broken(), 0);
  EXPECT_LT(worstPositionError(strong.world), Real(0.01));
}
