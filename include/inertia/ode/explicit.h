// Explicit one-step methods for first-order systems y' = f(t, y): Euler, midpoint, Heun, RK4.
//
// Each method is a function object, so it can be called directly,
//     ode::rk4(f, t, h, y, ws);        // y <- y(t + h), in place
// or handed to a generic driver (ode::StepDoubling) with its order, `decltype(ode::rk4)::order`.
// The state is updated in place: the seeds' "state in, state out" interface with one buffer,
// which is what a particle system wants; copy first to keep the old state.
#pragma once

#include "inertia/ode/state.h"
#include "inertia/ode/workspace.h"

namespace inertia::ode {

/// Explicit (forward) Euler, order 1: y_{n+1} = y_n + h f(t_n, y_n). One evaluation.
struct ExplicitEulerStepper {
  static constexpr int order = 1;

  template <class F, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>>
  void operator()(F&& f, ScalarOf<S> t, ScalarOf<S> h, S&& state,
                  Workspace<ScalarOf<S>>& ws) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    auto y = detail::view(state);
    auto k = ws.template slot<N>(0, y.size());
    f(t, ConstView<Scalar, N>(y.data(), y.size()), k);
    y += h * k;
  }
};

/// Explicit midpoint (RK2), order 2: y_{n+1} = y_n + h f(t_n + h/2, y_n + (h/2) f(t_n, y_n)).
/// Two evaluations.
struct MidpointStepper {
  static constexpr int order = 2;

  template <class F, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>>
  void operator()(F&& f, ScalarOf<S> t, ScalarOf<S> h, S&& state,
                  Workspace<ScalarOf<S>>& ws) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    auto y = detail::view(state);
    const Eigen::Index n = y.size();
    auto k = ws.template slot<N>(0, n);
    auto mid = ws.template slot<N>(1, n);
    const Scalar half = h / Scalar(2);
    f(t, ConstView<Scalar, N>(y.data(), n), k);
    mid = y + half * k;
    f(t + half, ConstView<Scalar, N>(mid.data(), n), k);
    y += h * k;
  }
};

/// Heun's method (explicit trapezoid, RK2 with a_1 = a_2 = 1/2), order 2:
/// y_{n+1} = y_n + (h/2) (k1 + k2), k1 = f(t_n, y_n), k2 = f(t_n + h, y_n + h k1).
/// Two evaluations.
struct HeunStepper {
  static constexpr int order = 2;

  template <class F, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>>
  void operator()(F&& f, ScalarOf<S> t, ScalarOf<S> h, S&& state,
                  Workspace<ScalarOf<S>>& ws) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    auto y = detail::view(state);
    const Eigen::Index n = y.size();
    auto k1 = ws.template slot<N>(0, n);
    auto k2 = ws.template slot<N>(1, n);
    auto predictor = ws.template slot<N>(2, n);
    f(t, ConstView<Scalar, N>(y.data(), n), k1);
    predictor = y + h * k1;
    f(t + h, ConstView<Scalar, N>(predictor.data(), n), k2);
    y += (h / Scalar(2)) * (k1 + k2);
  }
};

/// Classic fourth-order Runge-Kutta, order 4: y_{n+1} = y_n + (h/6)(k1 + 2 k2 + 2 k3 + k4),
/// with k1 = f(t, y), k2 = f(t + h/2, y + h/2 k1), k3 = f(t + h/2, y + h/2 k2),
/// k4 = f(t + h, y + h k3). Four evaluations; three buffers (the sum is accumulated).
struct Rk4Stepper {
  static constexpr int order = 4;

  template <class F, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>>
  void operator()(F&& f, ScalarOf<S> t, ScalarOf<S> h, S&& state,
                  Workspace<ScalarOf<S>>& ws) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    auto y = detail::view(state);
    const Eigen::Index n = y.size();
    auto k = ws.template slot<N>(0, n);
    auto sum = ws.template slot<N>(1, n);
    auto stage = ws.template slot<N>(2, n);
    const ConstView<Scalar, N> stageIn(stage.data(), n);
    const Scalar half = h / Scalar(2);

    f(t, ConstView<Scalar, N>(y.data(), n), k);  // k1
    sum = k;
    stage = y + half * k;
    f(t + half, stageIn, k);  // k2
    sum += Scalar(2) * k;
    stage = y + half * k;
    f(t + half, stageIn, k);  // k3
    sum += Scalar(2) * k;
    stage = y + h * k;
    f(t + h, stageIn, k);  // k4
    sum += k;
    y += (h / Scalar(6)) * sum;
  }
};

inline constexpr ExplicitEulerStepper explicitEuler{};
inline constexpr MidpointStepper midpoint{};
inline constexpr HeunStepper heun{};
inline constexpr Rk4Stepper rk4{};

}  // namespace inertia::ode
