#include "joints_section.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace inertia::io::detail {

namespace {

constexpr std::string_view kTypes = "ball, hinge, slider, universal, weld, distance, six_dof";

std::string showNumber(Real x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", double(x));
  return text;
}

// Keys every type takes; each adds its own.
void requireJointKeys(const Node& n, std::initializer_list<std::string_view> own) {
  std::vector<std::string_view> all{"name",        "type",         "body_a",
                                    "body_b",      "anchor_a",     "anchor_b",
                                    "break_force", "break_torque", "collide_connected"};
  all.insert(all.end(), own.begin(), own.end());
  n.requireObject(all);
}

// A body by its "name" in "bodies" (unique: parseScene checks): its index.
std::size_t readBody(const Node& n, const std::vector<BodyDesc>& bodies) {
  if (!n.json().is_string()) n.fail("expected a body's name (a string), got " + typeName(n.json()));
  const std::string name = n.string();
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].settings.name == name) return i;
  n.fail("no body is named \"" + name + "\"");
}

// A number >= 0 in `unit`: friction, forces, lengths.
Real readNonNegative(const Node& n, const char* unit) {
  const double x = n.number();
  if (x < 0) n.fail("must be >= 0 (" + std::string(unit) + "), got " + n.json().dump());
  return Real(x);
}

// A break threshold: >= 0; left out, the joint never breaks.
Real readThreshold(const Node& n, const char* unit) {
  const double x = n.number();
  if (x < 0)
    n.fail("a break threshold must be >= 0 (" + std::string(unit) + "), got " + n.json().dump() +
           "; leave it out for a joint that never breaks");
  return Real(x);
}

Vec3 readAxis(const Node& n) {
  const Vec3 axis = n.vec3();
  if (!(axis.norm() > Real(1e-6))) n.fail("an axis must not be zero");
  return axis;
}

// [lower, upper] of an angle (rad, within [-bound, bound]) or a position (m).
JointLimits readLimits(const Node& n, bool angle, Real bound = Real(std::numbers::pi)) {
  if (n.requireArray() != 2)
    n.fail("expected [lower, upper], got " + std::to_string(n.json().size()) + " elements");
  const Real limit = bound;
  Real bounds[2];
  for (std::size_t k = 0; k < 2; ++k) {
    Node e = n.at(k);
    bounds[k] = Real(e.number());
    if (angle && std::fabs(bounds[k]) > limit)
      e.fail("angle limits must lie in [-" + showNumber(limit) + ", " + showNumber(limit) + "] (rad), got " +
             e.json().dump());
  }
  if (bounds[0] > bounds[1])
    n.fail("the lower limit " + n.json()[0].dump() + " is above the upper limit " +
           n.json()[1].dump());
  return {bounds[0], bounds[1]};
}

// `maxKey` is "max_torque" (a hinge) or "max_force" (a slider).
JointMotor readMotor(const Node& n, std::string_view maxKey, const char* unit) {
  const std::string_view otherKey = maxKey == "max_torque" ? "max_force" : "max_torque";
  if (n.has(otherKey))
    n.at(otherKey).fail(std::string(maxKey == "max_torque" ? "a hinge's" : "a slider's") +
                        " motor takes \"" + std::string(maxKey) + "\" (" + unit + "), not \"" +
                        std::string(otherKey) + "\"");
  n.requireObject({"speed", maxKey, "target", "servo_frequency"});
  JointMotor m;
  if (n.has("target")) {
    if (n.has("speed"))
      n.at("speed").fail("a motor with a \"target\" is a servo and has no speed; give one of them");
    m.target = Real(n.at("target").number());
  } else if (n.has("servo_frequency")) {
    n.at("servo_frequency").fail("\"servo_frequency\" needs \"target\"");
  }
  if (n.has("speed")) m.speed = Real(n.at("speed").number());
  m.maxForce = readNonNegative(n.at(maxKey), unit);
  if (n.has("servo_frequency"))
    m.servoFrequency = Real(n.at("servo_frequency").number(0, 1e6, /*openLo=*/true));
  return m;
}

// A spring's `rest` is a hinge's angle or a slider's position; the others have none.
JointSpring readSpring(const Node& n, bool hasRest) {
  if (hasRest)
    n.requireObject({"frequency", "damping_ratio", "rest"});
  else
    n.requireObject({"frequency", "damping_ratio"});
  JointSpring s;
  s.frequency = Real(n.at("frequency").number(0, 1e6, /*openLo=*/true));
  if (n.has("damping_ratio")) s.dampingRatio = Real(n.at("damping_ratio").number(0, 1e6));
  if (n.has("rest")) s.rest = Real(n.at("rest").number());
  return s;
}

// Where a point of a body (or of the world) is when the scene starts (m).
Vec3 worldPoint(const std::vector<BodyDesc>& bodies, std::optional<std::size_t> body,
                const Vec3& local) {
  if (!body) return local;
  const BodySettings& s = bodies[*body].settings;
  return s.position + s.orientation * local;
}

Quat rotationOf(const std::vector<BodyDesc>& bodies, std::optional<std::size_t> body) {
  return body ? bodies[*body].settings.orientation : Quat::Identity();
}

// What every type shares: the name, the bodies, the anchors and the break thresholds.
template <class S>
void readCommon(const Node& n, std::size_t index, const std::vector<BodyDesc>& bodies, S& s,
                JointDesc& d) {
  s.name = n.has("name") ? n.at("name").string() : std::to_string(index);
  if (n.has("body_a") && !n.at("body_a").json().is_null())
    d.bodyA = readBody(n.at("body_a"), bodies);
  Node b = n.at("body_b");
  if (b.json().is_null()) b.fail("body_b must be a body; only body_a may be null (the world)");
  d.bodyB = readBody(b, bodies);
  if (d.bodyA == d.bodyB)
    b.fail("a body cannot be joined to itself: body_a is \"" + b.string() + "\" too");
  if (n.has("anchor_a")) s.anchorA = n.at("anchor_a").vec3();
  if (n.has("anchor_b")) s.anchorB = n.at("anchor_b").vec3();
  if (n.has("break_force")) s.breakForce = readThreshold(n.at("break_force"), "N");
  if (n.has("break_torque")) s.breakTorque = readThreshold(n.at("break_torque"), "N m");
  if (n.has("collide_connected")) s.collideConnected = n.at("collide_connected").boolean();
}

// The free coordinate's limits, motor, spring and friction of a hinge or a slider.
template <class S>
void readAxisDrives(const Node& n, S& s, bool angle) {
  if (n.has("limits")) s.limits = readLimits(n.at("limits"), angle);
  if (n.has("motor"))
    s.motor = angle ? readMotor(n.at("motor"), "max_torque", "N m")
                    : readMotor(n.at("motor"), "max_force", "N");
  if (n.has("spring")) s.spring = readSpring(n.at("spring"), /*hasRest=*/true);
  if (n.has("friction")) s.friction = readNonNegative(n.at("friction"), angle ? "N m" : "N");
}

// B's axis left out: A's axis as it lies at the start, so the joint starts aligned.
Vec3 axisB(const Node& n, const std::vector<BodyDesc>& bodies, const JointDesc& d,
           const Vec3& axisA) {
  return n.has("axis_b") ? readAxis(n.at("axis_b"))
                         : Vec3(rotationOf(bodies, d.bodyB).conjugate() *
                                (rotationOf(bodies, d.bodyA) * axisA));
}

// A six-DOF joint's frame: {"position": [x, y, z], "orientation": [w, x, y, z]}.
Transform readFrame(const Node& n) {
  n.requireObject({"position", "orientation"});
  Transform t;
  if (n.has("position")) t.p = n.at("position").vec3();
  if (n.has("orientation")) t.q = n.at("orientation").quaternion();
  return t;
}

// One of a six-DOF joint's axes: "free", "locked", [lower, upper], or an object with
// "limits" and "motor", "spring", "friction".
JointAxis readSixDofAxis(const Node& n, bool angle, Real bound) {
  JointAxis a;
  if (n.json().is_string()) {
    const std::string mode = n.string();
    if (mode != "free" && mode != "locked")
      n.fail("expected \"free\", \"locked\", [lower, upper] or an object, got \"" + mode + "\"");
    a.locked = mode == "locked";
    return a;
  }
  a.locked = false;
  if (n.json().is_array()) {
    a.limits = readLimits(n, angle, bound);
    return a;
  }
  n.requireObject({"limits", "motor", "spring", "friction"});
  if (n.has("limits")) a.limits = readLimits(n.at("limits"), angle, bound);
  if (n.has("motor"))
    a.motor = angle ? readMotor(n.at("motor"), "max_torque", "N m")
                    : readMotor(n.at("motor"), "max_force", "N");
  if (n.has("spring")) a.spring = readSpring(n.at("spring"), /*hasRest=*/true);
  if (n.has("friction")) a.friction = readNonNegative(n.at("friction"), angle ? "N m" : "N");
  return a;
}

SixDofJointSettings readSixDof(const Node& n, std::size_t index,
                               const std::vector<BodyDesc>& bodies, JointDesc& d) {
  n.requireObject({"name", "type", "body_a", "body_b", "frame_a", "frame_b", "axes", "break_force",
                   "break_torque", "collide_connected"});
  // The anchors and thresholds as every type reads them, through a ball joint's settings.
  BallJointSettings common;
  readCommon(n, index, bodies, common, d);
  SixDofJointSettings s{.name = common.name};
  s.breakForce = common.breakForce;
  s.breakTorque = common.breakTorque;
  s.collideConnected = common.collideConnected;
  if (n.has("frame_a")) s.frameA = readFrame(n.at("frame_a"));
  if (n.has("frame_b")) s.frameB = readFrame(n.at("frame_b"));
  if (n.has("axes")) {
    const Node axes = n.at("axes");
    static constexpr std::array<const char*, 6> kNames{"x", "y", "z", "rx", "ry", "rz"};
    axes.requireObject({"x", "y", "z", "rx", "ry", "rz"});
    for (std::size_t i = 0; i < 6; ++i)
      if (axes.has(kNames[i]))
        s.axes[i] = readSixDofAxis(axes.at(kNames[i]), i >= 3,
                                   Real(i == 4 ? std::numbers::pi / 2 : std::numbers::pi));
  }
  return s;
}

DistanceJointSettings readDistance(const Node& n, const std::vector<BodyDesc>& bodies, JointDesc& d,
                                   DistanceJointSettings s) {
  if (n.has("length")) s.length = readNonNegative(n.at("length"), "m");
  if (n.has("min_length")) s.minLength = readNonNegative(n.at("min_length"), "m");
  if (n.has("max_length")) s.maxLength = readNonNegative(n.at("max_length"), "m");
  if (n.has("spring")) s.spring = readSpring(n.at("spring"), /*hasRest=*/false);
  // Bounds left out are the length, and a length left out is the anchors' distance at the
  // start (as DistanceJointSettings defines them): check what they come to.
  const Real length =
      s.length >= 0
          ? s.length
          : (worldPoint(bodies, d.bodyB, s.anchorB) - worldPoint(bodies, d.bodyA, s.anchorA))
                .norm();
  const Real lower = s.minLength >= 0 ? s.minLength : length;
  const Real upper = s.maxLength >= 0 ? s.maxLength : length;
  if (lower > upper) {
    const std::string what = n.has("length") ? "length" : "the anchors' distance at the start";
    if (n.has("min_length") && n.has("max_length"))
      n.at("min_length").fail("min_length exceeds max_length");
    if (n.has("min_length"))
      n.at("min_length")
          .fail("min_length exceeds " + what + " (" + showNumber(length) +
                " m), which max_length defaults to");
    n.at("max_length")
        .fail("max_length is below " + what + " (" + showNumber(length) +
              " m), which min_length defaults to");
  }
  return s;
}

}  // namespace

JointDesc readJoint(const Node& n, std::size_t index, const std::vector<BodyDesc>& bodies) {
  JointDesc d;
  d.pointer = n.pointer().to_string();
  Node typeNode = n.at("type");
  const std::string type = typeNode.string();
  if (type == "ball") {
    requireJointKeys(n, {"axis_a", "axis_b", "cone_limit", "twist_limits", "friction"});
    BallJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("axis_a")) s.axisA = readAxis(n.at("axis_a"));
    s.axisB = axisB(n, bodies, d, s.axisA);
    if (n.has("cone_limit")) {
      const Node cone = n.at("cone_limit");
      s.coneLimit = Real(cone.number(0, std::numbers::pi, /*openLo=*/true));
      if (*s.coneLimit >= Real(std::numbers::pi)) cone.fail("must be below pi (rad)");
    }
    if (n.has("twist_limits")) s.twistLimits = readLimits(n.at("twist_limits"), true);
    if (n.has("friction")) s.friction = readNonNegative(n.at("friction"), "N m");
    d.settings = std::move(s);
  } else if (type == "hinge") {
    requireJointKeys(n, {"axis_a", "axis_b", "limits", "motor", "spring", "friction"});
    HingeJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("axis_a")) s.axisA = readAxis(n.at("axis_a"));
    // Left out, B's axis is A's as it lies at the start, so the hinge starts aligned.
    s.axisB = axisB(n, bodies, d, s.axisA);
    readAxisDrives(n, s, /*angle=*/true);
    d.settings = std::move(s);
  } else if (type == "slider") {
    requireJointKeys(n, {"axis_a", "limits", "motor", "spring", "friction"});
    SliderJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("axis_a")) s.axisA = readAxis(n.at("axis_a"));
    readAxisDrives(n, s, /*angle=*/false);
    d.settings = std::move(s);
  } else if (type == "weld") {
    requireJointKeys(n, {"spring"});
    WeldJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("spring")) s.spring = readSpring(n.at("spring"), /*hasRest=*/false);
    d.settings = std::move(s);
  } else if (type == "distance") {
    requireJointKeys(n, {"length", "min_length", "max_length", "spring"});
    DistanceJointSettings s;
    readCommon(n, index, bodies, s, d);
    d.settings = readDistance(n, bodies, d, std::move(s));
  } else if (type == "universal") {
    requireJointKeys(n, {"axis_a", "axis_b", "limits_a", "limits_b"});
    UniversalJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("axis_a")) s.axisA = readAxis(n.at("axis_a"));
    if (n.has("axis_b")) s.axisB = readAxis(n.at("axis_b"));
    if (n.has("limits_a")) s.limitsA = readLimits(n.at("limits_a"), true);
    if (n.has("limits_b"))
      s.limitsB = readLimits(n.at("limits_b"), true, Real(std::numbers::pi / 2));
    d.settings = std::move(s);
  } else if (type == "six_dof") {
    d.settings = readSixDof(n, index, bodies, d);
  } else {
    typeNode.fail("unknown joint type \"" + type + "\"; expected one of " + std::string(kTypes));
  }
  return d;
}

}  // namespace inertia::io::detail
