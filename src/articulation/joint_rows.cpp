// The joint-space constraint stage of a step: limits, Coulomb friction, velocity limits, and
// damping and drives as soft rows, each on one degree of freedom, solved by projected
// Gauss-Seidel with the inverse mass matrix's columns (CRBA, Cholesky).
//
// Every row acts on the end-of-step velocity w of its dof, and the end-of-step position follows
// it: q(t + h) = p + h (w - qd*), with p and qd* the position and velocity the smooth stage
// predicted. A row drives w towards its target with an impulse lambda in [lo, hi]; a soft row
// (softness gamma > 0) stops at lambda = (target - w) / gamma (Catto, "Soft constraints", GDC
// 2011: the implicit spring-damper as a constraint with compliance).
#include <algorithm>
#include <cmath>
#include <limits>

#include "inertia/articulation/articulation.h"

namespace inertia::articulation {

namespace {

// Where a limit stops a dof that starts the step at q0: at the limit from inside; from beyond
// it, where it is (it goes no deeper; the position is then moved back by a fraction of the
// violation, without a velocity that would carry on past it).
template <class S>
S lowerStop(S q0, S lower) {
  return std::min(q0, lower);
}
template <class S>
S upperStop(S q0, S upper) {
  return std::max(q0, upper);
}

}  // namespace

template <class S>
void Articulation<S>::buildJointRows(S h) {
  constexpr S kInf = std::numeric_limits<S>::infinity();
  rows_.clear();
  std::fill(hasLimitRow_.begin(), hasLimitRow_.end(), 0);
  qdSmooth_ = qd_;
  const Model<S>& m = model_;
  for (int k = 0; k < m.nv(); ++k) {
    const S w = qd_(k);
    // Damping c: the force -c w(t + h), an impulse -h c w.
    if (m.damping()(k) > 0) rows_.push_back({k, S(0), S(1) / (h * m.damping()(k)), -kInf, kInf});
    if (m.friction()(k) > 0) {
      const S bound = m.friction()(k) * h;
      rows_.push_back({k, S(0), S(0), -bound, bound});
    }
    const int qi = m.scalarQIndex()[k];
    if (qi >= 0 && m.hasDrive(k)) {
      // F = kp (qt - q(t + h)) + kd (vt - w), q(t + h) = p + h (w - qd*):
      // F = kp (qt - p + h qd*) + kd vt - (h kp + kd) w = (h kp + kd) (target - w).
      const Drive<S>& d = m.drives()[k];
      const S c = h * d.stiffness + d.damping;
      const S target =
          (d.stiffness * (d.targetPosition - q_(qi) + h * w) + d.damping * d.targetVelocity) / c;
      const S bound = h * d.maxForce;
      rows_.push_back({k, target, S(1) / (h * c), -bound, bound});
    }
    if (w > m.velocityLimit()(k)) rows_.push_back({k, m.velocityLimit()(k), S(0), -kInf, S(0)});
    if (w < -m.velocityLimit()(k)) rows_.push_back({k, -m.velocityLimit()(k), S(0), S(0), kInf});
  }
  addLimitRows(h);
}

// Limit rows for the dofs whose end-of-step position q(t + h) = p + h (w - qd*) passes its stop
// and that have no such row yet. Returns whether it added any.
template <class S>
bool Articulation<S>::addLimitRows(S h) {
  constexpr S kInf = std::numeric_limits<S>::infinity();
  const Model<S>& m = model_;
  bool added = false;
  for (int k = 0; k < m.nv(); ++k) {
    const int qi = m.scalarQIndex()[k];
    if (qi < 0) continue;
    const S p = q_(qi), w = qdSmooth_(k), end = p + h * (qd_(k) - w), q0 = qStart_(qi);
    const S lo = lowerStop(q0, m.lower()(k)), hi = upperStop(q0, m.upper()(k));
    if (end < lo && !hasLimitRow_[2 * k]) {
      rows_.push_back({k, w + (lo - p) / h, S(0), S(0), kInf});
      hasLimitRow_[2 * k] = 1;
      added = true;
    }
    if (end > hi && !hasLimitRow_[2 * k + 1]) {
      rows_.push_back({k, w + (hi - p) / h, S(0), -kInf, S(0)});
      hasLimitRow_[2 * k + 1] = 1;
      added = true;
    }
  }
  return added;
}

template <class S>
void Articulation<S>::solveJointRows(S h) {
  impulse_.setZero();
  if (rows_.empty()) return;

  // H at the step's start configuration, factored once; H^-1 columns for the rows' dofs.
  crba<S>(model_, qStart_, ws_);
  ws_.llt.compute(ws_.H);
  std::fill(column_.begin(), column_.end(), -1);
  Minv_.resize(model_.nv(), model_.nv());
  int columns = 0;

  // Gauss-Seidel, then the limits that the solution pushed past become rows too (an active set
  // that only grows, at most two rows per dof), warm-started from the impulses so far.
  do {
    for (const Row& r : rows_) {
      if (column_[r.dof] >= 0) continue;
      column_[r.dof] = columns;
      Minv_.col(columns++) = ws_.llt.solve(VectorX<S>::Unit(model_.nv(), r.dof));
    }
    for (int it = 0; it < settings_.constraintIterations; ++it) {
      for (Row& r : rows_) {
        const int c = column_[r.dof];
        const S A = Minv_(r.dof, c);
        const S delta = (r.target - qd_(r.dof) - r.softness * r.lambda) / (A + r.softness);
        const S lambda = std::clamp(r.lambda + delta, r.lo, r.hi);
        qd_ += Minv_.col(c) * (lambda - r.lambda);
        r.lambda = lambda;
      }
    }
  } while (addLimitRows(h));

  for (const Row& r : rows_) impulse_(r.dof) += r.lambda;
  // The positions follow the velocity change: q(t + h) = p (+) h (w - qd*).
  qdSmooth_ = qd_ - qdSmooth_;
  integrateConfiguration<S>(model_, q_, qdSmooth_, h);
}

// A dof that started beyond a limit moves back by limitBaumgarte of the violation (a position
// change only: no velocity is left to carry it on).
template <class S>
void Articulation<S>::recoverLimits() {
  const Model<S>& m = model_;
  for (int k = 0; k < m.nv(); ++k) {
    const int qi = m.scalarQIndex()[k];
    if (qi < 0) continue;
    const S q0 = qStart_(qi), beta = settings_.limitBaumgarte;
    if (q0 < m.lower()(k)) q_(qi) += beta * (m.lower()(k) - q0);
    if (q0 > m.upper()(k)) q_(qi) -= beta * (q0 - m.upper()(k));
  }
}

template void Articulation<float>::buildJointRows(float);
template void Articulation<double>::buildJointRows(double);
template void Articulation<double>::solveJointRows(double);
template bool Articulation<float>::addLimitRows(float);
template bool Articulation<double>::addLimitRows(double);
template void Articulation<float>::recoverLimits();
template void Articulation<double>::recoverLimits();
template void Articulation<float>::solveJointRows(float);

}  // namespace inertia::articulation
