#include "joint_solver.h"

#include <cmath>
#include <numbers>

namespace inertia::detail {

namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
// Box2D v3's joint softness in the soft step: twice the contacts' stiffness, damping ratio 2.
constexpr Real kJointHertzScale = 2;
constexpr Real kJointDampingRatio = 2;

// A joint's geometry in the current substep, from its bodies' motion since the step's start.
struct Frame {
  Vec3 rA, rB;  // anchors minus centres of mass (m, world)
  Vec3 d;       // B's anchor minus A's (m)
  Quat qA, qB;  // the joint's frames on A and B (world rotations)
};

Frame currentFrame(const JointConstraint& c, const SolverBody& a, const SolverBody& b) {
  Frame f;
  f.rA = a.dR * c.rA;
  f.rB = b.dR * c.rB;
  f.d = (b.dp - a.dp) + (f.rB - f.rA) + c.deltaCenter;
  f.qA = a.dq * c.frameA;
  f.qB = b.dq * c.frameB;
  return f;
}

// The rotation that takes frame A to frame B, as a rotation vector in world axes (rad): twice
// the vector part of qA^-1 qB for small angles, the error of a locked rotation.
Vec3 rotationError(const Quat& qA, const Quat& qB) {
  Quat r = qA.conjugate() * qB;
  if (r.w() < 0) r.coeffs() = -r.coeffs();
  return qA * (2 * r.vec());
}

// B's rotation about frame A's x axis relative to A (rad, in (-pi, pi]): the twist of
// qA^-1 qB about x.
Real twistAngle(const Quat& qA, const Quat& qB) {
  const Quat r = qA.conjugate() * qB;
  Real angle = 2 * std::atan2(r.x(), r.w());
  if (angle > Real(std::numbers::pi)) angle -= Real(2 * std::numbers::pi);
  if (angle <= -Real(std::numbers::pi)) angle += Real(2 * std::numbers::pi);
  return angle;
}

Vec3 axisOf(const Quat& q, int i) { return q * Vec3::Unit(i); }

// The rows of each part a type uses, for the current frame.
void setRows(JointConstraint& c, const JointRecord& j, const Frame& f) {
  JointParts& p = c.parts;
  const auto anchors = [&] {
    for (int i = 0; i < 3; ++i) p.point.rows[std::size_t(i)] = linearRow(Vec3::Unit(i), f.rA, f.rB);
  };
  const auto rotation = [&] {
    for (int i = 0; i < 3; ++i) p.rotation.rows[std::size_t(i)] = angularRow(Vec3::Unit(i));
  };
  switch (j.type) {
    case JointType::Ball:
      anchors();
      for (int i = 0; i < 3; ++i) p.spin.rows[std::size_t(i)] = angularRow(Vec3::Unit(i));
      break;
    case JointType::Hinge: {
      anchors();
      const Vec3 axisB = axisOf(f.qB, 0);
      // C = (axisB . b, axisB . c) for A's perpendiculars b, c: dC/dt = (wB - wA) . (axisB x b).
      p.aligned.rows[0] = angularRow(axisB.cross(axisOf(f.qA, 1)));
      p.aligned.rows[1] = angularRow(axisB.cross(axisOf(f.qA, 2)));
      p.axis.row = angularRow(axisOf(f.qA, 0));
      break;
    }
    case JointType::Slider: {
      rotation();
      // A's axes turn with A: the rows' lever arm on A reaches B's anchor (rA + d).
      const Vec3 armA = f.rA + f.d;
      p.offAxis.rows[0] = linearRow(axisOf(f.qA, 1), armA, f.rB);
      p.offAxis.rows[1] = linearRow(axisOf(f.qA, 2), armA, f.rB);
      p.axis.row = linearRow(axisOf(f.qA, 0), armA, f.rB);
      break;
    }
    case JointType::Weld:
      anchors();
      rotation();
      break;
    case JointType::Distance: {
      const Real length = f.d.norm();
      const Vec3 n = length > Real(1e-6) ? Vec3(f.d / length) : c.fallbackAxis;
      p.axis.row = linearRow(n, f.rA, f.rB);
      break;
    }
  }
}

// The free coordinate's spring, motor, friction and limits, in Box2D v3's order.
void driveAxis(JointConstraint& c, const JointRecord& j, SolverBody& a, SolverBody& b,
               Real coordinate, const JointPass& pass) {
  AxisRows& ax = c.parts.axis;
  if (j.spring && !pass.relax)
    ax.solveSoft(a, b, ax.spring, coordinate - j.spring->rest, c.spring, kInfinity);
  if (j.motor && j.motor->maxForce > 0) {
    const Real maxImpulse = j.motor->maxForce * pass.h;
    if (j.motor->target) {
      if (!pass.relax)
        ax.solveSoft(a, b, ax.motor, coordinate - *j.motor->target, c.servo, maxImpulse);
    } else
      ax.solveMotor(a, b, ax.motor, j.motor->speed, maxImpulse);
  }
  if (j.friction > 0) ax.solveMotor(a, b, ax.friction, 0, j.friction * pass.h);
  if (j.limits) {
    ax.solveLimit(a, b, ax.lower, coordinate - j.limits->lower, 1, pass.rigid, pass.invH);
    ax.solveLimit(a, b, ax.upper, j.limits->upper - coordinate, -1, pass.rigid, pass.invH);
  }
}

void solveBall(JointConstraint& c, const JointRecord& j, SolverBody& a, SolverBody& b,
               const Frame& f, const JointPass& pass) {
  if (j.friction > 0) c.parts.spin.solveFriction(a, b, j.friction * pass.h);
  c.parts.point.solve(a, b, f.d, pass.rigid);
}

void solveHinge(JointConstraint& c, const JointRecord& j, SolverBody& a, SolverBody& b,
                const Frame& f, const JointPass& pass) {
  driveAxis(c, j, a, b, twistAngle(f.qA, f.qB), pass);
  const Vec3 axisB = axisOf(f.qB, 0);
  c.parts.aligned.solve(
      a, b, Eigen::Matrix<Real, 2, 1>(axisB.dot(axisOf(f.qA, 1)), axisB.dot(axisOf(f.qA, 2))),
      pass.rigid);
  // The anchors last: of all the rows, their error shows most (Box2D v3's order).
  c.parts.point.solve(a, b, f.d, pass.rigid);
}

void solveSlider(JointConstraint& c, const JointRecord& j, SolverBody& a, SolverBody& b,
                 const Frame& f, const JointPass& pass) {
  driveAxis(c, j, a, b, axisOf(f.qA, 0).dot(f.d) - j.reference, pass);
  c.parts.rotation.solve(a, b, rotationError(f.qA, f.qB), pass.rigid);
  c.parts.offAxis.solve(
      a, b, Eigen::Matrix<Real, 2, 1>(axisOf(f.qA, 1).dot(f.d), axisOf(f.qA, 2).dot(f.d)),
      pass.rigid);
}

void solveWeld(JointConstraint& c, const JointRecord& j, SolverBody& a, SolverBody& b,
               const Frame& f, const JointPass& pass) {
  if (j.spring && pass.relax) return;
  const Softness& soft = j.spring ? c.spring : pass.rigid;
  c.parts.rotation.solve(a, b, rotationError(f.qA, f.qB), soft);
  c.parts.point.solve(a, b, f.d, soft);
}

void solveDistance(JointConstraint& c, const JointRecord& j, SolverBody& a, SolverBody& b,
                   const Frame& f, const JointPass& pass) {
  AxisRows& ax = c.parts.axis;
  const Real length = f.d.norm();
  if (j.minLength < j.maxLength) {
    if (j.spring && !pass.relax)
      ax.solveSoft(a, b, ax.spring, length - j.length, c.spring, kInfinity);
    ax.solveLimit(a, b, ax.lower, length - j.minLength, 1, pass.rigid, pass.invH);
    ax.solveLimit(a, b, ax.upper, j.maxLength - length, -1, pass.rigid, pass.invH);
  } else if (j.spring) {
    if (!pass.relax) ax.solveSoft(a, b, ax.spring, length - j.length, c.spring, kInfinity);
  } else {
    ax.solveSoft(a, b, ax.lock, length - j.length, pass.rigid, kInfinity);
  }
}

// Runs f(a, b) on copies of the joint's two solver bodies (a zero body for the world or a
// static body), and writes back the velocities of the moving ones only: a static or kinematic
// body may be shared by joints solved at the same time.
template <class F>
void withBodies(const JointConstraint& c, std::vector<SolverBody>& bodies, F f) {
  const SolverBody none{};
  SolverBody a = c.bodyA >= 0 ? bodies[std::size_t(c.bodyA)] : none;
  SolverBody b = c.bodyB >= 0 ? bodies[std::size_t(c.bodyB)] : none;
  f(a, b);
  for (const auto& [index, body] : {std::pair{c.bodyA, &a}, std::pair{c.bodyB, &b}}) {
    if (index < 0 || body->invMass == 0) continue;
    bodies[std::size_t(index)].v = body->v;
    bodies[std::size_t(index)].w = body->w;
  }
}

}  // namespace

JointPass jointPass(const DynamicsSettings& s, Real h, bool useBias) {
  JointPass pass;
  pass.h = h;
  pass.invH = 1 / h;
  pass.relax = !useBias;
  if (!useBias) {
    pass.rigid = {0, 1, 0};
  } else if (s.solver.type == SolverType::SoftStep) {
    const Real hertz = std::min(s.contact.hertz, Real(0.25) / h);
    pass.rigid = makeSoft(kJointHertzScale * hertz, kJointDampingRatio, h);
  } else {
    pass.rigid = {s.contact.baumgarte * pass.invH, 1, 0};
  }
  return pass;
}

void prepareJoints(RigidBodyData& D, const DynamicsSettings&, Real h, StepWorkers& workers) {
  workers.parallelFor(D.jointConstraints.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      JointConstraint& c = D.jointConstraints[k];
      const JointRecord& j = D.joints[c.joint];
      const bool world = j.bodyA == kWorldBody;
      const Transform poseA = world ? Transform{} : D.bodies[j.bodyA].pose;
      const Vec3 comA = world ? Vec3::Zero() : D.bodies[j.bodyA].com;
      const BodyRecord& b = D.bodies[j.bodyB];
      c.rA = poseA.apply(j.frameA.p) - comA;
      c.rB = b.pose.apply(j.frameB.p) - b.com;
      c.deltaCenter = b.com - comA;
      c.frameA = poseA.q * j.frameA.q;
      c.frameB = b.pose.q * j.frameB.q;
      c.spring = j.spring ? makeSoft(j.spring->frequency, j.spring->dampingRatio, h) : Softness{};
      c.servo = j.motor ? makeSoft(j.motor->servoFrequency, 1, h) : Softness{};
      const Vec3 d = c.deltaCenter + c.rB - c.rA;
      c.fallbackAxis = d.norm() > Real(1e-6) ? Vec3(d.normalized()) : axisOf(c.frameA, 0);
      c.parts = j.parts;
    }
  });
}

void warmStartJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies) {
  const JointRecord& j = D.joints[c.joint];
  withBodies(c, bodies, [&](SolverBody& a, SolverBody& b) {
    setRows(c, j, currentFrame(c, a, b));
    JointParts& p = c.parts;
    switch (j.type) {
      case JointType::Ball:
        p.spin.warmStart(a, b);
        p.point.warmStart(a, b);
        break;
      case JointType::Hinge:
        p.axis.warmStart(a, b);
        p.aligned.warmStart(a, b);
        p.point.warmStart(a, b);
        break;
      case JointType::Slider:
        p.axis.warmStart(a, b);
        p.rotation.warmStart(a, b);
        p.offAxis.warmStart(a, b);
        break;
      case JointType::Weld:
        p.rotation.warmStart(a, b);
        p.point.warmStart(a, b);
        break;
      case JointType::Distance:
        p.axis.warmStart(a, b);
        break;
    }
  });
}

void solveJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                const JointPass& pass) {
  const JointRecord& j = D.joints[c.joint];
  withBodies(c, bodies, [&](SolverBody& a, SolverBody& b) {
    const Frame f = currentFrame(c, a, b);
    setRows(c, j, f);
    switch (j.type) {
      case JointType::Ball:
        return solveBall(c, j, a, b, f, pass);
      case JointType::Hinge:
        return solveHinge(c, j, a, b, f, pass);
      case JointType::Slider:
        return solveSlider(c, j, a, b, f, pass);
      case JointType::Weld:
        return solveWeld(c, j, a, b, f, pass);
      case JointType::Distance:
        return solveDistance(c, j, a, b, f, pass);
    }
  });
}

void storeJoints(RigidBodyData& D, Real h) {
  for (JointConstraint& c : D.jointConstraints) {
    JointRecord& j = D.joints[c.joint];
    j.parts = c.parts;
    Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
    const JointParts& p = c.parts;
    p.point.reaction(linear, angular);
    p.offAxis.reaction(linear, angular);
    p.rotation.reaction(linear, angular);
    p.aligned.reaction(linear, angular);
    p.spin.reaction(linear, angular);
    p.axis.reaction(linear, angular);
    j.force = linear / h;
    j.torque = angular / h;
    if (j.force.norm() > j.breakForce || j.torque.norm() > j.breakTorque) {
      j.broken = true;
      j.enabled = false;
      j.parts = {};
      D.jointEvents.push_back({{c.joint, j.generation}, j.force, j.torque});
    }
  }
}

JointError jointError(const RigidBodyData& D, const JointRecord& j) {
  const Transform poseA = j.bodyA == kWorldBody ? Transform{} : D.bodies[j.bodyA].pose;
  const Transform fa = poseA * j.frameA;
  const Transform fb = D.bodies[j.bodyB].pose * j.frameB;
  const Vec3 d = fb.p - fa.p;
  const Vec3 x = axisOf(fa.q, 0);
  JointError e;
  switch (j.type) {
    case JointType::Ball:
      e.position = d.norm();
      break;
    case JointType::Hinge:
      e.position = d.norm();
      e.angle = std::acos(std::clamp(x.dot(axisOf(fb.q, 0)), Real(-1), Real(1)));
      break;
    case JointType::Slider:
      e.position = (d - x.dot(d) * x).norm();
      e.angle = rotationError(fa.q, fb.q).norm();
      break;
    case JointType::Weld:
      e.position = d.norm();
      e.angle = rotationError(fa.q, fb.q).norm();
      break;
    case JointType::Distance: {
      const Real length = d.norm();
      e.position = std::max({j.minLength - length, length - j.maxLength, Real(0)});
      break;
    }
  }
  return e;
}

Real jointCoordinate(const RigidBodyData& D, const JointRecord& j) {
  const Transform poseA = j.bodyA == kWorldBody ? Transform{} : D.bodies[j.bodyA].pose;
  const Transform fa = poseA * j.frameA;
  const Transform fb = D.bodies[j.bodyB].pose * j.frameB;
  switch (j.type) {
    case JointType::Hinge:
      return twistAngle(fa.q, fb.q);
    case JointType::Slider:
      return axisOf(fa.q, 0).dot(fb.p - fa.p) - j.reference;
    case JointType::Distance:
      return (fb.p - fa.p).norm();
    default:
      return 0;
  }
}

}  // namespace inertia::detail
