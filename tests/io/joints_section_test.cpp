// The "joints" section of scene files (src/io/joints_section.cpp): every type read and built
// as the file says, and every error named by its JSON pointer and reason.
#include <gtest/gtest.h>

#include <string>
#include <variant>
#include <vector>

#include "inertia/io/scene.h"
#include "scene_error_test_util.h"

using namespace inertia;
using inertia::io::parseScene;
using inertia::io::SceneError;
using inertia::test::BadCase;
using inertia::test::errorOf;

namespace {

// Joints' errors: two bodies, "a" and "b", and the joints given.
std::string withJoints(const std::string& joints) {
  return R"({"bodies": [{"name": "a", "position": [0, 1, 0]}, {"name": "b", "position": [1, 1, 0]}],
             "joints": )" +
         joints + "}";
}

}  // namespace

class BadJoint : public testing::TestWithParam<BadCase> {};

TEST_P(BadJoint, NamesThePointerAndTheReason) {
  const BadCase& c = GetParam();
  SceneError e = errorOf(withJoints(c.text));
  EXPECT_EQ(e.pointer(), c.pointer) << e.what();
  EXPECT_NE(e.reason().find(c.words), std::string::npos) << e.what();
  EXPECT_EQ(e.file(), "test.json") << e.what();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadJoint,
    testing::Values(
        BadCase{R"({})", "/joints", "expected an array"},
        BadCase{R"([{"body_b": "b"}])", "/joints/0", "missing required key \"type\""},
        BadCase{R"([{"type": "rope", "body_b": "b"}])", "/joints/0/type",
                "unknown joint type \"rope\""},
        BadCase{R"([{"type": 3, "body_b": "b"}])", "/joints/0/type", "expected a string"},
        // Unknown body names, wherever the joint is in the list.
        BadCase{R"([{"type": "ball", "body_b": "a"}, {"type": "ball", "body_b": "b"},
                    {"type": "ball", "body_a": "a", "body_b": "c"}])",
                "/joints/2/body_b", "no body is named \"c\""},
        BadCase{R"([{"type": "ball", "body_a": "z", "body_b": "b"}])", "/joints/0/body_a",
                "no body is named \"z\""},
        BadCase{R"([{"type": "ball"}])", "/joints/0", "missing required key \"body_b\""},
        BadCase{R"([{"type": "ball", "body_b": null}])", "/joints/0/body_b",
                "only body_a may be null"},
        BadCase{R"([{"type": "ball", "body_b": 1}])", "/joints/0/body_b", "expected a body's name"},
        BadCase{R"([{"type": "hinge", "body_a": "b", "body_b": "b"}])", "/joints/0/body_b",
                "joined to itself"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "axis_a": [0, 0, 0]}])", "/joints/0/axis_a",
                "must not be zero"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "axis_b": [0, 0, 0]}])", "/joints/0/axis_b",
                "must not be zero"},
        BadCase{R"([{"type": "slider", "body_b": "b", "axis_a": [0, 0, 0]}])", "/joints/0/axis_a",
                "must not be zero"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "axis_a": [0, 1]}])", "/joints/0/axis_a",
                "3 numbers"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "limits": [0.5, -0.5]}])", "/joints/0/limits",
                "lower limit 0.5 is above the upper limit -0.5"},
        BadCase{R"([{"type": "slider", "body_b": "b", "limits": [2, 1]}])", "/joints/0/limits",
                "above the upper limit"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "limits": [-1, 4]}])", "/joints/0/limits/1",
                "must lie in [-3.14159, 3.14159] (rad)"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "limits": [1]}])", "/joints/0/limits",
                "expected [lower, upper]"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "limits": "wide"}])", "/joints/0/limits",
                "expected an array, got a string"},
        BadCase{R"([{"type": "ball", "body_b": "b", "break_force": -1}])", "/joints/0/break_force",
                "must be >= 0 (N)"},
        BadCase{R"([{"type": "weld", "body_b": "b", "break_torque": -0.5}])",
                "/joints/0/break_torque", "must be >= 0 (N m)"},
        BadCase{R"([{"type": "ball", "body_b": "b", "friction": -0.1}])", "/joints/0/friction",
                ">= 0"},
        BadCase{R"([{"type": "ball", "body_b": "b", "collide_connected": "yes"}])",
                "/joints/0/collide_connected", "true or false"},
        BadCase{R"([{"type": "ball", "body_b": "b", "limits": [0, 1]}])", "/joints/0/limits",
                "unknown key"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "breakforce": 5}])", "/joints/0/breakforce",
                "did you mean \"break_force\""},
        BadCase{R"([{"type": "weld", "body_b": "b", "spring": {"frequency": 1, "rest": 0}}])",
                "/joints/0/spring/rest", "unknown key"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "spring": {"frequency": 0}}])",
                "/joints/0/spring/frequency", "out of range"},
        BadCase{R"([{"type": "hinge", "body_b": "b", "spring": {"damping_ratio": 1}}])",
                "/joints/0/spring", "missing required key \"frequency\""},
        BadCase{R"([{"type": "hinge", "body_b": "b", "motor": {"speed": 1}}])", "/joints/0/motor",
                "missing required key \"max_torque\""},
        BadCase{R"([{"type": "slider", "body_b": "b", "motor": {"speed": 1, "max_torque": 5}}])",
                "/joints/0/motor/max_torque", "takes \"max_force\" (N), not \"max_torque\""},
        BadCase{R"([{"type": "hinge", "body_b": "b", "motor": {"speed": 1, "max_torque": -5}}])",
                "/joints/0/motor/max_torque", "must be >= 0 (N m)"},
        BadCase{
            R"([{"type": "hinge", "body_b": "b", "motor": {"speed": 1, "target": 0, "max_torque": 5}}])",
            "/joints/0/motor/speed", "servo"},
        BadCase{
            R"([{"type": "hinge", "body_b": "b", "motor": {"servo_frequency": 3, "max_torque": 5}}])",
            "/joints/0/motor/servo_frequency", "needs \"target\""},
        BadCase{R"([{"type": "distance", "body_b": "b", "min_length": 2, "max_length": 1}])",
                "/joints/0/min_length", "exceeds max_length"},
        BadCase{R"([{"type": "distance", "body_b": "b", "length": -1}])", "/joints/0/length",
                ">= 0 (m)"},
        // The bounds left out are the length: b's origin is 1 m from a's.
        BadCase{R"([{"type": "distance", "body_a": "a", "body_b": "b", "max_length": 0.5}])",
                "/joints/0/max_length", "below the anchors' distance at the start (1 m)"},
        BadCase{
            R"([{"type": "distance", "body_a": "a", "body_b": "b", "length": 1, "min_length": 1.5}])",
            "/joints/0/min_length", "exceeds length (1 m)"},
        BadCase{R"([{"type": "ball", "body_b": "b", "cone_limit": 4}])", "/joints/0/cone_limit",
                "out of range"},
        BadCase{R"([{"type": "ball", "body_b": "b", "twist_limits": [1, -1]}])",
                "/joints/0/twist_limits", "above the upper limit"},
        BadCase{R"([{"type": "universal", "body_b": "b", "axis_a": [0, 0, 0]}])",
                "/joints/0/axis_a", "must not be zero"},
        BadCase{R"([{"type": "universal", "body_b": "b", "limits_b": [-2, 1]}])",
                "/joints/0/limits_b/0", "must lie in [-1.5708, 1.5708]"},
        BadCase{R"([{"type": "six_dof", "body_b": "b", "axes": {"q": "free"}}])",
                "/joints/0/axes/q", "unknown key"},
        BadCase{R"([{"type": "six_dof", "body_b": "b", "axes": {"rx": "loose"}}])",
                "/joints/0/axes/rx", "expected \"free\", \"locked\""},
        BadCase{R"([{"type": "six_dof", "body_b": "b", "axes": {"x": {"limits": [1, 0]}}}])",
                "/joints/0/axes/x/limits", "above the upper limit"},
        BadCase{R"([{"type": "six_dof", "body_b": "b", "anchor_a": [0, 0, 0]}])",
                "/joints/0/anchor_a", "unknown key"},
        BadCase{R"([{"type": "six_dof", "body_b": "b", "frame_a": {"orientation": [2, 0, 0, 0]}}])",
                "/joints/0/frame_a/orientation", ""}));

// Universal and six-DOF joints and a ball joint's cone and twist, read and built.
TEST(JointsSection, ReadsUniversalSixDofAndBallLimits) {
  io::Scene s = parseScene(R"({
    "bodies": [ {"name": "a", "position": [0, 0, 0]}, {"name": "b", "position": [1, 0, 0]} ],
    "joints": [
      { "type": "ball", "body_a": "a", "body_b": "b", "axis_a": [1, 0, 0], "cone_limit": 0.7,
        "twist_limits": [-0.2, 0.3] },
      { "type": "universal", "body_a": "a", "body_b": "b", "axis_a": [1, 0, 0], "axis_b": [0, 1, 0],
        "limits_a": [-1, 1], "limits_b": [-0.5, 0.5] },
      { "type": "six_dof", "body_a": "a", "body_b": "b",
        "frame_a": { "position": [0.5, 0, 0], "orientation": [1, 0, 0, 0] },
        "frame_b": { "position": [-0.5, 0, 0] },
        "axes": { "x": [-0.1, 0.2], "rx": "free",
                  "rz": { "limits": [-1, 1], "motor": { "speed": 2, "max_torque": 3 },
                          "spring": { "frequency": 4, "rest": 0.5 }, "friction": 0.1 } } }
    ] })",
                           "joints.json");
  ASSERT_EQ(s.joints.size(), 3u);
  const auto& ball = std::get<BallJointSettings>(s.joints[0].settings);
  EXPECT_EQ(ball.coneLimit.value_or(0), Real(0.7));
  ASSERT_TRUE(ball.twistLimits.has_value());
  EXPECT_EQ(ball.twistLimits->lower, Real(-0.2));
  EXPECT_EQ(ball.twistLimits->upper, Real(0.3));
  const auto& u = std::get<UniversalJointSettings>(s.joints[1].settings);
  EXPECT_EQ(u.axisB, Vec3(0, 1, 0));
  ASSERT_TRUE(u.limitsB.has_value());
  EXPECT_EQ(u.limitsB->upper, Real(0.5));
  const auto& six = std::get<SixDofJointSettings>(s.joints[2].settings);
  EXPECT_EQ(six.frameA.p, Vec3(Real(0.5), 0, 0));
  EXPECT_EQ(six.frameB.p, Vec3(Real(-0.5), 0, 0));
  EXPECT_FALSE(six.axes[0].locked);
  ASSERT_TRUE(six.axes[0].limits.has_value());
  EXPECT_EQ(six.axes[0].limits->upper, Real(0.2));
  EXPECT_TRUE(six.axes[1].locked);
  EXPECT_FALSE(six.axes[3].locked);
  EXPECT_FALSE(six.axes[3].limits.has_value());
  const JointAxis& rz = six.axes[5];
  EXPECT_FALSE(rz.locked);
  ASSERT_TRUE(rz.motor.has_value() && rz.spring.has_value());
  EXPECT_EQ(rz.motor->maxForce, Real(3));
  EXPECT_EQ(rz.spring->rest, Real(0.5));
  EXPECT_EQ(rz.friction, Real(0.1));

  auto world = io::instantiate(s);
  const RigidBodySystem& rb = world->rigidBodies();
  const std::vector<JointId> joints = rb.joints();
  ASSERT_EQ(joints.size(), 3u);
  EXPECT_EQ(rb.jointType(joints[1]), JointType::Universal);
  EXPECT_EQ(rb.jointType(joints[2]), JointType::SixDof);
  EXPECT_EQ(rb.jointAxis(joints[2], 5).friction, Real(0.1));
  // The six-DOF frames meet where the file puts them: at x = 0.5 between the bodies.
  EXPECT_TRUE(rb.jointFrameA(joints[2]).p.isApprox(Vec3(Real(0.5), 0, 0)));
  EXPECT_TRUE(rb.jointFrameB(joints[2]).p.isApprox(Vec3(Real(0.5), 0, 0)));
}

TEST(JointsSection, JointBodiesMustBeUniquelyNamed) {
  // Refused where the second name is given, before a joint names it.
  SceneError e = errorOf(R"({"bodies": [{"name": "twin"}, {"name": "twin"}, {"name": "c"}],
                             "joints": [{"type": "ball", "body_a": "c", "body_b": "twin"}]})");
  EXPECT_EQ(e.pointer(), "/bodies/1/name") << e.what();
  EXPECT_NE(e.reason().find("duplicate body name \"twin\""), std::string::npos) << e.what();
}

TEST(JointsSection, ReadsEveryJointType) {
  io::Scene s = parseScene(R"({
    "bodies": [ {"name": "base", "type": "static"}, {"name": "upper", "position": [0, 2, 0]},
                {"name": "lower", "position": [0, 1, 0]}, {"name": "cart", "position": [3, 0, 0]},
                {"name": "lid", "position": [0, 3, 0]} ],
    "joints": [
      { "name": "shoulder", "type": "ball", "body_a": null, "body_b": "upper", "anchor_a": [0, 2.5, 0],
        "anchor_b": [0, 0.5, 0], "friction": 0.25, "break_force": 1000, "break_torque": 500 },
      { "name": "elbow", "type": "hinge", "body_a": "upper", "body_b": "lower",
        "anchor_a": [0, -0.5, 0], "anchor_b": [0, 0.5, 0], "axis_a": [0, 0, 1], "axis_b": [0, 0, 1],
        "limits": [-2.0, 0.0], "motor": { "speed": 1.0, "max_torque": 50 },
        "spring": { "frequency": 2.0, "damping_ratio": 0.5, "rest": -1 }, "friction": 0.1,
        "break_force": 1000, "break_torque": 500, "collide_connected": true },
      { "type": "slider", "body_a": "base", "body_b": "cart", "axis_a": [2, 0, 0], "limits": [-1, 1.5],
        "motor": { "target": 0.5, "max_force": 20, "servo_frequency": 4 } },
      { "name": "glue", "type": "weld", "body_a": "upper", "body_b": "lid",
        "spring": { "frequency": 5, "damping_ratio": 1 } },
      { "name": "rope", "type": "distance", "body_a": "base", "body_b": "lower", "length": 1.2,
        "min_length": 0.5, "max_length": 2, "spring": { "frequency": 3 } }
    ] })",
                           "joints.json");
  ASSERT_EQ(s.joints.size(), 5u);

  const io::JointDesc& ball = s.joints[0];
  EXPECT_FALSE(ball.bodyA.has_value());  // the world
  EXPECT_EQ(ball.bodyB, 1u);
  EXPECT_EQ(ball.pointer, "/joints/0");
  const auto& b = std::get<BallJointSettings>(ball.settings);
  EXPECT_EQ(b.name, "shoulder");
  EXPECT_EQ(b.anchorA, Vec3(0, Real(2.5), 0));
  EXPECT_EQ(b.anchorB, Vec3(0, Real(0.5), 0));
  EXPECT_EQ(b.friction, Real(0.25));
  EXPECT_EQ(b.breakForce, Real(1000));
  EXPECT_EQ(b.breakTorque, Real(500));
  EXPECT_FALSE(b.collideConnected);

  const io::JointDesc& elbow = s.joints[1];
  EXPECT_EQ(elbow.bodyA, std::optional<std::size_t>(1));
  EXPECT_EQ(elbow.bodyB, 2u);
  const auto& h = std::get<HingeJointSettings>(elbow.settings);
  EXPECT_EQ(h.axisA, Vec3::UnitZ());
  EXPECT_EQ(h.axisB, Vec3::UnitZ());
  ASSERT_TRUE(h.limits.has_value());
  EXPECT_EQ(h.limits->lower, Real(-2.0));
  EXPECT_EQ(h.limits->upper, Real(0.0));
  ASSERT_TRUE(h.motor.has_value());
  EXPECT_EQ(h.motor->speed, Real(1));
  EXPECT_EQ(h.motor->maxForce, Real(50));
  EXPECT_FALSE(h.motor->target.has_value());
  ASSERT_TRUE(h.spring.has_value());
  EXPECT_EQ(h.spring->frequency, Real(2));
  EXPECT_EQ(h.spring->dampingRatio, Real(0.5));
  EXPECT_EQ(h.spring->rest, Real(-1));
  EXPECT_EQ(h.friction, Real(0.1));
  EXPECT_TRUE(h.collideConnected);

  const auto& sl = std::get<SliderJointSettings>(s.joints[2].settings);
  EXPECT_EQ(sl.name, "2");  // unnamed: its index
  EXPECT_EQ(sl.axisA, Vec3(2, 0, 0));
  ASSERT_TRUE(sl.limits.has_value());
  EXPECT_EQ(sl.limits->lower, Real(-1));
  EXPECT_EQ(sl.limits->upper, Real(1.5));
  ASSERT_TRUE(sl.motor.has_value() && sl.motor->target.has_value());
  EXPECT_EQ(*sl.motor->target, Real(0.5));
  EXPECT_EQ(sl.motor->maxForce, Real(20));
  EXPECT_EQ(sl.motor->servoFrequency, Real(4));
  EXPECT_FALSE(sl.spring.has_value());
  EXPECT_EQ(sl.breakForce, kUnbreakable);

  const auto& w = std::get<WeldJointSettings>(s.joints[3].settings);
  ASSERT_TRUE(w.spring.has_value());
  EXPECT_EQ(w.spring->frequency, Real(5));
  EXPECT_EQ(w.spring->dampingRatio, Real(1));

  const auto& d = std::get<DistanceJointSettings>(s.joints[4].settings);
  EXPECT_EQ(d.length, Real(1.2));
  EXPECT_EQ(d.minLength, Real(0.5));
  EXPECT_EQ(d.maxLength, Real(2));
  ASSERT_TRUE(d.spring.has_value());
  EXPECT_EQ(d.spring->frequency, Real(3));
  EXPECT_EQ(d.spring->dampingRatio, Real(0));

  // Built, each joint joins the bodies the file names, as the file's type.
  auto world = io::instantiate(s);
  const RigidBodySystem& rb = world->rigidBodies();
  const std::vector<JointId> joints = rb.joints();
  ASSERT_EQ(joints.size(), 5u);
  const JointType types[] = {JointType::Ball, JointType::Hinge, JointType::Slider, JointType::Weld,
                             JointType::Distance};
  const char* names[] = {"shoulder", "elbow", "2", "glue", "rope"};
  const char* bodyA[] = {"", "upper", "base", "upper", "base"};
  const char* bodyB[] = {"upper", "lower", "cart", "lid", "lower"};
  for (std::size_t i = 0; i < joints.size(); ++i) {
    EXPECT_EQ(rb.jointType(joints[i]), types[i]) << i;
    EXPECT_EQ(rb.jointName(joints[i]), names[i]) << i;
    const BodyId a = rb.jointBodyA(joints[i]);
    EXPECT_EQ(a.isNull() ? std::string() : std::string(rb.name(a)), bodyA[i]) << i;
    EXPECT_EQ(rb.name(rb.jointBodyB(joints[i])), bodyB[i]) << i;
  }
  // The anchors coincide as the file placed them: the world's (0, 2.5, 0) is upper's top.
  EXPECT_TRUE(rb.jointAnchorA(joints[0]).isApprox(rb.jointAnchorB(joints[0])));
  EXPECT_NEAR(rb.jointCoordinate(joints[4]), 1.0, 1e-6);  // the rope's length now: lower is 1 m up
}

// Without axis_b, a hinge's axis in B's frame is A's axis as it lies at the start, so that a
// rotated body is not snapped round.
TEST(JointsSection, HingeAxisBDefaultsToAxisAAtTheStart) {
  // b is turned 90 degrees about x: its local y axis points along world z.
  io::Scene s = parseScene(R"({
    "bodies": [ {"name": "b", "orientation": [0.70710678, 0.70710678, 0, 0]} ],
    "joints": [ {"type": "hinge", "body_b": "b", "axis_a": [0, 0, 1]} ] })",
                           "axis.json");
  const auto& h = std::get<HingeJointSettings>(s.joints.at(0).settings);
  EXPECT_TRUE(h.axisB.isApprox(Vec3(0, 1, 0), Real(1e-6))) << h.axisB.transpose();
  auto world = io::instantiate(s);
  EXPECT_NEAR(world->rigidBodies().jointError(world->rigidBodies().joints().at(0)).angle, 0, 1e-5);
}

// What only createJoint checks is reported at the joint's pointer too.
TEST(JointsSection, CreateJointErrorsNameTheJoint) {
  io::Scene s = parseScene(withJoints(R"([{"type": "ball", "body_b": "a"},
                                          {"type": "hinge", "body_a": "a", "body_b": "b"}])"),
                           "made.json");
  std::get<HingeJointSettings>(s.joints.at(1).settings).axisA = Vec3::Zero();
  try {
    io::instantiate(s);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "made.json");
    EXPECT_EQ(e.pointer(), "/joints/1") << e.what();
    EXPECT_NE(e.reason().find("axisA"), std::string::npos) << e.what();
  }
}
