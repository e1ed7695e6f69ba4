// The joint-space constraint rows: limits, Coulomb friction, velocity limits, and damping and
// drives as soft rows, each on one degree of freedom, solved by projected Gauss-Seidel with the
// inverse mass matrix's columns (CRBA, Cholesky).
//
// Every row acts on the end-of-step velocity w of its dof, and the end-of-step position of a
// scalar dof follows it: q(t + h) = base + h w (base: the step's start position under
// semi-implicit Euler; p - h qd* after RK4, p and qd* the position and velocity it predicted).
// A row drives w towards its target with an impulse lambda in [lo, hi]; a soft row (softness
// gamma > 0) stops at lambda = (target - w) / gamma (Catto, "Soft constraints", GDC 2011: the
// implicit spring-damper as a constraint with compliance).
#include <algorithm>
#include <cmath>
#include <limits>

#include "inertia/articulation/articulation.h"

namespace inertia::articulation {

template <class S>
void Articulation<S>::factorMassMatrix(const VectorX<S>& q) {
  crba<S>(model_, q, ws_);
  ws_.llt.compute(ws_.H);
  std::fill(columnReady_.begin(), columnReady_.end(), 0);
}

// H^-1 e_dof, solved from the factor on first use after each factorisation.
template <class S>
typename MatrixX<S>::ColXpr Articulation<S>::inverseMassColumn(int dof) {
  auto column = Minv_.col(dof);
  if (!columnReady_[std::size_t(dof)]) {
    column.setZero();
    column(dof) = 1;
    ws_.llt.solveInPlace(column);
    columnReady_[std::size_t(dof)] = 1;
  }
  return column;
}

// Where each scalar dof ends the step, base + h w, and the stops its limits set: at a limit
// from inside; from beyond it (the dof at `from`), where it is, so that it goes no deeper (the
// position is then moved back by recoverLimits, without a velocity that would carry on past it).
template <class S>
void Articulation<S>::aimLimits(const VectorX<S>& from, S h, bool afterSmooth) {
  constexpr S kInf = std::numeric_limits<S>::infinity();
  const Model<S>& m = model_;
  h_ = h;
  for (int k = 0; k < m.nv(); ++k) {
    const int qi = m.scalarQIndex()[k];
    base_(k) = qi < 0 ? S(0) : q_(qi) - (afterSmooth ? h * qd_(k) : S(0));
    lowStop_(k) = qi < 0 ? -kInf : std::min(from(qi), m.lower()(k));
    highStop_(k) = qi < 0 ? kInf : std::max(from(qi), m.upper()(k));
  }
}

template <class S>
void Articulation<S>::buildJointRows(S h) {
  constexpr S kInf = std::numeric_limits<S>::infinity();
  const Model<S>& m = model_;
  std::fill(lastImpulse_.begin(), lastImpulse_.end(), S(0));
  for (const Row& r : rows_) lastImpulse_[std::size_t(r.kind * m.nv() + r.dof)] = r.lambda;
  rows_.clear();
  std::fill(hasLimitRow_.begin(), hasLimitRow_.end(), 0);
  for (int k = 0; k < m.nv(); ++k) {
    // Damping c: the force -c w(t + h), an impulse -h c w.
    if (m.damping()(k) > 0)
      rows_.push_back({k, kDamping, S(0), S(1) / (h * m.damping()(k)), -kInf, kInf});
    if (m.friction()(k) > 0) {
      const S bound = m.friction()(k) * h;
      rows_.push_back({k, kFriction, S(0), S(0), -bound, bound});
    }
    if (m.scalarQIndex()[k] >= 0 && m.hasDrive(k)) {
      // F = kp (qt - q(t + h)) + kd (vt - w), q(t + h) = base + h w:
      // F = kp (qt - base) + kd vt - (h kp + kd) w = (h kp + kd) (target - w).
      const Drive<S>& d = m.drives()[k];
      const S c = h * d.stiffness + d.damping;
      const S target =
          (d.stiffness * (d.targetPosition - base_(k)) + d.damping * d.targetVelocity) / c;
      const S bound = h * d.maxForce;
      rows_.push_back({k, kDrive, target, S(1) / (h * c), -bound, bound});
    }
    // Velocity limits, both sides whenever finite: other rows and contacts may push past them.
    const S vmax = m.velocityLimit()(k);
    if (std::isfinite(vmax)) {
      rows_.push_back({k, kSpeedMax, vmax, S(0), -kInf, S(0)});
      rows_.push_back({k, kSpeedMin, -vmax, S(0), S(0), kInf});
    }
  }
  addLimitRows();
}

// A limit's row: the end position base + h w stays on the stop's side.
template <class S>
typename Articulation<S>::Row Articulation<S>::limitRow(int dof, RowKind kind) const {
  constexpr S kInf = std::numeric_limits<S>::infinity();
  if (kind == kLower) return {dof, kind, (lowStop_(dof) - base_(dof)) / h_, S(0), S(0), kInf};
  return {dof, kind, (highStop_(dof) - base_(dof)) / h_, S(0), -kInf, S(0)};
}

// Limit rows for the dofs whose end-of-step position base + h w passes its stop and that have
// no such row yet (an active set that only grows, at most two rows per dof). Returns whether it
// added any.
template <class S>
bool Articulation<S>::addLimitRows() {
  bool added = false;
  for (int k = 0; k < model_.nv(); ++k) {
    const S end = base_(k) + h_ * qd_(k);
    for (const RowKind kind : {kLower, kUpper}) {
      char& has = hasLimitRow_[std::size_t(2 * k + (kind == kUpper))];
      if (has || (kind == kLower ? end >= lowStop_(k) : end <= highStop_(k))) continue;
      rows_.push_back(limitRow(k, kind));
      has = 1;
      added = true;
    }
  }
  return added;
}

// In a world's substeps, each row starts from its impulse of the last substep (within its new
// bounds) and applies it, as the contacts are warm-started: a robot that holds a pose starts
// each substep with the torques that held it, and the few iterations that the contacts take
// refine them. Limits that pushed join the rows at once.
template <class S>
void Articulation<S>::warmStartJointRows() {
  const int nv = model_.nv();
  for (int k = 0; k < nv; ++k) {
    for (const RowKind kind : {kLower, kUpper}) {
      char& has = hasLimitRow_[std::size_t(2 * k + (kind == kUpper))];
      if (has || lastImpulse_[std::size_t(kind * nv + k)] == 0) continue;
      rows_.push_back(limitRow(k, kind));
      has = 1;
    }
  }
  for (Row& r : rows_) {
    r.lambda = std::clamp(lastImpulse_[std::size_t(r.kind * nv + r.dof)], r.lo, r.hi);
    if (r.lambda != 0) qd_ += inverseMassColumn(r.dof) * r.lambda;
  }
}

// The limit rows aimed again from base_ and the stops (after the position update: a relax
// pass may leave no velocity that would carry a dof past its stop in the next step).
template <class S>
void Articulation<S>::retargetLimitRows() {
  for (Row& r : rows_)
    if (r.kind == kLower || r.kind == kUpper) r.target = limitRow(r.dof, r.kind).target;
}

template <class S>
void Articulation<S>::sweepRows() {
  for (Row& r : rows_) {
    const auto column = inverseMassColumn(r.dof);
    const S delta = (r.target - qd_(r.dof) - r.softness * r.lambda) / (column(r.dof) + r.softness);
    const S lambda = std::clamp(r.lambda + delta, r.lo, r.hi);
    if (lambda == r.lambda) continue;
    qd_ += column * (lambda - r.lambda);
    r.lambda = lambda;
  }
}

template <class S>
void Articulation<S>::sweepJointRows() {
  addLimitRows();
  sweepRows();
}

// Gauss-Seidel sweeps, then the limits that the solution pushed past become rows too, and the
// sweeps repeat, warm-started from the impulses so far. H at the step's start configuration.
template <class S>
void Articulation<S>::solveJointRows() {
  if (rows_.empty()) return;
  factorMassMatrix(qStart_);
  do {
    for (int it = 0; it < settings_.constraintIterations; ++it) sweepRows();
  } while (addLimitRows());
}

template <class S>
void Articulation<S>::gatherImpulses() {
  impulse_.setZero();
  for (const Row& r : rows_) impulse_(r.dof) += r.lambda;
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

#define INERTIA_JOINT_ROWS(S)                                           \
  template void Articulation<S>::factorMassMatrix(const VectorX<S>&);   \
  template void Articulation<S>::aimLimits(const VectorX<S>&, S, bool); \
  template void Articulation<S>::buildJointRows(S);                     \
  template bool Articulation<S>::addLimitRows();                        \
  template void Articulation<S>::retargetLimitRows();                   \
  template void Articulation<S>::warmStartJointRows();                  \
  template void Articulation<S>::sweepJointRows();                      \
  template void Articulation<S>::solveJointRows();                      \
  template void Articulation<S>::gatherImpulses();                      \
  template void Articulation<S>::recoverLimits();
INERTIA_JOINT_ROWS(float)
INERTIA_JOINT_ROWS(double)
#undef INERTIA_JOINT_ROWS

}  // namespace inertia::articulation
