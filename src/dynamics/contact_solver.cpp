#include "contact_solver.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace inertia::detail {

namespace {

// The static body: no velocity, no motion, infinite mass.
const SolverBody kStatic{};

SolverBody& bodyRef(std::vector<SolverBody>& bodies, int i, SolverBody& scratch) {
  if (i < 0) {
    scratch = kStatic;
    return scratch;
  }
  return bodies[static_cast<std::size_t>(i)];
}

Real invEffective(Real k) { return k > 0 ? Real(1) / k : Real(0); }

// Linear and angular impulse P at anchors rA/rB: A gets -P, B gets +P.
inline void applyLinear(SolverBody& a, SolverBody& b, const Vec3& rA, const Vec3& rB,
                        const Vec3& P) {
  a.v -= a.invMass * P;
  a.w -= a.invInertia * rA.cross(P);
  b.v += b.invMass * P;
  b.w += b.invInertia * rB.cross(P);
}

inline void applyAngular(SolverBody& a, SolverBody& b, const Vec3& L) {
  a.w -= a.invInertia * L;
  b.w += b.invInertia * L;
}

inline Vec3 relativeVelocity(const SolverBody& a, const SolverBody& b, const Vec3& rA,
                             const Vec3& rB) {
  return b.v + b.w.cross(rB) - a.v - a.w.cross(rA);
}

}  // namespace

Softness makeSoft(Real hertz, Real zeta, Real h) {
  if (hertz <= 0) return {0, 1, 0};
  const Real omega = Real(2 * std::numbers::pi) * hertz;
  const Real a1 = 2 * zeta + h * omega;
  const Real a2 = h * omega * a1;
  const Real a3 = 1 / (1 + a2);
  return {omega / a1, a2 * a3, a3};
}

std::array<Vec3, 2> tangentBasis(const Vec3& n) {
  const Real sign = std::copysign(Real(1), n.z());
  const Real a = -1 / (sign + n.z());
  const Real b = n.x() * n.y() * a;
  return {Vec3(1 + sign * n.x() * n.x() * a, sign * b, -sign * n.x()),
          Vec3(b, sign + n.y() * n.y() * a, -n.y())};
}

void computeMasses(ContactConstraint& c, const SolverBody& a, const SolverBody& b) {
  const Real mSum = a.invMass + b.invMass;
  auto rowMass = [&](const Vec3& rA, const Vec3& rB, const Vec3& d) {
    const Vec3 ra = rA.cross(d), rb = rB.cross(d);
    return invEffective(mSum + ra.dot(a.invInertia * ra) + rb.dot(b.invInertia * rb));
  };
  for (int i = 0; i < c.pointCount; ++i) {
    ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
    p.normalMass = rowMass(p.rA, p.rB, c.normal);
    for (int k = 0; k < 2; ++k) p.tangentMass[k] = rowMass(p.rA, p.rB, c.tangent[k]);
  }
  const Mat3 iSum = a.invInertia + b.invInertia;
  for (int k = 0; k < 2; ++k) c.rollingMass[k] = invEffective(c.tangent[k].dot(iSum * c.tangent[k]));
  c.spinningMass = invEffective(c.normal.dot(iSum * c.normal));
}

void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies) {
  SolverBody sa, sb;
  for (ContactConstraint& c : cs) {
    SolverBody& a = bodyRef(bodies, c.bodyA, sa);
    SolverBody& b = bodyRef(bodies, c.bodyB, sb);
    for (int i = 0; i < c.pointCount; ++i) {
      const ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      const Vec3 P = p.normalImpulse * c.normal + p.tangentImpulse[0] * c.tangent[0] +
                     p.tangentImpulse[1] * c.tangent[1];
      applyLinear(a, b, p.rA, p.rB, P);
    }
    applyAngular(a, b, c.rollingImpulse[0] * c.tangent[0] + c.rollingImpulse[1] * c.tangent[1] +
                           c.spinningImpulse * c.normal);
  }
}

void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode) {
  SolverBody sa, sb;
  for (ContactConstraint& c : cs) {
    SolverBody& a = bodyRef(bodies, c.bodyA, sa);
    SolverBody& b = bodyRef(bodies, c.bodyB, sb);
    const Vec3& n = c.normal;
    const Vec3 dp = b.dp - a.dp;
    Real totalNormal = 0;

    // Non-penetration rows.
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      // The separation now, from the bodies' motion since the step's start.
      const Vec3 d = dp + b.dq * p.rB - a.dq * p.rA;
      const Real s = d.dot(n) + p.adjustedSeparation;
      Real bias = 0, massScale = 1, impulseScale = 0;
      if (s > 0) {
        bias = s * mode.invH;  // speculative: the gap may close within this substep, no more
      } else if (mode.useBias) {
        if (mode.soft) {
          bias = std::max(c.softness.biasRate * s, -mode.pushVelocity);
          massScale = c.softness.massScale;
          impulseScale = c.softness.impulseScale;
        } else {
          // Baumgarte: feed back a fraction of the overlap beyond the slop.
          bias = std::max(mode.baumgarte * mode.invH * std::min(s + mode.linearSlop, Real(0)),
                          -mode.pushVelocity);
        }
      }
      const Real vn = relativeVelocity(a, b, p.rA, p.rB).dot(n);
      Real impulse = -p.normalMass * massScale * (vn + bias) - impulseScale * p.normalImpulse;
      const Real updated = std::max(p.normalImpulse + impulse, Real(0));
      impulse = updated - p.normalImpulse;
      p.normalImpulse = updated;
      p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
      totalNormal += updated;
      applyLinear(a, b, p.rA, p.rB, impulse * n);
    }

    // Coulomb friction: the tangential impulse stays in the disc of radius mu * normal.
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      const Vec3 dv = relativeVelocity(a, b, p.rA, p.rB);
      std::array<Real, 2> updated;
      for (int k = 0; k < 2; ++k)
        updated[k] = p.tangentImpulse[k] - p.tangentMass[k] * dv.dot(c.tangent[k]);
      const Real limit = c.friction * p.normalImpulse;
      const Real len2 = updated[0] * updated[0] + updated[1] * updated[1];
      if (len2 > limit * limit) {
        const Real scale = limit / std::sqrt(len2);
        updated[0] *= scale;
        updated[1] *= scale;
      }
      const Vec3 P = (updated[0] - p.tangentImpulse[0]) * c.tangent[0] +
                     (updated[1] - p.tangentImpulse[1]) * c.tangent[1];
      p.tangentImpulse = updated;
      applyLinear(a, b, p.rA, p.rB, P);
    }

    // Rolling resistance (torque <= b N about the tangents) and spinning friction.
    if (c.rolling > 0) {
      const Vec3 dw = b.w - a.w;
      std::array<Real, 2> updated;
      for (int k = 0; k < 2; ++k)
        updated[k] = c.rollingImpulse[k] - c.rollingMass[k] * dw.dot(c.tangent[k]);
      const Real limit = c.rolling * totalNormal;
      const Real len2 = updated[0] * updated[0] + updated[1] * updated[1];
      if (len2 > limit * limit) {
        const Real scale = limit / std::sqrt(len2);
        updated[0] *= scale;
        updated[1] *= scale;
      }
      applyAngular(a, b, (updated[0] - c.rollingImpulse[0]) * c.tangent[0] +
                             (updated[1] - c.rollingImpulse[1]) * c.tangent[1]);
      c.rollingImpulse = updated;
    }
    if (c.spinning > 0) {
      const Real limit = c.spinning * totalNormal;
      const Real updated = std::clamp(c.spinningImpulse - c.spinningMass * (b.w - a.w).dot(n),
                                      -limit, limit);
      applyAngular(a, b, (updated - c.spinningImpulse) * n);
      c.spinningImpulse = updated;
    }
  }
}

void updateApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies) {
  for (ContactConstraint& c : cs) {
    if (c.restitution == 0) continue;
    const SolverBody& a = c.bodyA >= 0 ? bodies[static_cast<std::size_t>(c.bodyA)] : kStatic;
    const SolverBody& b = c.bodyB >= 0 ? bodies[static_cast<std::size_t>(c.bodyB)] : kStatic;
    const Vec3 dp = b.dp - a.dp;
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      const Real s = (dp + b.dq * p.rB - a.dq * p.rA).dot(c.normal) + p.adjustedSeparation;
      if (s > 0 && p.maxNormalImpulse == 0)
        p.relativeVelocity = relativeVelocity(a, b, p.rA, p.rB).dot(c.normal);
    }
  }
}

void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold) {
  SolverBody sa, sb;
  for (ContactConstraint& c : cs) {
    if (c.restitution == 0) continue;
    SolverBody& a = bodyRef(bodies, c.bodyA, sa);
    SolverBody& b = bodyRef(bodies, c.bodyB, sb);
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      if (p.relativeVelocity > -threshold || p.maxNormalImpulse == 0) continue;
      const Real vn = relativeVelocity(a, b, p.rA, p.rB).dot(c.normal);
      Real impulse = -p.normalMass * (vn + c.restitution * p.relativeVelocity);
      const Real updated = std::max(p.normalImpulse + impulse, Real(0));
      impulse = updated - p.normalImpulse;
      p.normalImpulse = updated;
      p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
      applyLinear(a, b, p.rA, p.rB, impulse * c.normal);
    }
  }
}

}  // namespace inertia::detail
