// The joint API of RigidBodySystem: settings checked and turned into a JointRecord (frames in
// each body's frame that coincide at creation), and the accessors. The solver is
// joint_solver.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "inertia/core/error.h"
#include "inertia/core/math.h"
#include "inertia/dynamics/rigid_body_system.h"
#include "joint_solver.h"
#include "rigid_body_data.h"

namespace inertia {

using detail::AxisRows;
using detail::BodyRecord;
using detail::JointRecord;
using detail::kWorldBody;
using Data = detail::RigidBodyData;

namespace {

struct TypeEntry {
  JointType type;
  std::string_view name;
};
constexpr std::array<TypeEntry, 7> kTypes{{{JointType::Ball, "ball"},
                                           {JointType::Hinge, "hinge"},
                                           {JointType::Slider, "slider"},
                                           {JointType::Universal, "universal"},
                                           {JointType::Weld, "weld"},
                                           {JointType::Distance, "distance"},
                                           {JointType::SixDof, "six_dof"}}};

// Throws InvalidArgument "<Settings>::<field> <what>" unless `ok`.
void check(bool ok, std::string_view settings, std::string_view field, std::string_view what) {
  if (ok) return;
  std::string message;
  message.append(settings).append("::").append(field).append(" ").append(what);
  throw InvalidArgument(message);
}

Vec3 unitAxis(const Vec3& axis, const char* settings, const char* field) {
  check(allFinite(axis) && axis.norm() > Real(1e-6), settings, field,
        "must be finite and not zero");
  return axis.normalized();
}

void checkLimits(const std::optional<JointLimits>& l, const char* settings, Real bound) {
  if (!l) return;
  check(std::isfinite(l->lower) && std::isfinite(l->upper), settings, "limits", "must be finite");
  check(l->lower <= l->upper, settings, "limits", "lower must be <= upper");
  check(l->lower >= -bound && l->upper <= bound, settings, "limits", "must lie in [-pi, pi] (rad)");
}

void checkMotor(const std::optional<JointMotor>& m, const char* settings) {
  if (!m) return;
  check(std::isfinite(m->speed), settings, "motor.speed", "must be finite");
  check(std::isfinite(m->maxForce) && m->maxForce >= 0, settings, "motor.maxForce",
        "must be finite and >= 0");
  check(!m->target || std::isfinite(*m->target), settings, "motor.target", "must be finite");
  check(std::isfinite(m->servoFrequency) && m->servoFrequency > 0, settings, "motor.servoFrequency",
        "must be finite and > 0 (Hz)");
}

void checkSpring(const std::optional<JointSpring>& s, const char* settings) {
  if (!s) return;
  check(std::isfinite(s->frequency) && s->frequency > 0, settings, "spring.frequency",
        "must be finite and > 0 (Hz)");
  check(std::isfinite(s->dampingRatio) && s->dampingRatio >= 0, settings, "spring.dampingRatio",
        "must be finite and >= 0");
  check(std::isfinite(s->rest), settings, "spring.rest", "must be finite");
}

// A rotation whose x axis is `x` (unit) and whose y axis is `y` made perpendicular to it (or
// any perpendicular when y is parallel to x).
Quat frameWithAxes(const Vec3& x, const Vec3& yHint) {
  Vec3 y = yHint - yHint.dot(x) * x;
  if (y.norm() < Real(1e-6)) y = x.unitOrthogonal();
  y.normalize();
  Mat3 m;
  m.col(0) = x;
  m.col(1) = y;
  m.col(2) = x.cross(y);
  return Quat(m).normalized();
}

// What every type shares: the bodies, anchors, thresholds and name, checked.
template <class S>
JointRecord commonRecord(Data& D, const S& s, JointType type, const char* name) {
  check(!s.bodyB.isNull(), name, "bodyB", "must be a body (only bodyA may be null: the world)");
  check(D.isValidBody(s.bodyB), name, "bodyB", "is not a valid body");
  check(s.bodyA.isNull() || D.isValidBody(s.bodyA), name, "bodyA", "is not a valid body");
  check(s.bodyA != s.bodyB, name, "bodyB", "must differ from bodyA (a body joined to itself)");
  check(allFinite(s.anchorA), name, "anchorA", "must be finite (m)");
  check(allFinite(s.anchorB), name, "anchorB", "must be finite (m)");
  check(!std::isnan(s.breakForce) && s.breakForce >= 0, name, "breakForce", "must be >= 0 (N)");
  check(!std::isnan(s.breakTorque) && s.breakTorque >= 0, name, "breakTorque",
        "must be >= 0 (N m)");
  JointRecord j;
  j.type = type;
  j.bodyA = s.bodyA.isNull() ? kWorldBody : s.bodyA.index;
  j.bodyB = s.bodyB.index;
  j.frameA.p = s.anchorA;
  j.frameB.p = s.anchorB;
  j.breakForce = s.breakForce;
  j.breakTorque = s.breakTorque;
  j.collideConnected = s.collideConnected;
  j.name = s.name;
  return j;
}

Quat rotationOf(const Data& D, std::uint32_t body) {
  return body == kWorldBody ? Quat::Identity() : D.bodies[body].pose.q;
}

// B's frame rotation that makes its world rotation equal A's frame's now.
void alignFrameB(const Data& D, JointRecord& j) {
  j.frameB.q = rotationOf(D, j.bodyB).conjugate() * rotationOf(D, j.bodyA) * j.frameA.q;
}

}  // namespace

std::string_view jointTypeName(JointType type) {
  for (const auto& t : kTypes)
    if (t.type == type) return t.name;
  return "unknown";
}

namespace {

JointId addJoint(Data& D, JointRecord&& record, const char* name) {
  // A link's joints are solved by their locked rows through its articulation's response
  // (multibody_contacts.h): any type, without limits, motors, springs or friction.
  if (drivenJoint(D, record))
    check(lockedOnly(record), name, D.bodies[record.bodyB].group >= 0 ? "bodyB" : "bodyA",
          "is an articulation's link: a joint on one takes no limits, motor, spring or "
          "friction");
  // The lowest free slot, searched from the lowest that may be free (as for bodies).
  std::uint32_t slot = D.firstFreeJoint;
  while (slot < D.joints.size() && D.joints[slot].alive) ++slot;
  D.firstFreeJoint = slot + 1;
  if (slot == D.joints.size()) D.joints.emplace_back();
  record.generation = D.joints[slot].generation;
  record.alive = true;
  D.joints[slot] = std::move(record);
  JointRecord& j = D.joints[slot];
  if (j.bodyA != kWorldBody) {
    D.bodies[j.bodyA].joints.push_back(slot);
    D.wake(D.bodies[j.bodyA]);
  }
  D.bodies[j.bodyB].joints.push_back(slot);
  D.wake(D.bodies[j.bodyB]);
  if (!j.collideConnected) D.pairsDirty = true;
  ++D.liveJoints;
  return {slot, j.generation};
}

}  // namespace

// A free axis of `settings`' limits, motor, spring and friction, checked.
JointAxis freeAxis(const char* settings, const std::optional<JointLimits>& limits, Real bound,
                   const std::optional<JointMotor>& motor, const std::optional<JointSpring>& spring,
                   Real friction) {
  checkLimits(limits, settings, bound);
  checkMotor(motor, settings);
  checkSpring(spring, settings);
  check(std::isfinite(friction) && friction >= 0, settings, "friction", "must be finite and >= 0");
  return {
      .locked = false, .limits = limits, .motor = motor, .spring = spring, .friction = friction};
}

// Frames on A and B whose x axes are the joint's axis in each body (axisA, axisB), and whose y
// axes are now related by the shortest rotation from A's axis to B's, so that the twist about
// the axis is 0 at creation, also where the axes are apart (a ball joint created at a swing).
void axisFrames(const Data& D, JointRecord& j, const Vec3& axisA, const Vec3& axisB) {
  j.frameA.q = frameWithAxes(axisA, axisA.unitOrthogonal());
  const Quat qA = rotationOf(D, j.bodyA), qB = rotationOf(D, j.bodyB);
  const Quat swing = Quat::FromTwoVectors(qA * axisA, qB * axisB);
  const Vec3 yWorld = swing * (qA * (j.frameA.q * Vec3::UnitY()));
  j.frameB.q = frameWithAxes(axisB, qB.conjugate() * yWorld);
}

JointId RigidBodySystem::createJoint(const BallJointSettings& s) {
  Data& D = *d_;
  const char* name = "BallJointSettings";
  const Vec3 axisA = unitAxis(s.axisA, name, "axisA");
  const Vec3 axisB = unitAxis(s.axisB, name, "axisB");
  check(!s.coneLimit || (*s.coneLimit > 0 && *s.coneLimit < Real(std::numbers::pi)), name,
        "coneLimit", "must be in (0, pi) (rad)");
  checkLimits(s.twistLimits, name, Real(std::numbers::pi));
  check(std::isfinite(s.friction) && s.friction >= 0, name, "friction", "must be finite and >= 0");
  JointRecord j = commonRecord(D, s, JointType::Ball, name);
  axisFrames(D, j, axisA, axisB);
  j.coneLimit = s.coneLimit;
  j.axes[3] = {.locked = false, .limits = s.twistLimits};
  j.friction = s.friction;
  return addJoint(D, std::move(j), name);
}

JointId RigidBodySystem::createJoint(const HingeJointSettings& s) {
  Data& D = *d_;
  const char* name = "HingeJointSettings";
  const Vec3 axisA = unitAxis(s.axisA, name, "axisA");
  const Vec3 axisB = unitAxis(s.axisB, name, "axisB");
  const JointAxis angle =
      freeAxis(name, s.limits, Real(std::numbers::pi), s.motor, s.spring, s.friction);
  JointRecord j = commonRecord(D, s, JointType::Hinge, name);
  axisFrames(D, j, axisA, axisB);
  j.axes[3] = angle;
  return addJoint(D, std::move(j), name);
}

JointId RigidBodySystem::createJoint(const SliderJointSettings& s) {
  Data& D = *d_;
  const char* name = "SliderJointSettings";
  const Vec3 axisA = unitAxis(s.axisA, name, "axisA");
  const JointAxis position = freeAxis(name, s.limits, std::numeric_limits<Real>::infinity(),
                                      s.motor, s.spring, s.friction);
  JointRecord j = commonRecord(D, s, JointType::Slider, name);
  j.frameA.q = frameWithAxes(axisA, axisA.unitOrthogonal());
  alignFrameB(D, j);
  const Transform fa = worldFrame(D, j.bodyA, j.frameA);
  const Transform fb = worldFrame(D, j.bodyB, j.frameB);
  j.reference = (fa.q * Vec3::UnitX()).dot(fb.p - fa.p);
  j.axes[0] = position;
  return addJoint(D, std::move(j), name);
}

JointId RigidBodySystem::createJoint(const UniversalJointSettings& s) {
  Data& D = *d_;
  const char* name = "UniversalJointSettings";
  const Vec3 axisA = unitAxis(s.axisA, name, "axisA");
  const Vec3 axisB = unitAxis(s.axisB, name, "axisB");
  checkLimits(s.limitsA, name, Real(std::numbers::pi));
  checkLimits(s.limitsB, name, Real(std::numbers::pi / 2));
  JointRecord j = commonRecord(D, s, JointType::Universal, name);
  // Frame A: x along axisA, y along axisB now; B's frame coincides with it now. The joint is
  // then a six-DOF joint with rx (about axisA) and ry (about axisB) free: R = Rx(a) Ry(b).
  const Vec3 bInA = rotationOf(D, j.bodyA).conjugate() * (rotationOf(D, j.bodyB) * axisB);
  check(std::abs(bInA.dot(axisA)) < Real(1e-3), name, "axisB",
        "must be perpendicular to axisA at creation");
  j.frameA.q = frameWithAxes(axisA, bInA);
  alignFrameB(D, j);
  j.axes[3] = {.locked = false, .limits = s.limitsA};
  j.axes[4] = {.locked = false, .limits = s.limitsB};
  return addJoint(D, std::move(j), name);
}

JointId RigidBodySystem::createJoint(const SixDofJointSettings& s) {
  Data& D = *d_;
  const char* name = "SixDofJointSettings";
  check(allFinite(s.frameA.p) && allFinite(s.frameA.q) && s.frameA.q.norm() > Real(1e-6), name,
        "frameA", "must be finite with a non-zero orientation");
  check(allFinite(s.frameB.p) && allFinite(s.frameB.q) && s.frameB.q.norm() > Real(1e-6), name,
        "frameB", "must be finite with a non-zero orientation");
  static constexpr std::array<const char*, 6> kAxes{
      "SixDofJointSettings::axes[0] (x)",  "SixDofJointSettings::axes[1] (y)",
      "SixDofJointSettings::axes[2] (z)",  "SixDofJointSettings::axes[3] (rx)",
      "SixDofJointSettings::axes[4] (ry)", "SixDofJointSettings::axes[5] (rz)"};
  for (std::size_t i = 0; i < 6; ++i) {
    const JointAxis& a = s.axes[i];
    const char* field = kAxes[i];
    const Real bound = i < 3 ? std::numeric_limits<Real>::infinity()
                             : Real(i == 4 ? std::numbers::pi / 2 : std::numbers::pi);
    if (!a.locked) freeAxis(field, a.limits, bound, a.motor, a.spring, a.friction);
  }
  BallJointSettings anchors{.bodyA = s.bodyA,
                            .bodyB = s.bodyB,
                            .anchorA = s.frameA.p,
                            .anchorB = s.frameB.p,
                            .breakForce = s.breakForce,
                            .breakTorque = s.breakTorque,
                            .collideConnected = s.collideConnected,
                            .name = s.name};
  JointRecord j = commonRecord(D, anchors, JointType::SixDof, name);
  j.frameA.q = s.frameA.q.normalized();
  j.frameB.q = s.frameB.q.normalized();
  j.axes = s.axes;
  return addJoint(D, std::move(j), name);
}

JointId RigidBodySystem::createJoint(const WeldJointSettings& s) {
  Data& D = *d_;
  const char* name = "WeldJointSettings";
  checkSpring(s.spring, name);
  JointRecord j = commonRecord(D, s, JointType::Weld, name);
  alignFrameB(D, j);
  j.spring = s.spring;
  return addJoint(D, std::move(j), name);
}

JointId RigidBodySystem::createJoint(const DistanceJointSettings& s) {
  Data& D = *d_;
  const char* name = "DistanceJointSettings";
  checkSpring(s.spring, name);
  check(std::isfinite(s.length) && std::isfinite(s.minLength) && std::isfinite(s.maxLength), name,
        "length", "and minLength, maxLength must be finite (m)");
  JointRecord j = commonRecord(D, s, JointType::Distance, name);
  const Real now = (worldFrame(D, j.bodyB, j.frameB).p - worldFrame(D, j.bodyA, j.frameA).p).norm();
  j.length = s.length < 0 ? now : s.length;
  j.minLength = s.minLength < 0 ? j.length : s.minLength;
  j.maxLength = s.maxLength < 0 ? j.length : s.maxLength;
  check(j.minLength <= j.maxLength, name, "minLength", "must be <= maxLength");
  j.spring = s.spring;
  return addJoint(D, std::move(j), name);
}

void RigidBodySystem::destroyJoint(JointId id) {
  Data& D = *d_;
  JointRecord& j = D.joint(id);
  const std::uint32_t slot = id.index;
  for (std::uint32_t body : {j.bodyA, j.bodyB}) {
    if (body == kWorldBody) continue;
    std::vector<std::uint32_t>& list = D.bodies[body].joints;
    list.erase(std::remove(list.begin(), list.end(), slot), list.end());
    D.wake(D.bodies[body]);
  }
  if (!j.collideConnected) D.pairsDirty = true;
  const std::uint32_t generation = j.generation + 1;
  j = JointRecord{};
  j.generation = generation;
  --D.liveJoints;
  D.firstFreeJoint = std::min(D.firstFreeJoint, slot);
}

bool RigidBodySystem::isValid(JointId id) const { return d_->isValidJoint(id); }
JointType RigidBodySystem::jointType(JointId id) const { return d_->joint(id).type; }
std::string_view RigidBodySystem::jointName(JointId id) const { return d_->joint(id).name; }

BodyId RigidBodySystem::jointBodyA(JointId id) const {
  const JointRecord& j = d_->joint(id);
  return j.bodyA == kWorldBody ? BodyId{} : d_->bodyId(j.bodyA);
}

BodyId RigidBodySystem::jointBodyB(JointId id) const { return d_->bodyId(d_->joint(id).bodyB); }

void RigidBodySystem::setJointEnabled(JointId id, bool enabled) {
  Data& D = *d_;
  JointRecord& j = D.joint(id);
  if (j.enabled == enabled) return;
  j.enabled = enabled;
  j.parts = {};
  if (enabled) j.broken = false;
  for (std::uint32_t body : {j.bodyA, j.bodyB})
    if (body != kWorldBody) D.wake(D.bodies[body]);
}

bool RigidBodySystem::isJointEnabled(JointId id) const { return d_->joint(id).enabled; }
bool RigidBodySystem::isJointBroken(JointId id) const { return d_->joint(id).broken; }

namespace {
void wakeJoint(Data& D, const JointRecord& j) {
  for (std::uint32_t body : {j.bodyA, j.bodyB})
    if (body != kWorldBody) D.wake(D.bodies[body]);
}
}  // namespace

namespace {
// A link's joint keeps to its locked rows (addJoint): `change` is undone and refused where it
// would give one a limit, motor, spring or friction.
// Out of line: a message built by concatenation (GCC 12's false -Warray-bounds when inlined).
[[gnu::noinline]] void refuseLinkJointChange(const char* what) {
  require(false, std::string(what) +
                     ": the joint joins an articulation's link, whose joints take no limits, "
                     "motor, spring or friction");
}

template <class F>
void changeJoint(const Data& D, JointRecord& j, const char* what, F change) {
  if (!drivenJoint(D, j)) return change();
  const JointRecord before = j;
  change();
  if (lockedOnly(j)) return;
  j = before;
  refuseLinkJointChange(what);
}

// The degree of freedom a hinge's or slider's motor, limits and spring act on.
JointAxis& primaryAxis(JointRecord& j, AxisRows*& rows, const char* what) {
  require(j.type == JointType::Hinge || j.type == JointType::Slider,
          std::string(what) + ": only hinge and slider joints have one (six-DOF: setJointAxis)");
  const std::size_t k = j.type == JointType::Hinge ? 3 : 0;
  rows = &j.parts.axes[k];
  return j.axes[k];
}
}  // namespace

void RigidBodySystem::setJointMotor(JointId id, const std::optional<JointMotor>& motor) {
  JointRecord& j = d_->joint(id);
  AxisRows* rows = nullptr;
  JointAxis& axis = primaryAxis(j, rows, "setJointMotor");
  checkMotor(motor, "setJointMotor");
  changeJoint(*d_, j, "setJointMotor", [&] { axis.motor = motor; });
  rows->motor = 0;
  wakeJoint(*d_, j);
}

void RigidBodySystem::setJointLimits(JointId id, const std::optional<JointLimits>& limits) {
  JointRecord& j = d_->joint(id);
  AxisRows* rows = nullptr;
  JointAxis& axis = primaryAxis(j, rows, "setJointLimits");
  checkLimits(
      limits, "setJointLimits",
      j.type == JointType::Hinge ? Real(std::numbers::pi) : std::numeric_limits<Real>::infinity());
  changeJoint(*d_, j, "setJointLimits", [&] { axis.limits = limits; });
  rows->lower = rows->upper = 0;
  wakeJoint(*d_, j);
}

void RigidBodySystem::setJointSpring(JointId id, const std::optional<JointSpring>& spring) {
  JointRecord& j = d_->joint(id);
  checkSpring(spring, "setJointSpring");
  if (j.type == JointType::Weld || j.type == JointType::Distance) {
    changeJoint(*d_, j, "setJointSpring", [&] { j.spring = spring; });
    j.parts.axes[0].spring = 0;
  } else {
    AxisRows* rows = nullptr;
    JointAxis& axis = primaryAxis(j, rows, "setJointSpring");
    changeJoint(*d_, j, "setJointSpring", [&] { axis.spring = spring; });
    rows->spring = 0;
  }
  wakeJoint(*d_, j);
}

void RigidBodySystem::setJointAxis(JointId id, int axis, const JointAxis& settings) {
  JointRecord& j = d_->joint(id);
  require(j.type == JointType::SixDof, "setJointAxis: only six-DOF joints have axes to set");
  require(axis >= 0 && axis < 6, "setJointAxis: axis must be 0..5 (x, y, z, rx, ry, rz)");
  if (!settings.locked)
    freeAxis("setJointAxis", settings.limits,
             axis < 3 ? std::numeric_limits<Real>::infinity()
                      : Real(axis == 4 ? std::numbers::pi / 2 : std::numbers::pi),
             settings.motor, settings.spring, settings.friction);
  changeJoint(*d_, j, "setJointAxis", [&] { j.axes[std::size_t(axis)] = settings; });
  j.parts.axes[std::size_t(axis)] = {};
  j.parts.lockImpulse.setZero();  // its rows change
  wakeJoint(*d_, j);
}

Real RigidBodySystem::jointAxisCoordinate(JointId id, int axis) const {
  require(axis >= 0 && axis < 6, "jointAxisCoordinate: axis must be 0..5 (x, y, z, rx, ry, rz)");
  return detail::axisCoordinate(*d_, d_->joint(id), axis);
}

Vec3 RigidBodySystem::jointForce(JointId id) const { return d_->joint(id).force; }
Vec3 RigidBodySystem::jointTorque(JointId id) const { return d_->joint(id).torque; }
Real RigidBodySystem::jointCoordinate(JointId id) const {
  return detail::jointCoordinate(*d_, d_->joint(id));
}
JointError RigidBodySystem::jointError(JointId id) const {
  return detail::jointError(*d_, d_->joint(id));
}
Vec3 RigidBodySystem::jointAnchorA(JointId id) const {
  const JointRecord& j = d_->joint(id);
  return worldFrame(*d_, j.bodyA, j.frameA).p;
}
Vec3 RigidBodySystem::jointAnchorB(JointId id) const {
  const JointRecord& j = d_->joint(id);
  return worldFrame(*d_, j.bodyB, j.frameB).p;
}
Transform RigidBodySystem::jointFrameA(JointId id) const {
  const JointRecord& j = d_->joint(id);
  return worldFrame(*d_, j.bodyA, j.frameA);
}
Transform RigidBodySystem::jointFrameB(JointId id) const {
  const JointRecord& j = d_->joint(id);
  return worldFrame(*d_, j.bodyB, j.frameB);
}
const JointAxis& RigidBodySystem::jointAxis(JointId id, int axis) const {
  require(axis >= 0 && axis < 6, "jointAxis: axis must be 0..5 (x, y, z, rx, ry, rz)");
  return d_->joint(id).axes[std::size_t(axis)];
}
int RigidBodySystem::jointCount() const { return d_->liveJoints; }

std::vector<JointId> RigidBodySystem::joints() const {
  std::vector<JointId> ids;
  for (std::uint32_t i = 0; i < d_->joints.size(); ++i)
    if (d_->joints[i].alive) ids.push_back({i, d_->joints[i].generation});
  return ids;
}

const std::vector<JointEvent>& RigidBodySystem::jointEvents() const { return d_->jointEvents; }

}  // namespace inertia
