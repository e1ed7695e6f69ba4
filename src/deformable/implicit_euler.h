// Baraff and Witkin's implicit step (1998, "Large steps in cloth simulation", section 4):
// one Newton step of backward Euler, linearised about the state at the start of the step,
//     (M - h dF/dv - h^2 dF/dx) dv = h (F + h dF/dx v),   v' = v + dv,   x' = x + h v',
// with the springs' analytic Jacobians, solved matrix-free (3 x 3 blocks per spring) by the
// modified preconditioned conjugate gradients, which keep pinned vertices still.
// Assembled and solved in double whatever Real is: on stiff cloth float CG stalls near 1e-4.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "deformable/modified_pcg.h"
#include "inertia/core/types.h"
#include "inertia/deformable/model.h"
#include "inertia/ode/implicit.h"

namespace inertia::detail {

/// What one implicit step reads besides the state.
struct ImplicitEulerInput {
  std::span<const Spring> springs;
  std::span<const std::uint8_t> broken;     ///< one per spring
  std::span<const Real> masses;             ///< kg, one per vertex
  std::span<const std::uint8_t> pinned;     ///< one per vertex
  std::span<const Real> fieldAcceleration;  ///< m/s^2, 3 per vertex, at the step's start
  /// Per vertex, the linear drag coefficient k (kg/s) of the fields (F = -k v), taken into
  /// dF/dv so that strong drag is implicit too.
  std::span<const Real> fieldDamping;
  double tolerance = 1e-6;
  int maxIterations = 1000;
};

class ImplicitEuler {
 public:
  /// One step of h seconds; updates x and v (3 per vertex) in place unless the solve gave
  /// non-finite values, which leaves them as they were (the report says so).
  ode::LinearSolveReport step(const ImplicitEulerInput& in, Real h, std::span<Real> x,
                              std::span<Real> v);

  // The last step's system, for tests: A w, the right-hand side b and the solution dv.
  void apply(const Eigen::VectorXd& w, Eigen::VectorXd& out) const;
  void filter(Eigen::VectorXd& w) const;
  const Eigen::VectorXd& rhs() const { return b_; }
  const Eigen::VectorXd& solution() const { return dv_; }

 private:
  void assemble(const ImplicitEulerInput& in, double h);
  void rightHandSide(const ImplicitEulerInput& in, double h);

  std::span<const Spring> springs_;
  std::span<const std::uint8_t> broken_, pinned_;
  std::vector<Eigen::Matrix3d> stiffness_;  // dF_a/dx_a per spring
  std::vector<Eigen::Matrix3d> blocks_;     // -(h dF_a/dv_a + h^2 dF_a/dx_a) per spring
  Eigen::VectorXd x_, v_, f_, kv_, b_, dv_, massDiagonal_, inverseDiagonal_;
  PcgBuffers pcg_;
};

}  // namespace inertia::detail
