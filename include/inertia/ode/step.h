// One generic entry point: advance a second-order system by one step of a method chosen at run
// time (from a scene file's "integrator" string), so a particle system or a world can switch
// integrators without templates of its own.
#pragma once

#include <string>

#include "inertia/ode/explicit.h"
#include "inertia/ode/implicit.h"
#include "inertia/ode/method.h"
#include "inertia/ode/second_order.h"

namespace inertia::ode {

/// Advances x'' = a(t, x, v) from t to t + h with `method`, updating positions `x` and
/// velocities `v` in place.
///
/// - explicit_euler, midpoint, heun, rk4: the first-order method on the stacked state (x, v)
///   (StackedStepper).
/// - verlet, velocity_verlet, symplectic_euler: the native second-order methods.
/// - backward_euler: BackwardEulerSecondOrderStepper, matrix-free with `linear` settings; it
///   needs `system.dadx` and `system.dadv` and throws InvalidArgument naming the one that is
///   NoJacobian. The other methods never call the Jacobians.
///
/// x and v: Eigen vectors, spans, std::vectors or arrays of the same size and scalar (for SoA
/// particles: one span over 3n position scalars, one over 3n velocity scalars). `ws` is the
/// caller's scratch; after one warm-up step of a method, no step of it allocates, except
/// backward Euler's Krylov solve (Eigen allocates its work vectors per solve).
/// Throws InvalidArgument for h not finite or <= 0, t not finite, mismatched sizes, or a
/// method value outside the enum. Returns the linear solve's report (defaults for explicit
/// methods).
template <class Accel, class DaDx, class DaDv, MutableState X, MutableState V>
requires Acceleration<Accel, ScalarOf<X>, commonSizeOf<X, V>> LinearSolveReport step(
    Method method, const SecondOrderSystem<Accel, DaDx, DaDv>& system, ScalarOf<X> t, ScalarOf<X> h,
    X&& x, V&& v, Workspace<ScalarOf<X>>& ws, const LinearSolverOptions<ScalarOf<X>>& linear = {}) {
  const auto& a = system.acceleration;
  switch (method) {
    case Method::ExplicitEuler:
      stacked(explicitEuler)(a, t, h, x, v, ws);
      return {};
    case Method::Midpoint:
      stacked(midpoint)(a, t, h, x, v, ws);
      return {};
    case Method::Heun:
      stacked(heun)(a, t, h, x, v, ws);
      return {};
    case Method::Rk4:
      stacked(rk4)(a, t, h, x, v, ws);
      return {};
    case Method::Verlet:
      verlet(a, t, h, x, v, ws);
      return {};
    case Method::VelocityVerlet:
      velocityVerlet(a, t, h, x, v, ws);
      return {};
    case Method::SymplecticEuler:
      symplecticEuler(a, t, h, x, v, ws);
      return {};
    case Method::BackwardEuler:
      return backwardEulerSecondOrder(system, t, h, x, v, ws, linear);
  }
  throw InvalidArgument("ode: unknown integration method (value " +
                        std::to_string(static_cast<int>(method)) + ")");
}

/// The same for a system given by its acceleration alone (no Jacobians): backward_euler then
/// throws InvalidArgument naming the missing dadx.
template <class Accel, MutableState X, MutableState V>
requires Acceleration<Accel, ScalarOf<X>, commonSizeOf<X, V>> LinearSolveReport
step(Method method, const Accel& acceleration, ScalarOf<X> t, ScalarOf<X> h, X&& x, V&& v,
     Workspace<ScalarOf<X>>& ws) {
  const SecondOrderSystem<const Accel&> system{acceleration};
  return step(method, system, t, h, std::forward<X>(x), std::forward<V>(v), ws);
}

}  // namespace inertia::ode
