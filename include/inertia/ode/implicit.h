// Linearised backward Euler for first-order systems y' = f(t, y): one Newton step of
// y_{n+1} = y_n + h f(t_{n+1}, y_{n+1}) about y_n (seed 000 "Implicit Euler", seed 002
// "Backward Euler"), with a dense Jacobian (LU) or matrix-free (conjugate gradients).
#pragma once

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <utility>

#include "inertia/ode/state.h"
#include "inertia/ode/workspace.h"

namespace inertia::ode {

/// Krylov solver for the matrix-free implicit steps.
enum class LinearSolver {
  /// Conjugate gradients: needs a symmetric positive definite system matrix, which (I - h J)
  /// is when J is symmetric negative semi-definite (springs and linear damping, Baraff-Witkin).
  ConjugateGradient,
  /// BiCGSTAB: any non-singular system matrix (drag vortices, non-symmetric couplings), at
  /// about twice the cost per iteration.
  BiCgStab,
};

/// Settings of the matrix-free linear solve (Eigen's iterative solvers, identity
/// preconditioner since the matrix is never formed).
template <class Scalar>
struct LinearSolverOptions {
  LinearSolver solver = LinearSolver::ConjugateGradient;
  /// Relative residual |M dy - b| / |b| at which the solve stops. The default, sqrt(epsilon)
  /// (1.5e-8 in double, 3.5e-4 in float), keeps the solve error below backward Euler's own
  /// O(h^2) local error for any useful h.
  Scalar tolerance = std::sqrt(std::numeric_limits<Scalar>::epsilon());
  /// Iteration cap; 0 means Eigen's default, twice the system size.
  int maxIterations = 0;
};

/// What an implicit step's linear solve did. Explicit methods report the defaults.
struct LinearSolveReport {
  int iterations = 0;     ///< Krylov iterations (0 for a dense LU solve).
  double error = 0;       ///< Relative residual reached (Krylov) or 0 (dense).
  bool converged = true;  ///< False if the tolerance was not met or the solution was not finite.
};

namespace detail {

/// A linear operator known only by its action, w -> M w, for Eigen's iterative solvers
/// (Eigen's "matrix-free solvers" recipe). `Apply` is `void(ConstView<Scalar> w,
/// View<Scalar> out)`. Two workspace buffers carry the product so nothing is allocated here.
template <class Scalar, class Apply>
class MatrixFreeOperator;

}  // namespace detail
}  // namespace inertia::ode

namespace Eigen::internal {
template <class Scalar, class Apply>
struct traits<inertia::ode::detail::MatrixFreeOperator<Scalar, Apply>>
    : public traits<Eigen::SparseMatrix<Scalar>> {};
}  // namespace Eigen::internal

namespace inertia::ode::detail {

template <class Scalar_, class Apply>
class MatrixFreeOperator : public Eigen::EigenBase<MatrixFreeOperator<Scalar_, Apply>> {
 public:
  using Scalar = Scalar_;
  using RealScalar = Scalar_;
  using StorageIndex = int;
  enum {
    ColsAtCompileTime = Eigen::Dynamic,
    MaxColsAtCompileTime = Eigen::Dynamic,
    IsRowMajor = false
  };

  MatrixFreeOperator(const Apply& apply, View<Scalar> in, View<Scalar> out)
      : apply_(&apply), in_(in.data(), in.size()), out_(out.data(), out.size()) {}

  Eigen::Index rows() const { return in_.size(); }
  Eigen::Index cols() const { return in_.size(); }

  template <class Rhs>
  Eigen::Product<MatrixFreeOperator, Rhs, Eigen::AliasFreeProduct> operator*(
      const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<MatrixFreeOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

  /// dst += alpha * M rhs.
  template <class Dest, class Rhs>
  void scaleAndAddTo(Dest& dst, const Rhs& rhs, Scalar alpha) const {
    in_ = rhs;
    (*apply_)(ConstView<Scalar>(in_.data(), in_.size()), out_);
    dst += alpha * out_;
  }

 private:
  const Apply* apply_;
  mutable View<Scalar> in_;
  mutable View<Scalar> out_;
};

}  // namespace inertia::ode::detail

namespace Eigen::internal {
template <class Scalar, class Apply, class Rhs, int ProductType>
struct generic_product_impl<inertia::ode::detail::MatrixFreeOperator<Scalar, Apply>, Rhs,
                            SparseShape, DenseShape, ProductType>
    : generic_product_impl_base<
          inertia::ode::detail::MatrixFreeOperator<Scalar, Apply>, Rhs,
          generic_product_impl<inertia::ode::detail::MatrixFreeOperator<Scalar, Apply>, Rhs>> {
  template <class Dest>
  static void scaleAndAddTo(Dest& dst,
                            const inertia::ode::detail::MatrixFreeOperator<Scalar, Apply>& lhs,
                            const Rhs& rhs, const Scalar& alpha) {
    lhs.scaleAndAddTo(dst, rhs, alpha);
  }
};
}  // namespace Eigen::internal

namespace inertia::ode {
namespace detail {

/// Solves M dy = b with the operator `apply` (w -> M w) by CG or BiCGSTAB; dy starts at 0.
/// Eigen's solvers allocate their four to seven work vectors on each solve; nothing else does.
template <class Scalar, class Apply>
LinearSolveReport solveMatrixFree(const Apply& apply, ConstView<Scalar> b, View<Scalar> dy,
                                  View<Scalar> scratchIn, View<Scalar> scratchOut,
                                  const LinearSolverOptions<Scalar>& options) {
  using Operator = MatrixFreeOperator<Scalar, Apply>;
  const Operator op(apply, scratchIn, scratchOut);
  LinearSolveReport report;
  auto run = [&](auto& solver) {
    solver.setTolerance(options.tolerance);
    if (options.maxIterations > 0) solver.setMaxIterations(options.maxIterations);
    solver.compute(op);
    dy = solver.solve(b);
    report.iterations = static_cast<int>(solver.iterations());
    report.error = static_cast<double>(solver.error());
    report.converged = solver.info() == Eigen::Success;
  };
  if (options.solver == LinearSolver::ConjugateGradient) {
    Eigen::ConjugateGradient<Operator, Eigen::Lower | Eigen::Upper, Eigen::IdentityPreconditioner>
        cg;
    run(cg);
  } else {
    Eigen::BiCGSTAB<Operator, Eigen::IdentityPreconditioner> bicg;
    run(bicg);
  }
  if (!dy.allFinite()) report.converged = false;
  return report;
}

template <class Scalar>
void checkLinearOptions(const LinearSolverOptions<Scalar>& options) {
  if (!(options.tolerance > Scalar(0) && std::isfinite(options.tolerance)))
    throw InvalidArgument("ode: LinearSolverOptions::tolerance must be finite and > 0");
  if (options.maxIterations < 0)
    throw InvalidArgument("ode: LinearSolverOptions::maxIterations must be >= 0");
}

}  // namespace detail

/// Linearised backward Euler with a dense Jacobian, order 1.
///
/// One Newton step of y_{n+1} = y_n + h f(t_{n+1}, y_{n+1}) about y_n:
///     (I - h J) dy = h f(t_n + h, y_n),   y_{n+1} = y_n + dy,   J = df/dy (t_n + h, y_n),
/// solved by Eigen's partial-pivoting LU. f and J are taken at the new time so that the step
/// equals exact backward Euler on every linear system y' = A y + g(t) (stable for any h > 0
/// when A's eigenvalues have non-positive real parts); on non-linear systems it differs from
/// backward Euler by O(h^2) per step, keeping order 1. One evaluation of f and of J.
///
/// `jacobian(t, y, J)` writes df/dy into J, zeroed before the call. Cost O(n^3): for large
/// sparse systems use backwardEulerMatrixFree. If (I - h J) is singular the solution is not
/// finite: y is then left unchanged and the report says `converged = false`.
struct BackwardEulerStepper {
  static constexpr int order = 1;

  template <class F, class Jac, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>> && DenseJacobian<Jac, ScalarOf<S>, sizeOf<S>>
      LinearSolveReport operator()(F&& f, Jac&& jacobian, ScalarOf<S> t, ScalarOf<S> h, S&& state,
                                   Workspace<ScalarOf<S>>& ws) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    auto y = detail::view(state);
    const Eigen::Index n = y.size();
    const ConstView<Scalar, N> yIn(y.data(), n);
    auto rhs = ws.template slot<N>(0, n);
    auto dy = ws.template slot<N>(1, n);
    auto& m = ws.matrix(n);

    f(t + h, yIn, rhs);
    rhs *= h;
    m.setZero();
    jacobian(t + h, yIn, JacobianView<Scalar, N>(m.data(), n, n));
    // Seed 002: (I - h df/dy) dy = h f.
    m *= -h;
    m.diagonal().array() += Scalar(1);
    ws.lu().compute(m);
    dy = ws.lu().solve(rhs);
    LinearSolveReport report;
    if (!dy.allFinite()) {
      report.converged = false;
      return report;
    }
    y += dy;
    return report;
  }
};

/// Linearised backward Euler solved matrix-free by a Krylov method, order 1.
///
/// The same step as BackwardEulerStepper, (I - h J) dy = h f(t_n + h, y_n), but J is known only
/// through `jacobianTimes(t, y, w, out)`, out = J w, and the system is solved by Eigen's
/// ConjugateGradient (default) or BiCGSTAB (LinearSolverOptions::solver).
///
/// Conjugate gradients require (I - h J) symmetric positive definite, which holds for every
/// h > 0 when J is symmetric negative semi-definite (mass-spring systems with linear damping,
/// Baraff-Witkin 1998). For a non-symmetric J select LinearSolver::BiCgStab. A solve that does
/// not reach the tolerance still applies its last (finite) iterate and reports
/// `converged = false`; a non-finite one leaves y unchanged.
struct BackwardEulerMatrixFreeStepper {
  static constexpr int order = 1;

  template <class F, class JacTimes, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>> &&
      JacobianProduct<JacTimes, ScalarOf<S>, sizeOf<S>>
          LinearSolveReport operator()(F&& f, JacTimes&& jacobianTimes, ScalarOf<S> t,
                                       ScalarOf<S> h, S&& state, Workspace<ScalarOf<S>>& ws,
                                       const LinearSolverOptions<ScalarOf<S>>& options = {}) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    detail::checkLinearOptions(options);
    auto y = detail::view(state);
    const Eigen::Index n = y.size();
    const ConstView<Scalar, N> yIn(y.data(), n);
    auto rhs = ws.template slot<N>(0, n);
    auto dy = ws.template slot<N>(1, n);
    auto jw = ws.template slot<N>(2, n);

    f(t + h, yIn, rhs);
    rhs *= h;
    // w -> (I - h J) w
    const auto apply = [&](ConstView<Scalar> w, View<Scalar> out) {
      jacobianTimes(t + h, yIn, ConstView<Scalar, N>(w.data(), n), View<Scalar, N>(jw.data(), n));
      out = w - h * View<Scalar>(jw.data(), n);
    };
    const LinearSolveReport report = detail::solveMatrixFree<Scalar>(
        apply, ConstView<Scalar>(rhs.data(), n), View<Scalar>(dy.data(), n),
        ws.template slot<Eigen::Dynamic>(3, n), ws.template slot<Eigen::Dynamic>(4, n), options);
    if (dy.allFinite()) y += dy;
    return report;
  }
};

inline constexpr BackwardEulerStepper backwardEuler{};
inline constexpr BackwardEulerMatrixFreeStepper backwardEulerMatrixFree{};

/// An implicit stepper with its Jacobian bound, so that it has the plain stepper interface
/// `(f, t, h, y, ws)` and `order` of the explicit ones, e.g. as the base method of
/// StepDoubling: `ode::StepDoubling<double, decltype(s)> sd(s)` with
/// `auto s = ode::withJacobian(ode::backwardEuler, jacobian)`. The linear solve's report is
/// dropped (matrix-free solves use default LinearSolverOptions).
template <class ImplicitStepper, class Jacobian>
struct WithJacobian {
  static constexpr int order = ImplicitStepper::order;
  ImplicitStepper stepper;
  Jacobian jacobian;

  template <class F, MutableState S>
  void operator()(F&& f, ScalarOf<S> t, ScalarOf<S> h, S&& y, Workspace<ScalarOf<S>>& ws) const {
    stepper(f, jacobian, t, h, y, ws);
  }
};

template <class ImplicitStepper, class Jacobian>
WithJacobian<ImplicitStepper, Jacobian> withJacobian(ImplicitStepper stepper, Jacobian jacobian) {
  return {stepper, std::move(jacobian)};
}

}  // namespace inertia::ode
