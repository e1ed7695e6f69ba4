// Scratch memory for the fixed-step integrators, owned by the caller and reused across steps.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>

#include "inertia/ode/state.h"

namespace inertia::ode {

/// Stage buffers for the fixed-step integrators (explicit, implicit and second-order), owned by
/// the caller so that a step allocates nothing once the buffers are sized.
///
/// One Workspace serves every method and any state size: each buffer grows on first use to the
/// size asked for and never shrinks. `Workspace(n)` sizes up front the stage buffers the
/// explicit first-order methods and the native second-order methods need for states of n
/// scalars; the rest (more stages for Dormand-Prince and backward Euler, the stacked (x, v)
/// state of a first-order method on a second-order system, a dense Jacobian, Verlet's history)
/// is sized by the first step that needs it. After that warm-up step, further steps of the same
/// method on states of the same size do not allocate (stage buffers also serve smaller states).
/// Not thread-safe: one workspace per thread of integration.
template <class Scalar>
class Workspace {
 public:
  /// Number of stage buffers (Dormand-Prince 5 at a fixed step needs 7: six stages and a
  /// stage state).
  static constexpr int kSlots = 7;

  Workspace() = default;
  /// Sizes the buffers the explicit first-order methods and the second-order methods use, for
  /// states of `n` scalars.
  explicit Workspace(Eigen::Index n) { reserve(n); }

  /// Grows (never shrinks) the three stage buffers the explicit first-order methods (RK4 at
  /// most) and the native second-order methods use to `n` scalars.
  void reserve(Eigen::Index n) {
    for (int i = 0; i < 3; ++i) grow(slots_[i], n);
  }

  /// Stage buffer `i` (0 <= i < kSlots) seen as a state of `n` scalars, grown if needed.
  /// For integrator implementations; the content is scratch between steps.
  template <int N>
  View<Scalar, N> slot(int i, Eigen::Index n) {
    grow(slots_[i], n);
    return View<Scalar, N>(slots_[i].data(), n);
  }

  /// The stacked state z = (x, v) of 2n scalars that a first-order method integrates when it
  /// is applied to a second-order system (kept apart from the stage buffers it uses).
  template <int N2>
  View<Scalar, N2> stacked(Eigen::Index n2) {
    grow(stacked_, n2);
    return View<Scalar, N2>(stacked_.data(), n2);
  }

  /// Dense n x n matrix (backward Euler with a dense Jacobian) and its LU factorisation.
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& matrix(Eigen::Index n) {
    if (matrix_.rows() != n) matrix_.resize(n, n);
    return matrix_;
  }
  Eigen::PartialPivLU<Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>>& lu() { return lu_; }

  /// Position Verlet's history: x_{n-1}, and the x and v the last Verlet step wrote, by which a
  /// step detects components the caller changed in between (see ode::verlet).
  struct VerletHistory {
    Vector<Scalar> previous;  ///< x_{n-1}.
    Vector<Scalar> lastX;     ///< x as the last step left it.
    Vector<Scalar> lastV;     ///< v as the last step left it.
    Scalar step = Scalar(0);  ///< h of the last step.
    bool valid = false;
  };
  VerletHistory& verletHistory() { return verlet_; }

  /// Forgets Verlet's history: the next Verlet step restarts from (x, v) by a Taylor step.
  /// Not needed after changing x or v between steps (that is detected), only to force it.
  void resetHistory() { verlet_.valid = false; }

 private:
  static void grow(Vector<Scalar>& buffer, Eigen::Index n) {
    if (buffer.size() < n) buffer.resize(n);
  }

  std::array<Vector<Scalar>, kSlots> slots_;
  Vector<Scalar> stacked_;
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> matrix_;
  Eigen::PartialPivLU<Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>> lu_;
  VerletHistory verlet_;
};

}  // namespace inertia::ode
