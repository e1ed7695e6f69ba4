#include "multibody_contacts.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "inertia/core/math.h"

namespace inertia::detail {

using Data = RigidBodyData;

namespace {

MultibodyResponse& response(Data& D, const MultibodySide& s) {
  return *D.multibodies[std::size_t(s.group)].response;
}

// A side's point: its velocity, its velocity change per unit impulse, its displacement since
// the step's start, and an impulse on it. A rigid side's anchor r is fixed for the step, as the
// coloured contacts' is (Box2D v3).
Vec3 velocity(Data& D, const MultibodySide& s, int handle, const Vec3& r) {
  if (s.group >= 0) return response(D, s).pointVelocity(handle);
  if (s.body < 0) return Vec3::Zero();
  const SolverBody& b = D.solverBodies[std::size_t(s.body)];
  return b.v + b.w.cross(r);
}

Mat3 responseMatrix(Data& D, const MultibodySide& s, int handle, const Vec3& r) {
  if (s.group >= 0) return response(D, s).pointResponse(handle);
  if (s.body < 0) return Mat3::Zero();
  // dv = P / m + (I^-1 (r x P)) x r = (1/m - [r] I^-1 [r]) P.
  const SolverBody& b = D.solverBodies[std::size_t(s.body)];
  const Mat3 R = skew(r);
  return b.invMass * Mat3::Identity() - R * b.invInertia * R;
}

// The rows' W between sides a and b (the relative velocity B - A per unit impulse P on B, -P on
// A): each side's own response, less the coupling where both sides are points of one group (two
// links of a tree: an impulse on one moves the other).
Mat3 pairResponse(Data& D, const MultibodySide& a, int ha, const Vec3& rA, const MultibodySide& b,
                  int hb, const Vec3& rB) {
  Mat3 W = responseMatrix(D, a, ha, rA) + responseMatrix(D, b, hb, rB);
  if (a.group >= 0 && a.group == b.group) {
    const Mat3 C = response(D, a).crossResponse(ha, hb);
    W -= C + C.transpose();
  }
  return W;
}

Vec3 displacement(Data& D, const MultibodySide& s, int handle, const Vec3& r) {
  if (s.group >= 0) return response(D, s).pointDisplacement(handle);
  if (s.body < 0) return Vec3::Zero();
  const SolverBody& b = D.solverBodies[std::size_t(s.body)];
  return b.dp + b.dR * r - r;
}

void applyImpulse(Data& D, const MultibodySide& s, int handle, const Vec3& r, const Vec3& P) {
  if (s.group >= 0) return response(D, s).applyImpulse(handle, P);
  if (s.body < 0) return;
  SolverBody& b = D.solverBodies[std::size_t(s.body)];
  b.v += b.invMass * P;
  b.w += b.invInertia * r.cross(P);
}

// The relative velocity B - A at point k.
Vec3 relativeVelocity(Data& D, const MultibodyContact& c, const MultibodyPoint& p) {
  return velocity(D, c.b, p.handle[1], p.rB) - velocity(D, c.a, p.handle[0], p.rA);
}

// An impulse P on B at point k, -P on A.
void applyPair(Data& D, const MultibodyContact& c, const MultibodyPoint& p, const Vec3& P) {
  applyImpulse(D, c.a, p.handle[0], p.rA, -P);
  applyImpulse(D, c.b, p.handle[1], p.rB, P);
}

Real invEffective(Real k) { return k > 0 ? Real(1) / k : Real(0); }

// The points of contact c: anchors, the groups' points, and last step's impulses.
void preparePoints(Data& D, const DynamicsSettings& s, MultibodyContact& c) {
  const ContactInfo& info = D.contacts[std::size_t(c.contactIndex)];
  const BodyRecord& ba = D.bodies[info.bodyA.index];
  const BodyRecord& bb = D.bodies[info.bodyB.index];
  const Material& ma = D.frames[info.shapeA.index].material;
  const Material& mb = D.frames[info.shapeB.index].material;
  c.restitution = combine(s.combine.restitution, ma.restitution, mb.restitution);
  c.normal = info.manifold.normal;
  c.pointCount = info.manifold.pointCount;
  Vec3 slip = Vec3::Zero();
  std::array<Vec3, 4> dvs;
  for (int k = 0; k < c.pointCount; ++k) {
    const ContactPoint& cp = info.manifold.points[std::size_t(k)];
    MultibodyPoint& p = c.points[std::size_t(k)];
    const Vec3 mid = Real(0.5) * (cp.pointA + cp.pointB);
    p.rA = mid - ba.com;
    p.rB = mid - bb.com;
    p.handle[0] = c.a.group >= 0 ? response(D, c.a).addPoint(ba.member, mid) : -1;
    p.handle[1] = c.b.group >= 0 ? response(D, c.b).addPoint(bb.member, mid) : -1;
    p.separation = cp.separation;
    dvs[std::size_t(k)] = relativeVelocity(D, c, p);
    slip += dvs[std::size_t(k)];
  }
  // Friction axes along the sliding direction when sliding, as the coloured contacts'.
  slip -= slip.dot(c.normal) * c.normal;
  if (slip.norm() / Real(c.pointCount) > kStickSpeed) {
    c.tangent[0] = slip.normalized();
    c.tangent[1] = c.normal.cross(c.tangent[0]);
  } else {
    c.tangent = tangentBasis(c.normal);
  }
  const ContactExtra& extra = D.extras[std::size_t(c.contactIndex)];
  Real tangentialSpeed2 = 0;
  for (int k = 0; k < c.pointCount; ++k) {
    MultibodyPoint& p = c.points[std::size_t(k)];
    const Mat3 W = pairResponse(D, c.a, p.handle[0], p.rA, c.b, p.handle[1], p.rB);
    p.normalMass = invEffective(c.normal.dot(W * c.normal));
    for (int t = 0; t < 2; ++t) {
      p.tangentMass[std::size_t(t)] = invEffective(c.tangent[t].dot(W * c.tangent[t]));
      p.tangentImpulse[std::size_t(t)] = extra.tangentImpulse[std::size_t(k)].dot(c.tangent[t]);
    }
    p.normalImpulse = info.normalImpulses[std::size_t(k)];
    p.maxNormalImpulse = 0;
    const Vec3& dv = dvs[std::size_t(k)];
    p.relativeVelocity = dv.dot(c.normal);
    tangentialSpeed2 =
        std::max(tangentialSpeed2, (dv - p.relativeVelocity * c.normal).squaredNorm());
  }
  const bool sticking = tangentialSpeed2 < kStickSpeed * kStickSpeed;
  c.friction = sticking ? combine(s.combine.friction, ma.friction, mb.friction)
                        : combine(s.combine.friction, ma.sliding(), mb.sliding());
}

// A side's anchor from its reference point now: a rigid side's turns with its body within the
// step (the coloured joints' do too); a driven side's reference is the anchor itself.
Vec3 arm(const Data& D, const MultibodySide& s, const Vec3& r) {
  if (s.group >= 0 || s.body < 0) return r;
  return D.solverBodies[std::size_t(s.body)].dR * r;
}

using Vector6 = MultibodyResponse::FrameVector;
using Matrix6 = MultibodyResponse::FrameMatrix;
using SideRows = Eigen::Matrix<Real, Eigen::Dynamic, 6, 0, RowBlock::kMax, 6>;
using BlockMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using BlockVector = RowBlock::Vector;

// A side's [v; w]: a rigid side's centre of mass, a driven side's frame (at its anchor).
Vector6 sideVelocity(Data& D, const MultibodySide& s, int handle) {
  if (s.group >= 0) return response(D, s).frameVelocity(handle);
  Vector6 v = Vector6::Zero();
  if (s.body < 0) return v;
  const SolverBody& b = D.solverBodies[std::size_t(s.body)];
  v << b.v, b.w;
  return v;
}

// An impulse [P; L] at a side's reference point.
void applySideImpulse(Data& D, const MultibodySide& s, int handle, const Vector6& impulse) {
  if (s.group >= 0) return response(D, s).applyFrameImpulse(handle, impulse);
  if (s.body < 0) return;
  SolverBody& b = D.solverBodies[std::size_t(s.body)];
  b.v += b.invMass * impulse.head<3>();
  b.w += b.invInertia * impulse.tail<3>();
}

// A side's [v; w] change per unit [P; L] at its reference point.
Matrix6 sideResponse(Data& D, const MultibodySide& s, int handle) {
  if (s.group >= 0) return response(D, s).frameResponse(handle, handle);
  Matrix6 W = Matrix6::Zero();
  if (s.body < 0) return W;
  const SolverBody& b = D.solverBodies[std::size_t(s.body)];
  W.topLeftCorner<3, 3>() = b.invMass * Mat3::Identity();
  W.bottomRightCorner<3, 3>() = b.invInertia;
  return W;
}

// The joint frame's rotation now: a driven side's member turns it, a rigid side's body by its
// rotation since the step's start; the world's stays.
Quat sideRotation(Data& D, const MultibodySide& s, int handle, const Quat& frame) {
  if (s.group >= 0) return response(D, s).frameRotation(handle) * frame;
  if (s.body < 0) return frame;
  return D.solverBodies[std::size_t(s.body)].dq * frame;
}

// The rows' Jacobians on each side's [v; w]: row i is -[l_i; ja_i] on A and [l_i; jb_i] on B.
void sideRows(const RowBlock& rows, SideRows& A, SideRows& B) {
  A.resize(rows.count, 6);
  B.resize(rows.count, 6);
  for (int i = 0; i < rows.count; ++i) {
    const JointRow& r = rows.rows[std::size_t(i)];
    A.row(i) << -r.linear.transpose(), -r.ja.transpose();
    B.row(i) << r.linear.transpose(), r.jb.transpose();
  }
}

// The joint's locked rows in its frame now and their effective mass K^+, K = J W J^T over both
// sides (with the coupling where both are frames of one group): made again after every
// position update (JointPass::stamp), as the coloured joints' are, since a hung body's turn
// within the step moves its anchor's response (a small sphere on a long arm: its W spans
// 1 : 91). A ball joint's point block is written as its three rows along the world axes.
//
// K is singular wherever the rows cannot move apart: out of the plane of a planar loop, along
// the bars of a straight linkage. Its pseudo-inverse leaves those directions alone (eigenvalues
// below 1e-6 of the largest: far below any real response, above float rounding).
void refreshJoint(Data& D, MultibodyJoint& m) {
  const JointRecord& j = D.joints[m.joint];
  JointFrame f;
  f.rA = arm(D, m.a, m.rA);
  f.rB = arm(D, m.b, m.rB);
  f.d = m.separation + displacement(D, m.b, m.handle[1], m.rB) -
        displacement(D, m.a, m.handle[0], m.rA);
  f.qA = sideRotation(D, m.a, m.handle[0], m.frameA);
  f.qB = sideRotation(D, m.b, m.handle[1], m.frameB);
  BlockVector C;
  lockedRows(j, f, m.fallbackAxis, m.rows, C);
  if (m.rows.point) {
    m.rows.clear();
    for (int i = 0; i < 3; ++i) m.rows.add(linearRow(Vec3::Unit(i), f.rA, f.rB));
  }
  m.rows.error.head(m.rows.count) = C;
  if (m.rows.count == 0) return;  // a six-DOF joint with every axis free
  SideRows A, B;
  sideRows(m.rows, A, B);
  BlockMatrix K = A * sideResponse(D, m.a, m.handle[0]) * A.transpose() +
                  B * sideResponse(D, m.b, m.handle[1]) * B.transpose();
  if (m.a.group >= 0 && m.a.group == m.b.group) {
    const BlockMatrix coupling =
        A * response(D, m.a).frameResponse(m.handle[0], m.handle[1]) * B.transpose();
    K += coupling + coupling.transpose();
  }
  // Scaled by its diagonal first (as RowBlock::invert): linear rows (1/kg) and angular ones
  // (1/(kg m^2)) differ by the square of a body's size, which would put a small body's linear
  // rows under the cut. A row with no response at all (an angular row across a planar loop's
  // hinges: rounding, 1e-14 of the largest) stays out: scaled up, its noise would count.
  const BlockVector diagonal = K.diagonal();
  BlockVector scale = BlockVector::Zero(diagonal.size());
  for (int i = 0; i < diagonal.size(); ++i)
    if (diagonal(i) > Real(1e-12) * diagonal.maxCoeff()) scale(i) = 1 / std::sqrt(diagonal(i));
  const BlockMatrix scaled = scale.asDiagonal() * K * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<BlockMatrix> eig(scaled);
  const BlockVector lambda = eig.eigenvalues();
  BlockVector inverse = BlockVector::Zero(lambda.size());
  for (int i = 0; i < lambda.size(); ++i)
    if (lambda(i) > Real(1e-6) * lambda.maxCoeff()) inverse(i) = 1 / lambda(i);
  m.mass = scale.asDiagonal() *
           (eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose()) *
           scale.asDiagonal();
  if (!m.mass.allFinite()) m.mass.setZero();
}

// A driven joint's anchors, frames, reference points and last step's impulses.
void prepareJointPoints(Data& D, MultibodyJoint& m) {
  const JointRecord& j = D.joints[m.joint];
  const Transform fA = worldFrame(D, j.bodyA, j.frameA), fB = worldFrame(D, j.bodyB, j.frameB);
  const auto side = [&](const MultibodySide& s, std::uint32_t body, const Transform& local,
                        const Transform& world, int& handle, Vec3& r, Quat& frame) {
    handle = -1;
    r = Vec3::Zero();
    frame = world.q;
    if (s.group >= 0) {
      handle = response(D, s).addFrame(D.bodies[body].member, world.p);
      frame = local.q;
    } else if (s.body >= 0) {
      r = world.p - D.bodies[body].com;
    }
  };
  side(m.a, j.bodyA, j.frameA, fA, m.handle[0], m.rA, m.frameA);
  side(m.b, j.bodyB, j.frameB, fB, m.handle[1], m.rB, m.frameB);
  m.separation = fB.p - fA.p;
  m.fallbackAxis = m.separation.norm() > Real(1e-6) ? Vec3(m.separation.normalized())
                                                    : Vec3(fA.q * Vec3::UnitX());
  m.rows.impulse = j.parts.lockImpulse;
  m.stamp = -1;  // rows made by the first warm start
}

// Impulses `lambda` along the rows: -A^T lambda on A, B^T lambda on B (as [P; L]).
void applyJointRows(Data& D, const MultibodyJoint& m, const BlockVector& lambda) {
  SideRows A, B;
  sideRows(m.rows, A, B);
  applySideImpulse(D, m.a, m.handle[0], A.transpose() * lambda);
  applySideImpulse(D, m.b, m.handle[1], B.transpose() * lambda);
}

// Whether a side cannot move: a static body, or a kinematic one.
bool fixedSide(const Data& D, const MultibodySide& s) {
  return s.group < 0 && (s.body < 0 || D.solverBodies[std::size_t(s.body)].invMass == 0);
}

}  // namespace

void prepareMultibodyContacts(Data& D, const DynamicsSettings& s, const Softness& soft,
                              const Softness& staticSoft) {
  for (MultibodyGroup& g : D.multibodies)
    if (g.response) g.response->beginStep();
  for (MultibodyContact& c : D.multibodyContacts) {
    preparePoints(D, s, c);
    c.softness = fixedSide(D, c.a) || fixedSide(D, c.b) ? staticSoft : soft;
  }
  for (MultibodyJoint& m : D.multibodyJoints) prepareJointPoints(D, m);
}

void warmStartMultibodyJoints(Data& D, int stamp) {
  for (MultibodyJoint& m : D.multibodyJoints) {
    if (m.stamp != stamp) {
      refreshJoint(D, m);
      m.stamp = stamp;
    }
    applyJointRows(D, m, m.rows.impulse.head(m.rows.count));
  }
}

void solveMultibodyJoints(Data& D, const JointPass& pass) {
  const Softness& soft = pass.rigid;
  for (MultibodyJoint& m : D.multibodyJoints) {
    if (m.stamp != pass.stamp) {
      refreshJoint(D, m);
      m.stamp = pass.stamp;
    }
    const int n = m.rows.count;
    if (n == 0) continue;
    SideRows A, B;
    sideRows(m.rows, A, B);
    BlockVector rhs = A * sideVelocity(D, m.a, m.handle[0]) + B * sideVelocity(D, m.b, m.handle[1]);
    for (int i = 0; i < n; ++i) rhs(i) += jointBias(soft, m.rows.error(i));
    const BlockVector delta =
        -soft.massScale * (m.mass * rhs) - soft.impulseScale * m.rows.impulse.head(n);
    m.rows.impulse.head(n) += delta;
    applySideImpulse(D, m.a, m.handle[0], A.transpose() * delta);
    applySideImpulse(D, m.b, m.handle[1], B.transpose() * delta);
  }
}

void storeMultibodyJoints(Data& D, Real h) {
  for (const MultibodyJoint& m : D.multibodyJoints) {
    JointRecord& j = D.joints[m.joint];
    j.parts.lockImpulse.setZero();
    j.parts.lockImpulse.head(m.rows.count) = m.rows.impulse.head(m.rows.count);
    Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
    m.rows.reaction(linear, angular);
    j.force = linear / h;
    j.torque = angular / h;
    j.overloaded = j.force.norm() > j.breakForce || j.torque.norm() > j.breakTorque;
  }
}

void integrateMultibodyVelocities(Data& D, Real h, StepWorkers& workers) {
  workers.parallelFor(D.multibodies.size(), 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t g = first; g < last; ++g)
      if (D.multibodies[g].response) D.multibodies[g].response->integrateVelocities(h);
  });
}

void integrateMultibodyPositions(Data& D, Real h, StepWorkers& workers) {
  workers.parallelFor(D.multibodies.size(), 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t g = first; g < last; ++g)
      if (D.multibodies[g].response) D.multibodies[g].response->integratePositions(h);
  });
}

void solveMultibodyRows(Data& D) {
  for (MultibodyGroup& g : D.multibodies)
    if (g.response) g.response->solveRows();
}

void warmStartMultibodyContacts(Data& D) {
  for (const MultibodyContact& c : D.multibodyContacts) {
    for (int k = 0; k < c.pointCount; ++k) {
      const MultibodyPoint& p = c.points[std::size_t(k)];
      applyPair(D, c, p,
                p.normalImpulse * c.normal + p.tangentImpulse[0] * c.tangent[0] +
                    p.tangentImpulse[1] * c.tangent[1]);
    }
  }
}

void solveMultibodyContacts(Data& D, const BiasMode& mode) {
  for (MultibodyContact& c : D.multibodyContacts) {
    // The normal rows, as the coloured contacts' normalRow (contact_kernels.inl).
    for (int k = 0; k < c.pointCount; ++k) {
      MultibodyPoint& p = c.points[std::size_t(k)];
      const Real s = p.separation + (displacement(D, c.b, p.handle[1], p.rB) -
                                     displacement(D, c.a, p.handle[0], p.rA))
                                        .dot(c.normal);
      Real bias = 0, massScale = 1, impulseScale = 0;
      if (mode.useBias) {
        if (mode.soft) {
          bias = std::max(c.softness.biasRate * s, -mode.pushVelocity);
          massScale = c.softness.massScale;
          impulseScale = c.softness.impulseScale;
        } else {
          bias = std::max(mode.baumgarte * mode.invH * std::min(s + mode.linearSlop, Real(0)),
                          -mode.pushVelocity);
        }
      }
      const bool open = s > 0;
      if (open) {
        // Speculative: the gap may close within this substep, no more.
        bias = s * mode.invH;
        massScale = 1;
        impulseScale = 0;
      }
      if (!mode.useBias && open && c.restitution != 0) continue;
      const Real vn = relativeVelocity(D, c, p).dot(c.normal);
      const Real accumulated = p.normalImpulse;
      const Real impulse0 = -p.normalMass * massScale * (vn + bias) - impulseScale * accumulated;
      const Real updated = std::max(accumulated + impulse0, Real(0));
      p.normalImpulse = updated;
      p.maxNormalImpulse = std::max(p.maxNormalImpulse, updated - accumulated);
      applyPair(D, c, p, (updated - accumulated) * c.normal);
    }
    // Coulomb friction: the tangential impulse in the disc of radius mu * normal impulse.
    for (int k = 0; k < c.pointCount; ++k) {
      MultibodyPoint& p = c.points[std::size_t(k)];
      const Vec3 dv = relativeVelocity(D, c, p);
      std::array<Real, 2> updated;
      for (int t = 0; t < 2; ++t)
        updated[std::size_t(t)] =
            p.tangentImpulse[std::size_t(t)] - p.tangentMass[std::size_t(t)] * dv.dot(c.tangent[t]);
      const Real limit = c.friction * p.normalImpulse;
      const Real norm = std::hypot(updated[0], updated[1]);
      if (norm > limit) {
        const Real scale = norm > 0 ? limit / norm : Real(0);
        updated[0] *= scale;
        updated[1] *= scale;
      }
      applyPair(D, c, p,
                (updated[0] - p.tangentImpulse[0]) * c.tangent[0] +
                    (updated[1] - p.tangentImpulse[1]) * c.tangent[1]);
      p.tangentImpulse = updated;
    }
  }
}

void restituteMultibodyContacts(Data& D, Real threshold) {
  for (MultibodyContact& c : D.multibodyContacts) {
    if (c.restitution == 0) continue;
    for (int k = 0; k < c.pointCount; ++k) {
      MultibodyPoint& p = c.points[std::size_t(k)];
      if (p.relativeVelocity > -threshold || p.maxNormalImpulse == 0) continue;
      const Real vn = relativeVelocity(D, c, p).dot(c.normal);
      const Real accumulated = p.normalImpulse;
      const Real updated =
          std::max(accumulated - p.normalMass * (vn + c.restitution * p.relativeVelocity), Real(0));
      p.normalImpulse = updated;
      p.maxNormalImpulse = std::max(p.maxNormalImpulse, updated - accumulated);
      applyPair(D, c, p, (updated - accumulated) * c.normal);
    }
  }
}

void storeMultibodyContacts(Data& D) {
  for (const MultibodyContact& c : D.multibodyContacts) {
    ContactInfo& info = D.contacts[std::size_t(c.contactIndex)];
    ContactExtra& extra = D.extras[std::size_t(c.contactIndex)];
    extra.approach = 0;
    for (int k = 0; k < c.pointCount; ++k) {
      const MultibodyPoint& p = c.points[std::size_t(k)];
      if (p.maxNormalImpulse > 0) extra.touching = true;
      extra.approach = std::max(extra.approach, -p.relativeVelocity);
      info.normalImpulses[std::size_t(k)] = p.normalImpulse;
      extra.tangentImpulse[std::size_t(k)] =
          p.tangentImpulse[0] * c.tangent[0] + p.tangentImpulse[1] * c.tangent[1];
    }
    extra.angularImpulse = Vec3::Zero();
  }
}

}  // namespace inertia::detail
