// Dormand-Prince 5(4) (Dormand & Prince 1980; Hairer, Norsett & Wanner, "Solving ODEs I",
// table II.5.2): a fixed-step fifth-order stepper, and the embedded-pair adaptive controller
// that propagates the fifth-order solution and estimates its error by the fourth-order one.
#pragma once

#include <array>
#include <utility>

#include "inertia/ode/adaptive.h"
#include "inertia/ode/state.h"
#include "inertia/ode/workspace.h"

namespace inertia::ode {
namespace detail {

/// Butcher tableau of DOPRI5. b (fifth order) equals the last row of a (first same as last);
/// e = b - b* with b* the embedded fourth-order weights.
template <class Scalar>
struct DormandPrinceTableau {
  static constexpr Scalar c2 = Scalar(1.0 / 5), c3 = Scalar(3.0 / 10), c4 = Scalar(4.0 / 5),
                          c5 = Scalar(8.0 / 9);
  static constexpr Scalar a21 = Scalar(1.0 / 5);
  static constexpr Scalar a31 = Scalar(3.0 / 40), a32 = Scalar(9.0 / 40);
  static constexpr Scalar a41 = Scalar(44.0 / 45), a42 = Scalar(-56.0 / 15), a43 = Scalar(32.0 / 9);
  static constexpr Scalar a51 = Scalar(19372.0 / 6561), a52 = Scalar(-25360.0 / 2187),
                          a53 = Scalar(64448.0 / 6561), a54 = Scalar(-212.0 / 729);
  static constexpr Scalar a61 = Scalar(9017.0 / 3168), a62 = Scalar(-355.0 / 33),
                          a63 = Scalar(46732.0 / 5247), a64 = Scalar(49.0 / 176),
                          a65 = Scalar(-5103.0 / 18656);
  static constexpr Scalar b1 = Scalar(35.0 / 384), b3 = Scalar(500.0 / 1113),
                          b4 = Scalar(125.0 / 192), b5 = Scalar(-2187.0 / 6784),
                          b6 = Scalar(11.0 / 84);
  static constexpr Scalar e1 = Scalar(71.0 / 57600), e3 = Scalar(-71.0 / 16695),
                          e4 = Scalar(71.0 / 1920), e5 = Scalar(-17253.0 / 339200),
                          e6 = Scalar(22.0 / 525), e7 = Scalar(-1.0 / 40);
};

/// Stages k2..k6 from k[0] = f(t, y), then yNew = y + h sum b_i k_i. Uses k[1..5] and `stage`.
template <class Scalar, int N, class F, class K>
void dormandPrinceStages(F& f, Scalar t, Scalar h, const View<Scalar, N>& y, K& k,
                         View<Scalar, N>& stage, View<Scalar, N>& yNew) {
  using T = DormandPrinceTableau<Scalar>;
  const Eigen::Index n = y.size();
  const ConstView<Scalar, N> s(stage.data(), n);
  stage = y + h * (T::a21 * k[0]);
  f(t + T::c2 * h, s, k[1]);
  stage = y + h * (T::a31 * k[0] + T::a32 * k[1]);
  f(t + T::c3 * h, s, k[2]);
  stage = y + h * (T::a41 * k[0] + T::a42 * k[1] + T::a43 * k[2]);
  f(t + T::c4 * h, s, k[3]);
  stage = y + h * (T::a51 * k[0] + T::a52 * k[1] + T::a53 * k[2] + T::a54 * k[3]);
  f(t + T::c5 * h, s, k[4]);
  stage = y + h * (T::a61 * k[0] + T::a62 * k[1] + T::a63 * k[2] + T::a64 * k[3] + T::a65 * k[4]);
  f(t + h, s, k[5]);
  yNew = y + h * (T::b1 * k[0] + T::b3 * k[2] + T::b4 * k[3] + T::b5 * k[4] + T::b6 * k[5]);
}

}  // namespace detail

/// Dormand-Prince's fifth-order solution at a fixed step, order 5. Six evaluations (the
/// seventh stage only serves the error estimate and is skipped). Seven workspace buffers.
struct DormandPrince5Stepper {
  static constexpr int order = 5;

  template <class F, MutableState S>
  requires Derivative<F, ScalarOf<S>, sizeOf<S>>
  void operator()(F&& f, ScalarOf<S> t, ScalarOf<S> h, S&& state,
                  Workspace<ScalarOf<S>>& ws) const {
    using Scalar = ScalarOf<S>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    auto y = detail::view(state);
    const Eigen::Index n = y.size();
    std::array<View<Scalar, N>, 6> k = {ws.template slot<N>(0, n), ws.template slot<N>(1, n),
                                        ws.template slot<N>(2, n), ws.template slot<N>(3, n),
                                        ws.template slot<N>(4, n), ws.template slot<N>(5, n)};
    auto stage = ws.template slot<N>(6, n);
    f(t, ConstView<Scalar, N>(y.data(), n), k[0]);
    // yNew may alias y: every stage has been computed from y before it is written.
    detail::dormandPrinceStages(f, t, h, y, k, stage, y);
  }
};

inline constexpr DormandPrince5Stepper dormandPrince5{};

/// Adaptive Dormand-Prince 5(4): each attempt computes the fifth-order solution y5 and the
/// error estimate y5 - y4 of the embedded fourth-order one; the step is accepted when that
/// estimate meets the tolerances (AdaptiveOptions) and y5 is kept (local extrapolation). Next
/// step h (1/err)^(1/5) with safety and limits, 5 = 4 + 1 for the fourth-order estimate.
/// Seven evaluations per attempt, six with FSAL (AdaptiveOptions::fsal): the last stage
/// f(t + h, y5) of an accepted step is the first of the next.
template <class Scalar>
class DormandPrince45 : public AdaptiveIntegrator<DormandPrince45<Scalar>, Scalar> {
 public:
  static constexpr int order = 5;

  DormandPrince45() = default;

  /// Step-by-step interface: tries one step of size h from (t, y). If accepted, y holds
  /// y(t + h); if rejected, y is unchanged. Either way `nextStep` is the proposed next h.
  /// Throws InvalidArgument for h not finite or <= 0 or bad options.
  template <class F, MutableState S>
  requires std::same_as<ScalarOf<S>, Scalar> && Derivative<F, Scalar, sizeOf<S>> StepAttempt<Scalar>
  tryStep(F&& f, Scalar t, S&& y, Scalar h, const AdaptiveOptions<Scalar>& options = {}) {
    using T = detail::DormandPrinceTableau<Scalar>;
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    detail::checkAdaptiveOptions(options);
    auto state = detail::view(y);
    const Eigen::Index n = state.size();
    grow(n);
    auto buffer = [n](Vector<Scalar>& b) { return View<Scalar, N>(b.data(), n); };
    std::array<View<Scalar, N>, 7> k = {buffer(k_[0]), buffer(k_[1]), buffer(k_[2]), buffer(k_[3]),
                                        buffer(k_[4]), buffer(k_[5]), buffer(k_[6])};
    auto stage = buffer(stage_);
    auto yNew = buffer(yNew_);
    auto cachedY = buffer(cachedY_);
    detail::CountingDerivative<std::remove_reference_t<F>> counted{f, evaluations_};

    // k1 = f(t, y), unless it is known for exactly this (t, y): the FSAL stage of the last
    // accepted step, or the k1 of a rejected attempt from the same point.
    const bool reuse =
        options.fsal && cacheValid_ && cachedSize_ == n && cachedT_ == t && cachedY == state;
    if (!reuse) {
      counted(t, ConstView<Scalar, N>(state.data(), n), k[0]);
      cachedY = state;
      cachedT_ = t;
      cachedSize_ = n;
      cacheValid_ = true;
    }
    detail::dormandPrinceStages(counted, t, h, state, k, stage, yNew);
    counted(t + h, ConstView<Scalar, N>(yNew.data(), n), k[6]);
    // err = y5 - y4 = h sum e_i k_i (in `stage`, free again).
    stage = h * (T::e1 * k[0] + T::e3 * k[2] + T::e4 * k[3] + T::e5 * k[4] + T::e6 * k[5] +
                 T::e7 * k[6]);
    const Scalar error = detail::errorNorm(stage, state, yNew, options);
    const StepAttempt<Scalar> attempt = detail::decide(h, error, 4, options);
    if (attempt.accepted) {
      state = yNew;
      // First same as last: k7 = f(t + h, y_{n+1}) is k1 of the next step.
      k_[0].swap(k_[6]);
      cachedY_.swap(yNew_);
      cachedT_ = t + h;
      cacheValid_ = attempt.finite;
    }
    return attempt;
  }

  /// Calls of f since construction.
  long evaluations() const { return evaluations_; }

 private:
  void grow(Eigen::Index n) {
    if (stage_.size() >= n) return;
    for (auto& k : k_) k.resize(n);
    stage_.resize(n);
    yNew_.resize(n);
    cachedY_.resize(n);
    cacheValid_ = false;
  }

  std::array<Vector<Scalar>, 7> k_;
  Vector<Scalar> stage_, yNew_, cachedY_;
  Scalar cachedT_ = Scalar(0);
  Eigen::Index cachedSize_ = 0;
  bool cacheValid_ = false;
  long evaluations_ = 0;
};

}  // namespace inertia::ode
