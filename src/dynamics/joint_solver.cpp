#include "joint_solver.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "inertia/core/math.h"
#include "lcp_contact.h"

namespace inertia::detail {

namespace {

using Frame = JointFrame;

// A joint's geometry in the current substep, from its bodies' motion since the step's start.
Frame currentFrame(const JointConstraint& c, const SolverBody& a, const SolverBody& b) {
  Frame f;
  f.rA = times(a.dR, c.rA);
  f.rB = times(b.dR, c.rB);
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

// X-Y-Z Euler angles of qA^-1 qB (B's frame relative to A's: R = Rx(a) Ry(b) Rz(c)), and the
// world axes whose velocity rows measure their rates: with e1 = A's x, e3 = B's z and
// e2 = e3 x e1 / |e3 x e1| the relative angular velocity is a' e1 + b' e2 + c' e3, so the
// rates are its components on the dual basis (Bullet's generic 6-DOF joint, exactly).
struct EulerFrame {
  Vec3 angles;
  std::array<Vec3, 3> rateAxes;
};

EulerFrame eulerFrame(const Quat& qA, const Quat& qB) {
  const Mat3 R = (qA.conjugate() * qB).toRotationMatrix();
  EulerFrame e;
  e.angles = Vec3(std::atan2(-R(1, 2), R(2, 2)), std::asin(std::clamp(R(0, 2), Real(-1), Real(1))),
                  std::atan2(-R(0, 1), R(0, 0)));
  const Vec3 e1 = axisOf(qA, 0), e3 = axisOf(qB, 2);
  Vec3 e2 = e3.cross(e1);
  const Real n = e2.norm();
  // At the gimbal lock (ry = +-pi/2) e1 and e3 align: A's y stands in for e2.
  e2 = n > Real(1e-6) ? Vec3(e2 / n) : axisOf(qA, 1);
  const Vec3 d1 = e2.cross(e3), d3 = e1.cross(e2);
  const Real s1 = e1.dot(d1), s3 = e3.dot(d3);
  e.rateAxes = {std::abs(s1) > Real(1e-6) ? Vec3(d1 / s1) : e1, e2,
                std::abs(s3) > Real(1e-6) ? Vec3(d3 / s3) : e3};
  return e;
}

// Swing-twist decomposition of qA^-1 qB about the x axis, q = swing twist: the swing's angle
// (rad, >= 0) and world axis, the twist angle (rad, in (-pi, pi]), and the world axis whose
// velocity row measures the twist's rate.
//
// The rates: with q = (w, v) and the relative angular velocity in A's frame u = qA^-1 (wB - wA),
// dq/dt = 1/2 (0, u) q. The swing is the angle between x and b = q x, so its rate is
// u . (x cross b) / |x cross b|: the swing axis. The twist is 2 atan2(v_x, w), whose rate is
// u . g with
//   g = (w^2 x + w (v cross x) + v_x v) / (w^2 + v_x^2),
// which is (x + b) / (1 + x . b) at zero twist: B's own x axis, the obvious row, is wrong by
// half the swing and makes a twist limit at a wide swing (a raised arm) pump energy in.
struct SwingTwist {
  Real swing = 0;
  Vec3 swingAxis = Vec3::UnitY();
  Real twist = 0;
  Vec3 twistAxis = Vec3::UnitX();
};

SwingTwist swingTwist(const Quat& qA, const Quat& qB) {
  const Quat q = qA.conjugate() * qB;
  SwingTwist st;
  st.twist = twistAngle(qA, qB);
  const Real norm2 = q.w() * q.w() + q.x() * q.x();
  // cos^2 of half the swing: near a swing of pi the twist is undefined and B's axis stands in.
  st.twistAxis = norm2 > Real(1e-4)
                     ? Vec3(qA * ((q.w() * q.w() * Vec3::UnitX() +
                                   q.w() * q.vec().cross(Vec3::UnitX()) + q.x() * q.vec()) /
                                  norm2))
                     : axisOf(qB, 0);
  const Real t = std::hypot(q.w(), q.x());
  const Quat twist = t > Real(1e-9) ? Quat(q.w() / t, q.x() / t, 0, 0) : Quat::Identity();
  Quat swing = q * twist.conjugate();
  if (swing.w() < 0) swing.coeffs() = -swing.coeffs();
  const Real s = swing.vec().norm();
  st.swing = 2 * std::atan2(s, swing.w());
  if (s > Real(1e-9)) st.swingAxis = qA * Vec3(swing.vec() / s);
  return st;
}

}  // namespace

void lockedRows(const JointRecord& j, const JointFrame& f, const Vec3& fallbackAxis, RowBlock& lock,
                RowBlock::Vector& C) {
  lock.clear();
  C.resize(RowBlock::kMax);
  const auto row = [&](const JointRow& r, Real error) {
    C(lock.count) = error;
    lock.add(r);
  };
  const auto anchors = [&] {
    for (int i = 0; i < 3; ++i) row(linearRow(Vec3::Unit(i), f.rA, f.rB), f.d(i));
  };
  const auto rotation = [&] {
    const Vec3 e = rotationError(f.qA, f.qB);
    for (int i = 0; i < 3; ++i) row(angularRow(Vec3::Unit(i)), e(i));
  };
  // Rows along A's axes turn with A: their lever arm on A reaches B's anchor (rA + d).
  const Vec3 armA = f.rA + f.d;
  switch (j.type) {
    case JointType::Ball:
      lock.setPoint(f.rA, f.rB);
      C.head<3>() = f.d;
      break;
    case JointType::Hinge: {
      anchors();
      const Vec3 axisB = axisOf(f.qB, 0);
      // C = axisB . b for A's perpendiculars b: dC/dt = (wB - wA) . (axisB x b).
      for (int i = 1; i < 3; ++i) {
        const Vec3 b = axisOf(f.qA, i);
        row(angularRow(axisB.cross(b)), axisB.dot(b));
      }
      break;
    }
    case JointType::Slider:
      rotation();
      for (int i = 1; i < 3; ++i) {
        const Vec3 e = axisOf(f.qA, i);
        row(linearRow(e, armA, f.rB), e.dot(f.d));
      }
      break;
    case JointType::Weld:
      anchors();
      rotation();
      break;
    case JointType::Universal:
    case JointType::SixDof: {
      const auto& ax = j.axes;
      if (ax[0].locked && ax[1].locked && ax[2].locked) {
        anchors();
      } else {
        for (int i = 0; i < 3; ++i)
          if (ax[std::size_t(i)].locked) {
            const Vec3 e = axisOf(f.qA, i);
            row(linearRow(e, armA, f.rB), e.dot(f.d));
          }
      }
      if (ax[3].locked && ax[4].locked && ax[5].locked) {
        rotation();
      } else {
        const EulerFrame e = eulerFrame(f.qA, f.qB);
        for (int i = 0; i < 3; ++i)
          if (ax[std::size_t(3 + i)].locked)
            row(angularRow(e.rateAxes[std::size_t(i)]), e.angles(i));
      }
      break;
    }
    case JointType::Distance:
      if (j.minLength == j.maxLength && !j.spring) {
        const Real length = f.d.norm();
        row(linearRow(length > Real(1e-6) ? Vec3(f.d / length) : fallbackAxis, f.rA, f.rB),
            length - j.length);
      }
      break;
  }
  C.conservativeResize(lock.count);
}

namespace {

// The rows of the free coordinates in the current frame, prepared, and the coordinates: per
// degree of freedom (x, y, z, rx, ry, rz) the value its rows drive, a ball joint's swing apart.
void freeRows(JointConstraint& c, const JointRecord& j, const Frame& f, JointParts& p,
              const SolverBody& a, const SolverBody& b) {
  const Vec3 armA = f.rA + f.d;
  const auto use = [&](std::size_t k, const JointRow& row, Real coordinate) {
    p.axes[k].row = row;
    p.axes[k].prepare(a, b);
    c.coordinate[k] = coordinate;
  };
  switch (j.type) {
    case JointType::Ball:
      // Only the rows the joint uses: most ball joints have none of them.
      if (j.friction > 0) {
        for (int i = 0; i < 3; ++i) p.spin.rows[std::size_t(i)] = angularRow(Vec3::Unit(i));
        p.spin.count = 3;
        p.spin.prepare(a, b, RowBlock::Vector::Zero(3));
      }
      if (j.coneLimit || j.axes[3].limits) {
        const SwingTwist st = swingTwist(f.qA, f.qB);
        p.cone.row = angularRow(st.swingAxis);
        p.cone.prepare(a, b);
        c.swing = st.swing;
        use(3, angularRow(st.twistAxis), st.twist);
      }
      break;
    case JointType::Hinge:
      use(3, angularRow(axisOf(f.qA, 0)), twistAngle(f.qA, f.qB));
      break;
    case JointType::Slider:
      use(0, linearRow(axisOf(f.qA, 0), armA, f.rB), axisOf(f.qA, 0).dot(f.d) - j.reference);
      break;
    case JointType::Universal:
    case JointType::SixDof: {
      for (std::size_t i = 0; i < 3; ++i)
        if (!j.axes[i].locked) {
          const Vec3 e = axisOf(f.qA, int(i));
          use(i, linearRow(e, armA, f.rB), e.dot(f.d));
        }
      if (j.axes[3].locked && j.axes[4].locked && j.axes[5].locked) break;
      const EulerFrame e = eulerFrame(f.qA, f.qB);
      for (std::size_t i = 0; i < 3; ++i)
        if (!j.axes[3 + i].locked) use(3 + i, angularRow(e.rateAxes[i]), e.angles(int(i)));
      break;
    }
    case JointType::Weld:
      break;
    case JointType::Distance: {
      const Real length = f.d.norm();
      use(0, linearRow(length > Real(1e-6) ? Vec3(f.d / length) : c.fallbackAxis, f.rA, f.rB),
          length);
      break;
    }
  }
}

// refresh() of a plain ball joint (JointConstraint::point): its anchors' arms and offset, and
// K^-1, without reading the joint's record. (K^-1 made once a step, at the step's arms, as
// Jolt's velocity steps do, cost a pendulum of a small bob on a 1 m arm 2.4% of its period at
// an amplitude of 1.5 rad: the arm turns 0.1 rad in a step.)
void refreshPoint(JointConstraint& c, const SolverBody& a, const SolverBody& b, bool withMass) {
  RowBlock& lock = c.lock;
  lock.setPoint(times(a.dR, c.rA), times(b.dR, c.rB));
  lock.error.head<3>() = (b.dp - a.dp) + (lock.armB - lock.armA) + c.deltaCenter;
  if (!withMass || lock.invertPoint(a, b)) return;
  RowBlock::Vector C = lock.error.head<3>();
  lock.prepare(a, b, C);  // the rows' LDLT, invertPoint having set the rows
}

// After a position update: the joint's frame, rows, coordinates and effective masses, which the
// passes until the next position update share.
void refresh(JointConstraint& c, const JointRecord& j, const SolverBody& a, const SolverBody& b,
             int stamp, bool withMass = true) {
  if (c.stamp == stamp) return;
  c.stamp = stamp;
  if (c.point) return refreshPoint(c, a, b, withMass);
  const Frame f = currentFrame(c, a, b);
  if (!c.lockedOnly) freeRows(c, j, f, *c.parts, a, b);
  RowBlock::Vector C;
  lockedRows(j, f, c.fallbackAxis, c.lock, C);
  c.lock.prepare(a, b, C);
}

// A free coordinate's spring, motor, friction and limits, in Box2D v3's order.
void driveAxis(AxisRows& ax, const JointAxis& axis, SolverBody& a, SolverBody& b, Real coordinate,
               const JointPass& pass) {
  if (axis.spring && !pass.relax)
    ax.solveSoft(a, b, ax.spring, coordinate - axis.spring->rest,
                 makeSoft(axis.spring->frequency, axis.spring->dampingRatio, pass.h), kInfinity);
  if (axis.motor && axis.motor->maxForce > 0) {
    const JointMotor& m = *axis.motor;
    const Real maxImpulse = m.maxForce * pass.h;
    if (!m.target)
      ax.solveMotor(a, b, ax.motor, m.speed, maxImpulse);
    else if (!pass.relax)
      ax.solveSoft(a, b, ax.motor, coordinate - *m.target, makeSoft(m.servoFrequency, 1, pass.h),
                   maxImpulse);
  }
  if (axis.friction > 0) ax.solveMotor(a, b, ax.friction, 0, axis.friction * pass.h);
  if (axis.limits) {
    ax.solveLimit(a, b, ax.lower, coordinate - axis.limits->lower, 1, pass.rigid, pass.invH);
    ax.solveLimit(a, b, ax.upper, axis.limits->upper - coordinate, -1, pass.rigid, pass.invH);
  }
}

// The free coordinates' rows (springs, motors, friction, limits), then the locked rows as one
// block: of all the rows, their error shows most (Box2D v3's order).
void solveRows(JointConstraint& c, const JointRecord& j, JointParts& p, SolverBody& a,
               SolverBody& b, const JointPass& pass) {
  switch (j.type) {
    case JointType::Ball:
      if (j.friction > 0) p.spin.solveFriction(a, b, j.friction * pass.h);
      if (j.coneLimit)
        p.cone.solveLimit(a, b, p.cone.upper, *j.coneLimit - c.swing, -1, pass.rigid, pass.invH);
      if (j.axes[3].limits) driveAxis(p.axes[3], j.axes[3], a, b, c.coordinate[3], pass);
      break;
    case JointType::Hinge:
      driveAxis(p.axes[3], j.axes[3], a, b, c.coordinate[3], pass);
      break;
    case JointType::Slider:
      driveAxis(p.axes[0], j.axes[0], a, b, c.coordinate[0], pass);
      break;
    case JointType::Universal:
    case JointType::SixDof:
      // Every free degree of freedom on its own row, the rotations first.
      for (std::size_t i : {3, 4, 5, 0, 1, 2})
        if (!j.axes[i].locked) driveAxis(p.axes[i], j.axes[i], a, b, c.coordinate[i], pass);
      break;
    case JointType::Weld:
      break;
    case JointType::Distance: {
      AxisRows& ax = p.axes[0];
      const Real length = c.coordinate[0];
      if (j.spring && !pass.relax)
        ax.solveSoft(a, b, ax.spring, length - j.length,
                     makeSoft(j.spring->frequency, j.spring->dampingRatio, pass.h), kInfinity);
      if (j.minLength < j.maxLength) {
        ax.solveLimit(a, b, ax.lower, length - j.minLength, 1, pass.rigid, pass.invH);
        ax.solveLimit(a, b, ax.upper, j.maxLength - length, -1, pass.rigid, pass.invH);
      }
      break;
    }
  }
  // A soft weld's rows are its spring (which sits out the relax pass, like every spring).
  if (j.type == JointType::Weld && j.spring) {
    if (!pass.relax)
      c.lock.solve(a, b, makeSoft(j.spring->frequency, j.spring->dampingRatio, pass.h));
    return;
  }
  c.lock.solve(a, b, pass.rigid);
}

// Runs f(a, b) on the joint's two solver bodies: a moving body in place, anything else (a zero
// body for the world or a static body, a kinematic body) as a copy whose writes are dropped,
// since a static or kinematic body may be shared by joints solved at the same time.
template <class F>
void withBodies(const JointConstraint& c, std::vector<SolverBody>& bodies, F f) {
  // Both bodies moving (no other joint or contact of the colour touches them): in place. That
  // is nearly every joint; the copies below are made only for the others (a joint to the
  // world, a static or a kinematic body), and a copy of a solver body costs its 144 bytes.
  const auto at = [&](int index) {
    return index >= 0 ? &bodies[std::size_t(index)] : static_cast<SolverBody*>(nullptr);
  };
  SolverBody* a = at(c.bodyA);
  SolverBody* b = at(c.bodyB);
  const auto moving = [](const SolverBody* body) { return body && body->invMass > 0; };
  if (moving(a) && moving(b)) return f(*a, *b);
  SolverBody copyA = a ? *a : SolverBody{}, copyB = b ? *b : SolverBody{};
  f(moving(a) ? *a : copyA, moving(b) ? *b : copyB);
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
    const Real hertz = std::min(s.solver.jointHertz, Real(0.5) / h);
    pass.rigid = makeSoft(hertz, s.solver.jointDampingRatio, h);
  } else {
    pass.rigid = {s.contact.baumgarte * pass.invH, 1, 0};
  }
  return pass;
}

void prepareJoints(RigidBodyData& D, std::span<const std::uint32_t> order, StepWorkers& workers) {
  D.jointConstraints.resize(D.jointEdges.size());
  workers.parallelFor(D.jointConstraints.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const std::size_t edge = order.empty() ? k : order[k];
      JointConstraint& c = D.jointConstraints[k];
      // Every field is set below or by the first refresh, which the step makes before any pass
      // reads the constraint; an empty lock block and zero coordinates until then, so that
      // nothing reads another step's rows. (A whole JointConstraint{} was 1.2 kB of writes per
      // joint, a twentieth of a joint grid's step.)
      c.lock.clear();
      c.coordinate = {};
      c.swing = 0;
      c.joint = D.edgeJoints[edge];
      c.bodyA = D.jointEdges[edge].bodyA;
      c.bodyB = D.jointEdges[edge].bodyB;
      const JointRecord& j = D.joints[c.joint];
      c.lockedOnly = lockedOnly(j);
      c.point = c.lockedOnly && j.type == JointType::Ball;
      c.inTree = false;
      const bool world = j.bodyA == kWorldBody;
      const Transform poseA = world ? Transform{} : D.bodies[j.bodyA].pose;
      const Vec3 comA = world ? Vec3::Zero() : D.bodies[j.bodyA].com;
      const BodyRecord& b = D.bodies[j.bodyB];
      c.rA = poseA.apply(j.frameA.p) - comA;
      c.rB = b.pose.apply(j.frameB.p) - b.com;
      c.deltaCenter = b.com - comA;
      c.frameA = poseA.q * j.frameA.q;
      c.frameB = b.pose.q * j.frameB.q;
      const Vec3 d = c.deltaCenter + c.rB - c.rA;
      c.fallbackAxis = d.norm() > Real(1e-6) ? Vec3(d.normalized()) : axisOf(c.frameA, 0);
      c.parts = &D.joints[c.joint].parts;
      // The locked rows' impulses for the warm start; the block itself lives in the
      // constraint, in colour order, so the passes read it in sequence.
      c.lock.impulse = j.parts.lockImpulse;
      c.stamp = -1;
    }
  });
}

void warmStartJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                    int stamp) {
  const JointRecord& j = D.joints[c.joint];
  withBodies(c, bodies, [&](SolverBody& a, SolverBody& b) {
    refresh(c, j, a, b, stamp);
    c.lock.warmStart(a, b);
    if (c.lockedOnly) return;
    JointParts& p = *c.parts;
    switch (j.type) {
      case JointType::Ball:
        if (j.friction > 0) p.spin.warmStart(a, b);
        if (j.coneLimit) p.cone.warmStart(a, b);
        if (j.axes[3].limits) p.axes[3].warmStart(a, b);
        break;
      case JointType::Hinge:
        p.axes[3].warmStart(a, b);
        break;
      case JointType::Slider:
      case JointType::Distance:
        p.axes[0].warmStart(a, b);
        break;
      case JointType::Universal:
      case JointType::SixDof:
        for (std::size_t i = 0; i < 6; ++i)
          if (!j.axes[i].locked) p.axes[i].warmStart(a, b);
        break;
      case JointType::Weld:
        break;
    }
  });
}

void refreshJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                  int stamp, bool withMass) {
  if (c.stamp == stamp) return;
  withBodies(c, bodies, [&](SolverBody& a, SolverBody& b) {
    refresh(c, D.joints[c.joint], a, b, stamp, withMass);
  });
}

void solveJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                const JointPass& pass) {
  if (c.inTree) return;
  withBodies(c, bodies, [&](SolverBody& a, SolverBody& b) {
    if (c.stamp != pass.stamp) refresh(c, D.joints[c.joint], a, b, pass.stamp);
    if (c.lockedOnly)
      c.lock.solve(a, b, pass.rigid);
    else
      solveRows(c, D.joints[c.joint], *c.parts, a, b, pass);
  });
}

namespace {

// A joint's rows for the LCP solvers (lcp_contact.h), in the order and with the right-hand
// sides of solveRows: each a row of the LCP with its kind, bias, compliance and bound.
class LcpRowWriter {
 public:
  LcpRowWriter(const JointConstraint& c, const std::vector<SolverBody>& bodies,
               const JointPass& pass, std::vector<LcpRow>& rows, int& groups)
      : c_(c), bodies_(bodies), pass_(pass), rows_(rows), groups_(groups) {}

  // A row towards C = 0 with `soft`'s coefficients, free (a locked row or a spring), or boxed
  // in [-bound, bound] (a servo).
  void soft(const JointRow& row, Real C, const Softness& soft, Real* store,
            Real bound = kInfinity) {
    LcpRow& r = add(row, 1, std::isinf(bound) ? LcpRowKind::Bilateral : LcpRowKind::Boxed, store);
    r.rhs += double(jointBias(soft, C));
    r.cfm = compliance(r, soft);
    r.bound = double(bound);
  }
  // A bounded velocity row driving J v to `speed` (a motor, or friction at speed 0).
  void motor(const JointRow& row, Real speed, Real bound, Real* store) {
    LcpRow& r = add(row, 1, LcpRowKind::Boxed, store);
    r.rhs -= double(speed);
    r.bound = double(bound);
  }
  // A one-sided row keeping C >= 0, speculative while C > 0, as AxisRows::solveLimit.
  void limit(const JointRow& row, Real C, Real sign, Real* store) {
    LcpRow& r = add(row, sign, LcpRowKind::Limit, store);
    r.rhs += double(C > 0 ? C * pass_.invH : jointBias(pass_.rigid, C));
    r.cfm = C > 0 ? 0 : compliance(r, pass_.rigid);
  }
  // A free coordinate's spring, motor, friction and limits (driveAxis).
  void axis(AxisRows& ax, const JointAxis& axis, Real coordinate) {
    if (axis.spring)
      soft(ax.row, coordinate - axis.spring->rest,
           makeSoft(axis.spring->frequency, axis.spring->dampingRatio, pass_.h), &ax.spring);
    if (axis.motor && axis.motor->maxForce > 0) {
      const JointMotor& m = *axis.motor;
      if (!m.target)
        motor(ax.row, m.speed, m.maxForce * pass_.h, &ax.motor);
      else
        soft(ax.row, coordinate - *m.target, makeSoft(m.servoFrequency, 1, pass_.h), &ax.motor,
             m.maxForce * pass_.h);
    }
    if (axis.friction > 0) motor(ax.row, 0, axis.friction * pass_.h, &ax.friction);
    if (axis.limits) {
      limit(ax.row, coordinate - axis.limits->lower, 1, &ax.lower);
      limit(ax.row, axis.limits->upper - coordinate, -1, &ax.upper);
    }
  }

 private:
  LcpRow& add(const JointRow& row, Real sign, LcpRowKind kind, Real* store) {
    LcpRow& r = rows_.emplace_back();
    r.a = c_.bodyA;
    r.b = c_.bodyB;
    r.linA = -double(sign) * row.linear.cast<double>();
    r.angA = -double(sign) * row.ja.cast<double>();
    r.linB = double(sign) * row.linear.cast<double>();
    r.angB = double(sign) * row.jb.cast<double>();
    r.rhs = lcpRowVelocity(r, bodies_);
    r.kind = kind;
    r.constraint = -1;
    r.store = store;
    if (kind == LcpRowKind::Boxed) r.group = groups_++;  // Lemke: its own slack
    return r;
  }
  // A soft row's fixed point J v+ + bias + (impulseScale / massScale) K z = 0 (solveSoft's
  // iteration converged) as a compliance on the diagonal.
  double compliance(const LcpRow& r, const Softness& soft) const {
    if (soft.impulseScale == 0) return 0;
    return double(soft.impulseScale / soft.massScale) * lcpDelassus(r, r, bodies_);
  }

  const JointConstraint& c_;
  const std::vector<SolverBody>& bodies_;
  const JointPass& pass_;
  std::vector<LcpRow>& rows_;
  int& groups_;
};

// The locked rows of the block (a point constraint's along the world axes).
JointRow lockRow(const RowBlock& lock, int i) {
  if (!lock.point) return lock.rows[std::size_t(i)];
  return linearRow(Vec3::Unit(i), lock.armA, lock.armB);
}

}  // namespace

void appendJointLcpRows(const RigidBodyData& D, JointConstraint& c,
                        const std::vector<SolverBody>& bodies, const JointPass& pass,
                        std::vector<LcpRow>& rows, int& groups) {
  const JointRecord& j = D.joints[c.joint];
  const SolverBody none{};
  const SolverBody& a = c.bodyA >= 0 ? bodies[std::size_t(c.bodyA)] : none;
  const SolverBody& b = c.bodyB >= 0 ? bodies[std::size_t(c.bodyB)] : none;
  refresh(c, j, a, b, pass.stamp);
  LcpRowWriter w(c, bodies, pass, rows, groups);
  JointParts& p = *c.parts;
  if (!c.lockedOnly) switch (j.type) {
      case JointType::Ball:
        // The rotation friction's ball |z| <= f h as a box per world axis.
        if (j.friction > 0)
          for (int i = 0; i < 3; ++i)
            w.motor(angularRow(Vec3::Unit(i)), 0, j.friction * pass.h, &p.spin.impulse(i));
        if (j.coneLimit) w.limit(p.cone.row, *j.coneLimit - c.swing, -1, &p.cone.upper);
        if (j.axes[3].limits) w.axis(p.axes[3], j.axes[3], c.coordinate[3]);
        break;
      case JointType::Hinge:
        w.axis(p.axes[3], j.axes[3], c.coordinate[3]);
        break;
      case JointType::Slider:
        w.axis(p.axes[0], j.axes[0], c.coordinate[0]);
        break;
      case JointType::Universal:
      case JointType::SixDof:
        for (std::size_t i : {3, 4, 5, 0, 1, 2})
          if (!j.axes[i].locked) w.axis(p.axes[i], j.axes[i], c.coordinate[i]);
        break;
      case JointType::Weld:
        break;
      case JointType::Distance: {
        AxisRows& ax = p.axes[0];
        const Real length = c.coordinate[0];
        if (j.spring)
          w.soft(ax.row, length - j.length,
                 makeSoft(j.spring->frequency, j.spring->dampingRatio, pass.h), &ax.spring);
        if (j.minLength < j.maxLength) {
          w.limit(ax.row, length - j.minLength, 1, &ax.lower);
          w.limit(ax.row, j.maxLength - length, -1, &ax.upper);
        }
        break;
      }
    }
  const Softness lockSoft = j.type == JointType::Weld && j.spring
                                ? makeSoft(j.spring->frequency, j.spring->dampingRatio, pass.h)
                                : pass.rigid;
  for (int i = 0; i < c.lock.count; ++i)
    w.soft(lockRow(c.lock, i), c.lock.error(i), lockSoft, &c.lock.impulse(i));
}

void storeJoints(RigidBodyData& D, Real h, StepWorkers& workers) {
  // Each joint's impulses and reaction on the workers (each writes its own record), then the
  // breaks in slot order in sequence.
  workers.parallelFor(D.jointConstraints.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const JointConstraint& c = D.jointConstraints[k];
      JointRecord& j = D.joints[c.joint];
      JointParts& p = j.parts;
      Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
      c.lock.reaction(linear, angular);
      p.lockImpulse = c.lock.impulse;
      if (!c.lockedOnly) {
        p.spin.reaction(linear, angular);
        p.cone.reaction(linear, angular);
        for (const AxisRows& ax : p.axes) ax.reaction(linear, angular);
      }
      j.force = linear / h;
      j.torque = angular / h;
      j.overloaded = j.force.norm() > j.breakForce || j.torque.norm() > j.breakTorque;
    }
  });
  for (std::uint32_t ji = 0; ji < D.joints.size(); ++ji) {
    JointRecord& j = D.joints[ji];
    if (std::exchange(j.overloaded, false)) {
      j.broken = true;
      j.enabled = false;
      j.parts = {};
      D.jointEvents.push_back({{ji, j.generation}, j.force, j.torque});
    }
  }
}

namespace {
// How far a degree of freedom is outside what its settings allow.
Real axisError(const JointAxis& axis, Real coordinate) {
  if (axis.locked) return std::abs(coordinate);
  if (!axis.limits) return 0;
  return std::max({axis.limits->lower - coordinate, coordinate - axis.limits->upper, Real(0)});
}
}  // namespace

JointError jointError(const RigidBodyData& D, const JointRecord& j) {
  const Transform fa = worldFrame(D, j.bodyA, j.frameA);
  const Transform fb = worldFrame(D, j.bodyB, j.frameB);
  const Vec3 d = fb.p - fa.p;
  const Vec3 x = axisOf(fa.q, 0);
  JointError e;
  switch (j.type) {
    case JointType::Ball: {
      e.position = d.norm();
      const SwingTwist st = swingTwist(fa.q, fb.q);
      if (j.coneLimit) e.angle += std::max(st.swing - *j.coneLimit, Real(0));
      e.angle += axisError(j.axes[3], st.twist);
      break;
    }
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
    case JointType::Universal:
    case JointType::SixDof: {
      // Each locked degree of freedom's offset; the limited ones' excess beyond their limits.
      const EulerFrame ef = eulerFrame(fa.q, fb.q);
      Vec3 linear, angular;
      for (int i = 0; i < 3; ++i) {
        linear(i) = axisError(j.axes[std::size_t(i)], axisOf(fa.q, i).dot(d));
        angular(i) = axisError(j.axes[std::size_t(3 + i)], ef.angles(i));
      }
      e.position = linear.norm();
      e.angle = angular.norm();
      break;
    }
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
    case JointType::Ball:
      return twistAngle(fa.q, fb.q);
    default:
      return 0;
  }
}

Real axisCoordinate(const RigidBodyData& D, const JointRecord& j, int axis) {
  const Transform poseA = j.bodyA == kWorldBody ? Transform{} : D.bodies[j.bodyA].pose;
  const Transform fa = poseA * j.frameA;
  const Transform fb = D.bodies[j.bodyB].pose * j.frameB;
  if (axis < 3) return axisOf(fa.q, axis).dot(fb.p - fa.p);
  return eulerFrame(fa.q, fb.q).angles(axis - 3);
}

}  // namespace inertia::detail
