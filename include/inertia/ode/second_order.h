// Integrators for second-order systems x'' = a(t, x, v) (particles, bodies, mass-springs):
// symplectic Euler, velocity Verlet, position (Stormer) Verlet, linearised backward Euler, and
// an adapter that runs any first-order method on the stacked state (x, v).
//
// Positions x and velocities v are two states of the same size and layout (e.g. 3n floats of a
// structure-of-arrays particle buffer each); both are updated in place. `a(t, x, v, acc)` writes
// the acceleration for every component (for particles: force / mass).
#pragma once

#include <string>

#include "inertia/ode/implicit.h"
#include "inertia/ode/state.h"
#include "inertia/ode/workspace.h"

namespace inertia::ode {

/// Marks a Jacobian the caller did not provide: methods that need it throw
/// InvalidArgument naming it.
struct NoJacobian {};
/// Declares a Jacobian identically zero (e.g. da/dv when no force depends on velocity).
struct ZeroJacobian {};

/// A second-order system x'' = a(t, x, v), with the Jacobians backward Euler needs.
///
///     ode::SecondOrderSystem system{.acceleration = a, .dadx = ax, .dadv = ode::ZeroJacobian{}};
///
/// `acceleration(t, x, v, acc)` writes a (m/s^2 for particles). `dadx(t, x, v, w, out)` and
/// `dadv(t, x, v, w, out)` write the products (da/dx) w and (da/dv) w: matrix-free, so a
/// mass-spring or particle system never forms an n x n matrix. Either may be NoJacobian (the
/// default: only explicit methods then work) or ZeroJacobian. Callbacks are called through a
/// const reference and must be const-callable (a lambda that is not `mutable`).
template <class Accel, class DaDx = NoJacobian, class DaDv = NoJacobian>
struct SecondOrderSystem {
  Accel acceleration;
  DaDx dadx{};
  DaDv dadv{};
};

namespace detail {

template <class Scalar, int N, class A>
void evalAcceleration(A& a, Scalar t, const View<Scalar, N>& x, const View<Scalar, N>& v,
                      View<Scalar, N> acc) {
  a(t, ConstView<Scalar, N>(x.data(), x.size()), ConstView<Scalar, N>(v.data(), v.size()), acc);
}

template <class X, class V>
void checkSecondOrder(ScalarOf<X> t, ScalarOf<X> h, const X& x, const V& v) {
  static_assert(std::is_same_v<ScalarOf<X>, ScalarOf<V>>,
                "ode: positions and velocities must have the same scalar type");
  checkStep(t, h);
  checkSameSize(static_cast<Eigen::Index>(x.size()), static_cast<Eigen::Index>(v.size()),
                "positions x and velocities v");
}

}  // namespace detail

/// Symplectic (semi-implicit) Euler, order 1: velocity first, then position with the new
/// velocity (seed 002; Bullet's and Box2D's integrator):
///     v_{n+1} = v_n + h a(t_n, x_n, v_n),   x_{n+1} = x_n + h v_{n+1}.
/// Symplectic: on a harmonic oscillator it conserves a modified energy, so the energy error
/// stays bounded (relative O(omega h)) instead of drifting. One evaluation.
struct SymplecticEulerStepper {
  static constexpr int order = 1;

  template <class A, MutableState X, MutableState V>
  requires Acceleration<A, ScalarOf<X>, commonSizeOf<X, V>>
  void operator()(A&& a, ScalarOf<X> t, ScalarOf<X> h, X&& positions, V&& velocities,
                  Workspace<ScalarOf<X>>& ws) const {
    constexpr int N = commonSizeOf<X, V>;
    detail::checkSecondOrder(t, h, positions, velocities);
    auto x = detail::viewAs<N>(positions);
    auto v = detail::viewAs<N>(velocities);
    auto acc = ws.template slot<N>(0, x.size());
    detail::evalAcceleration(a, t, x, v, acc);
    v += h * acc;
    x += h * v;
  }
};

/// Velocity Verlet, order 2 (seed 003):
///     x_{n+1} = x_n + h v_n + h^2/2 a_n,   v_{n+1} = v_n + h/2 (a_n + a_{n+1}),
/// with a_n = a(t_n, x_n, v_n) and a_{n+1} = a(t_n + h, x_{n+1}, v_n + h a_n): the velocity
/// passed to the second evaluation is an Euler predictor, which keeps order 2 when forces
/// depend on velocity (drag); for a = a(x) it is the textbook method. Symplectic for a = a(x):
/// a harmonic oscillator's energy error stays bounded, relative O((omega h)^2).
/// Two evaluations: a_{n+1} is not carried to the next step because the caller may change x
/// or v in between (collisions), which would make it stale.
struct VelocityVerletStepper {
  static constexpr int order = 2;

  template <class A, MutableState X, MutableState V>
  requires Acceleration<A, ScalarOf<X>, commonSizeOf<X, V>>
  void operator()(A&& a, ScalarOf<X> t, ScalarOf<X> h, X&& positions, V&& velocities,
                  Workspace<ScalarOf<X>>& ws) const {
    using Scalar = ScalarOf<X>;
    constexpr int N = commonSizeOf<X, V>;
    detail::checkSecondOrder(t, h, positions, velocities);
    auto x = detail::viewAs<N>(positions);
    auto v = detail::viewAs<N>(velocities);
    const Eigen::Index n = x.size();
    auto a0 = ws.template slot<N>(0, n);
    auto a1 = ws.template slot<N>(1, n);
    auto vPredicted = ws.template slot<N>(2, n);
    detail::evalAcceleration(a, t, x, v, a0);
    x += h * v + (h * h / Scalar(2)) * a0;
    vPredicted = v + h * a0;
    detail::evalAcceleration(a, t + h, x, vPredicted, a1);
    v += (h / Scalar(2)) * (a0 + a1);
  }
};

/// Position (Stormer) Verlet, order 2 (seed 000): x_{n+1} = 2 x_n - x_{n-1} + h^2 a_n.
///
/// x_{n-1} is kept in the workspace. Start, and restart: when there is no history (first
/// step, reset, new size, or h differs from the last step's) every component starts with the
/// Taylor step x_1 = x_0 + h v_0 + h^2/2 a_0, i.e. x_{-1} is taken as x_0 - h v_0 + h^2/2 a_0.
/// The same restart is applied per component whose x or v differs from what the last step
/// left (a collision response or a teleport by the caller), so such changes are honoured.
///
/// v is not part of the recurrence; it is output as the one-sided estimate
///     v_{n+1} = (x_{n+1} - x_n) / h + h/2 a_n,
/// second-order accurate, and passed to a(t, x, v) for velocity-dependent forces.
/// One evaluation.
struct VerletStepper {
  static constexpr int order = 2;

  template <class A, MutableState X, MutableState V>
  requires Acceleration<A, ScalarOf<X>, commonSizeOf<X, V>>
  void operator()(A&& a, ScalarOf<X> t, ScalarOf<X> h, X&& positions, V&& velocities,
                  Workspace<ScalarOf<X>>& ws) const {
    using Scalar = ScalarOf<X>;
    constexpr int N = commonSizeOf<X, V>;
    detail::checkSecondOrder(t, h, positions, velocities);
    auto x = detail::viewAs<N>(positions);
    auto v = detail::viewAs<N>(velocities);
    const Eigen::Index n = x.size();
    auto acc = ws.template slot<N>(0, n);
    detail::evalAcceleration(a, t, x, v, acc);

    auto& history = ws.verletHistory();
    const bool restartAll = !history.valid || history.previous.size() != n || history.step != h;
    if (history.previous.size() != n) {
      history.previous.resize(n);
      history.lastX.resize(n);
      history.lastV.resize(n);
    }
    const Scalar h2 = h * h;
    for (Eigen::Index i = 0; i < n; ++i) {
      Scalar& previous = history.previous[i];
      if (restartAll || x[i] != history.lastX[i] || v[i] != history.lastV[i])
        previous = x[i] - h * v[i] + (h2 / Scalar(2)) * acc[i];  // Taylor start
      const Scalar next = Scalar(2) * x[i] - previous + h2 * acc[i];
      v[i] = (next - x[i]) / h + (h / Scalar(2)) * acc[i];
      previous = x[i];
      x[i] = next;
      history.lastX[i] = x[i];
      history.lastV[i] = v[i];
    }
    history.step = h;
    history.valid = true;
  }
};

/// Runs a first-order method (explicitEuler, midpoint, heun, rk4, dormandPrince5) on a
/// second-order system by stacking z = (x, v), z' = (v, a(t, x, v)). The stacked state lives in
/// the workspace (two copies of 2n scalars per step, no allocation after warm-up).
template <class FirstOrderStepper>
struct StackedStepper {
  static constexpr int order = FirstOrderStepper::order;
  FirstOrderStepper stepper{};

  template <class A, MutableState X, MutableState V>
  requires Acceleration<A, ScalarOf<X>, commonSizeOf<X, V>>
  void operator()(A&& a, ScalarOf<X> t, ScalarOf<X> h, X&& positions, V&& velocities,
                  Workspace<ScalarOf<X>>& ws) const {
    using Scalar = ScalarOf<X>;
    constexpr int N = commonSizeOf<X, V>;
    constexpr int N2 = N == Eigen::Dynamic ? Eigen::Dynamic : 2 * N;
    detail::checkSecondOrder(t, h, positions, velocities);
    auto x = detail::viewAs<N>(positions);
    auto v = detail::viewAs<N>(velocities);
    const Eigen::Index n = x.size();
    auto z = ws.template stacked<N2>(2 * n);
    View<Scalar, N>(z.data(), n) = x;
    View<Scalar, N>(z.data() + n, n) = v;
    auto f = [&a, n](Scalar time, ConstView<Scalar, N2> zz, View<Scalar, N2> dz) {
      const ConstView<Scalar, N> xx(zz.data(), n);
      const ConstView<Scalar, N> vv(zz.data() + n, n);
      View<Scalar, N>(dz.data(), n) = vv;
      a(time, xx, vv, View<Scalar, N>(dz.data() + n, n));
    };
    stepper(f, t, h, z, ws);
    x = View<Scalar, N>(z.data(), n);
    v = View<Scalar, N>(z.data() + n, n);
  }
};

/// Linearised backward Euler for a second-order system, order 1, solved matrix-free.
///
/// One Newton step of (dx, dv) = h (v_n + dv, a(t_{n+1}, x_n + dx, v_n + dv)) about (x_n, v_n)
/// reduces to (Baraff-Witkin 1998, eq. 16; seed 002 drops the factor h on the right):
///     (I - h^2 A_x - h A_v) dv = h (a_n + h A_x v_n),   v_{n+1} = v_n + dv,
///     x_{n+1} = x_n + h v_{n+1},
/// with a_n, A_x = da/dx, A_v = da/dv at (t_n + h, x_n, v_n). This is exactly
/// BackwardEulerStepper applied to the stacked system (x, v), with the x block eliminated.
///
/// Conjugate gradients (the default) need A_x and A_v symmetric negative semi-definite (springs,
/// linear damping), which makes the matrix symmetric positive definite for every h > 0;
/// otherwise choose LinearSolver::BiCgStab. Throws InvalidArgument if `system.dadx` or
/// `system.dadv` is NoJacobian (use ZeroJacobian when a does not depend on x or v).
struct BackwardEulerSecondOrderStepper {
  static constexpr int order = 1;

  template <class Accel, class DaDx, class DaDv, MutableState X, MutableState V>
  requires Acceleration<Accel, ScalarOf<X>, commonSizeOf<X, V>> LinearSolveReport
  operator()(const SecondOrderSystem<Accel, DaDx, DaDv>& system, ScalarOf<X> t, ScalarOf<X> h,
             X&& positions, V&& velocities, Workspace<ScalarOf<X>>& ws,
             const LinearSolverOptions<ScalarOf<X>>& options = {}) const {
    using Scalar = ScalarOf<X>;
    constexpr int N = commonSizeOf<X, V>;
    detail::checkSecondOrder(t, h, positions, velocities);
    detail::checkLinearOptions(options);
    if constexpr (std::is_same_v<DaDx, NoJacobian> || std::is_same_v<DaDv, NoJacobian>) {
      throw InvalidArgument(
          std::string("ode: backward_euler on a second-order system needs ") +
          (std::is_same_v<DaDx, NoJacobian>
               ? "SecondOrderSystem::dadx, the Jacobian of the acceleration with respect to "
                 "position"
               : "SecondOrderSystem::dadv, the Jacobian of the acceleration with respect to "
                 "velocity") +
          " (pass ode::ZeroJacobian{} if it is zero)");
    } else {
      auto x = detail::viewAs<N>(positions);
      auto v = detail::viewAs<N>(velocities);
      const Eigen::Index n = x.size();
      const ConstView<Scalar, N> xIn(x.data(), n);
      const ConstView<Scalar, N> vIn(v.data(), n);
      const Scalar tNew = t + h;
      auto rhs = ws.template slot<N>(0, n);
      auto dv = ws.template slot<N>(1, n);
      auto product = ws.template slot<N>(2, n);

      // rhs = h (a_n + h A_x v_n)
      system.acceleration(tNew, xIn, vIn, rhs);
      if constexpr (!std::is_same_v<DaDx, ZeroJacobian>) {
        system.dadx(tNew, xIn, vIn, vIn, product);
        rhs += h * product;
      }
      rhs *= h;
      // w -> (I - h^2 A_x - h A_v) w
      const auto apply = [&](ConstView<Scalar> w, View<Scalar> out) {
        const ConstView<Scalar, N> wn(w.data(), n);
        out = w;
        if constexpr (!std::is_same_v<DaDx, ZeroJacobian>) {
          system.dadx(tNew, xIn, vIn, wn, product);
          out -= (h * h) * View<Scalar>(product.data(), n);
        }
        if constexpr (!std::is_same_v<DaDv, ZeroJacobian>) {
          system.dadv(tNew, xIn, vIn, wn, product);
          out -= h * View<Scalar>(product.data(), n);
        }
      };
      const LinearSolveReport report = detail::solveMatrixFree<Scalar>(
          apply, ConstView<Scalar>(rhs.data(), n), View<Scalar>(dv.data(), n),
          ws.template slot<Eigen::Dynamic>(3, n), ws.template slot<Eigen::Dynamic>(4, n), options);
      if (dv.allFinite()) {
        v += dv;
        x += h * v;
      }
      return report;
    }
  }
};

/// First-order methods applied to a second-order system through the stacked state (x, v).
template <class FirstOrderStepper>
constexpr StackedStepper<FirstOrderStepper> stacked(FirstOrderStepper stepper) {
  return {stepper};
}

inline constexpr SymplecticEulerStepper symplecticEuler{};
inline constexpr VelocityVerletStepper velocityVerlet{};
inline constexpr VerletStepper verlet{};
inline constexpr BackwardEulerSecondOrderStepper backwardEulerSecondOrder{};

}  // namespace inertia::ode
