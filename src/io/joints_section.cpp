#include "joints_section.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace inertia::io::detail {

namespace {

constexpr std::string_view kTypes = "ball, hinge, slider, weld, distance";

std::string show(Real x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", double(x));
  return text;
}

// Keys every type takes; each adds its own.
void requireKeys(const Node& n, std::initializer_list<std::string_view> own) {
  std::vector<std::string_view> all{"name",        "type",         "body_a",
                                    "body_b",      "anchor_a",     "anchor_b",
                                    "break_force", "break_torque", "collide_connected"};
  all.insert(all.end(), own.begin(), own.end());
  n.requireObject(all);
}

// Parts of DESIGN.md's joint format that the dynamics layer does not have yet.
[[noreturn]] void notSupported(const Node& n, const std::string& what) {
  n.fail(what + " is not supported yet in this version of Inertia");
}

// A body by its "name" in "bodies": its index.
std::size_t readBody(const Node& n, const std::vector<BodyDesc>& bodies) {
  if (!n.json().is_string()) n.fail("expected a body's name (a string), got " + typeName(n.json()));
  const std::string name = n.string();
  std::size_t found = 0, matches = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].settings.name == name) found = i, ++matches;
  if (matches == 0) n.fail("no body is named \"" + name + "\"");
  if (matches > 1)
    n.fail(std::to_string(matches) + " bodies are named \"" + name + "\"; the name must be unique");
  return found;
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

// [lower, upper] of an angle (rad, within [-pi, pi]) or a position (m).
JointLimits readLimits(const Node& n, bool angle) {
  if (n.requireArray() != 2)
    n.fail("expected [lower, upper], got " + std::to_string(n.json().size()) + " elements");
  Real bound[2];
  for (std::size_t k = 0; k < 2; ++k) {
    Node e = n.at(k);
    bound[k] = Real(e.number());
    if (angle && std::fabs(bound[k]) > Real(std::numbers::pi))
      e.fail("a hinge's limits must lie in [-pi, pi] (rad), got " + e.json().dump());
  }
  if (bound[0] > bound[1])
    n.fail("the lower limit " + n.json()[0].dump() + " is above the upper limit " +
           n.json()[1].dump());
  return {bound[0], bound[1]};
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
          .fail("min_length exceeds " + what + " (" + show(length) +
                " m), which max_length defaults to");
    n.at("max_length")
        .fail("max_length is below " + what + " (" + show(length) +
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
    if (n.has("cone_limit")) notSupported(n.at("cone_limit"), "a ball joint's \"cone_limit\"");
    if (n.has("twist_limits"))
      notSupported(n.at("twist_limits"), "a ball joint's \"twist_limits\"");
    requireKeys(n, {"friction"});
    BallJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("friction")) s.friction = readNonNegative(n.at("friction"), "N m");
    d.settings = std::move(s);
  } else if (type == "hinge") {
    requireKeys(n, {"axis_a", "axis_b", "limits", "motor", "spring", "friction"});
    HingeJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("axis_a")) s.axisA = readAxis(n.at("axis_a"));
    // Left out, B's axis is A's as it lies at the start, so the hinge starts aligned.
    s.axisB = n.has("axis_b") ? readAxis(n.at("axis_b"))
                              : Vec3(rotationOf(bodies, d.bodyB).conjugate() *
                                     (rotationOf(bodies, d.bodyA) * s.axisA));
    readAxisDrives(n, s, /*angle=*/true);
    d.settings = std::move(s);
  } else if (type == "slider") {
    requireKeys(n, {"axis_a", "limits", "motor", "spring", "friction"});
    SliderJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("axis_a")) s.axisA = readAxis(n.at("axis_a"));
    readAxisDrives(n, s, /*angle=*/false);
    d.settings = std::move(s);
  } else if (type == "weld") {
    requireKeys(n, {"spring"});
    WeldJointSettings s;
    readCommon(n, index, bodies, s, d);
    if (n.has("spring")) s.spring = readSpring(n.at("spring"), /*hasRest=*/false);
    d.settings = std::move(s);
  } else if (type == "distance") {
    requireKeys(n, {"length", "min_length", "max_length", "spring"});
    DistanceJointSettings s;
    readCommon(n, index, bodies, s, d);
    d.settings = readDistance(n, bodies, d, std::move(s));
  } else if (type == "universal" || type == "six_dof") {
    notSupported(typeNode, "the joint type \"" + type + "\"; supported: " + std::string(kTypes));
  } else {
    typeNode.fail("unknown joint type \"" + type + "\"; expected one of " + std::string(kTypes));
  }
  return d;
}

}  // namespace inertia::io::detail
