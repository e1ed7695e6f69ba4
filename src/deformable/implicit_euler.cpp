#include "deformable/implicit_euler.h"

#include "deformable/spring_forces.h"

namespace inertia::detail {

namespace {

template <class T>
Eigen::Ref<const Eigen::Vector3d> seg(const Eigen::VectorXd& v, T i) {
  return v.segment<3>(3 * Eigen::Index(i));
}

}  // namespace

// The spring blocks and the diagonal: A = M + h k_field - sum over springs of
// (h dF/dv + h^2 dF/dx), each spring's block entering at (a, a), (b, b) with + and at (a, b),
// (b, a) with -.
void ImplicitEuler::assemble(const ImplicitEulerInput& in, double h) {
  const std::size_t n = in.masses.size();
  stiffness_.resize(in.springs.size());
  blocks_.resize(in.springs.size());
  massDiagonal_.resize(3 * Eigen::Index(n));
  for (std::size_t i = 0; i < n; ++i)
    massDiagonal_.segment<3>(3 * Eigen::Index(i))
        .setConstant(double(in.masses[i]) + h * double(in.fieldDamping[i]));
  Eigen::VectorXd& diagonal = inverseDiagonal_;
  diagonal = massDiagonal_;
  for (std::size_t k = 0; k < in.springs.size(); ++k) {
    if (in.broken[k]) continue;
    const Spring& s = in.springs[k];
    const SpringJacobian j = springJacobian(s, seg(x_, s.a), seg(x_, s.b));
    stiffness_[k] = j.dx;
    blocks_[k] = -(h * j.dv + h * h * j.dx);
    diagonal.segment<3>(3 * Eigen::Index(s.a)) += blocks_[k].diagonal();
    diagonal.segment<3>(3 * Eigen::Index(s.b)) += blocks_[k].diagonal();
  }
  inverseDiagonal_ = diagonal.cwiseInverse();
}

// b = h (F + h dF/dx v) at the step's start, F the springs' and the fields' forces.
void ImplicitEuler::rightHandSide(const ImplicitEulerInput& in, double h) {
  const std::size_t n = in.masses.size();
  f_.setZero(3 * Eigen::Index(n));
  addSpringForces<double>(in.springs, in.broken, x_.data(), v_.data(), f_.data());
  for (std::size_t i = 0; i < 3 * n; ++i)
    f_[Eigen::Index(i)] += double(in.masses[i / 3]) * double(in.fieldAcceleration[i]);
  kv_.setZero(3 * Eigen::Index(n));
  for (std::size_t k = 0; k < in.springs.size(); ++k) {
    if (in.broken[k]) continue;
    const Spring& s = in.springs[k];
    const Eigen::Vector3d y = stiffness_[k] * (seg(v_, s.a) - seg(v_, s.b));
    kv_.segment<3>(3 * Eigen::Index(s.a)) += y;
    kv_.segment<3>(3 * Eigen::Index(s.b)) -= y;
  }
  b_ = h * (f_ + h * kv_);
}

void ImplicitEuler::apply(const Eigen::VectorXd& w, Eigen::VectorXd& out) const {
  out = massDiagonal_.cwiseProduct(w);
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    if (broken_[k]) continue;
    const Spring& s = springs_[k];
    const Eigen::Vector3d y = blocks_[k] * (seg(w, s.a) - seg(w, s.b));
    out.segment<3>(3 * Eigen::Index(s.a)) += y;
    out.segment<3>(3 * Eigen::Index(s.b)) -= y;
  }
}

// Baraff-Witkin's filter with S_i = 0 for a pinned vertex (all three directions constrained).
void ImplicitEuler::filter(Eigen::VectorXd& w) const {
  for (std::size_t i = 0; i < pinned_.size(); ++i)
    if (pinned_[i]) w.segment<3>(3 * Eigen::Index(i)).setZero();
}

ode::LinearSolveReport ImplicitEuler::step(const ImplicitEulerInput& in, Real hr, std::span<Real> x,
                                           std::span<Real> v) {
  const double h = double(hr);
  const Eigen::Index n3 = Eigen::Index(x.size());
  springs_ = in.springs;
  broken_ = in.broken;
  pinned_ = in.pinned;
  x_ = Eigen::Map<const VecX>(x.data(), n3).cast<double>();
  v_ = Eigen::Map<const VecX>(v.data(), n3).cast<double>();
  assemble(in, h);
  rightHandSide(in, h);
  // Pinned vertices are at rest and stay there: their prescribed velocity change z is zero.
  dv_.setZero(n3);
  const auto applyA = [this](const Eigen::VectorXd& w, Eigen::VectorXd& out) { apply(w, out); };
  const auto filterS = [this](Eigen::VectorXd& w) { filter(w); };
  ode::LinearSolveReport report =
      modifiedPcg(applyA, filterS, inverseDiagonal_, b_, dv_, in.tolerance, in.maxIterations, pcg_);
  if (!dv_.allFinite()) {
    report.converged = false;
    return report;
  }
  v_ += dv_;
  x_ += h * v_;
  Eigen::Map<VecX>(v.data(), n3) = v_.cast<Real>();
  Eigen::Map<VecX>(x.data(), n3) = x_.cast<Real>();
  return report;
}

}  // namespace inertia::detail
