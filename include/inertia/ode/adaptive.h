// Adaptive step-size control: options, statistics, the error norm, the step-size update and the
// integration loop shared by the controllers, and the step-doubling controller (seed 002
// "Adaptive Step Sizes", seed 003 "Adaptive Euler method") over any fixed-order stepper.
// The embedded Dormand-Prince 5(4) controller is in dormand_prince.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "inertia/ode/explicit.h"
#include "inertia/ode/state.h"
#include "inertia/ode/workspace.h"

namespace inertia::ode {

/// Settings of an adaptive integration. A step is accepted when, for every component i,
/// |err_i| <= absoluteTolerance + relativeTolerance * max(|y_i|, |y_new_i|) (a max norm, so
/// each component meets its own tolerance; this is a bound on the local error per step).
template <class Scalar>
struct AdaptiveOptions {
  Scalar absoluteTolerance = Scalar(1e-6);  ///< >= 0; 0 gives pure relative control.
  Scalar relativeTolerance = Scalar(1e-6);  ///< >= 0; at least one tolerance > 0.
  /// First step size tried by integrate(); 0 picks (t1 - t0) / 100 (the controller corrects
  /// a poor guess within a few rejected steps).
  Scalar initialStep = Scalar(0);
  /// Smallest step the controller may ask for before integrate() gives up (status
  /// StepTooSmall, or NonFinite if the last rejection was a non-finite result). The effective
  /// minimum is never below 16 epsilon |t|, where t + h stops advancing.
  Scalar minStep = Scalar(0);
  Scalar maxStep = std::numeric_limits<Scalar>::infinity();  ///< Largest step size used.
  /// h_new = h * clamp(safety * err^(-1/(p+1)), maxShrink, maxGrowth), err the normalised
  /// error estimate and p the order of the solution the estimate refers to.
  Scalar safety = Scalar(0.9);
  Scalar maxGrowth = Scalar(5);    ///< Largest factor a step may grow by (>= 1).
  Scalar maxShrink = Scalar(0.2);  ///< Smallest factor a step may shrink by (in (0, 1]).
  /// Cap on attempted steps (accepted + rejected) in integrate(): status TooManySteps.
  long maxSteps = 100000;
  /// Dormand-Prince only: reuse the last stage of an accepted step as the first of the next
  /// (first same as last), and k1 across retries of a rejected step. Safe even if the caller
  /// changes y in between: the saving is taken only if y is unchanged.
  bool fsal = true;
};

/// How an adaptive integration ended.
enum class AdaptiveStatus {
  Success,       ///< Reached t1.
  StepTooSmall,  ///< The error control asked for a step below the minimum step.
  TooManySteps,  ///< AdaptiveOptions::maxSteps attempts were made before t1.
  NonFinite,     ///< The derivative or trial state stayed non-finite down to the minimum step.
};

/// Statistics of an adaptive integration.
template <class Scalar>
struct AdaptiveStats {
  AdaptiveStatus status = AdaptiveStatus::Success;
  std::string message;   ///< Empty on success, else what went wrong, where and why.
  Scalar t = Scalar(0);  ///< Time reached: t1 on success, the last accepted time otherwise.
  long accepted = 0;     ///< Accepted steps.
  long rejected = 0;     ///< Rejected steps.
  long evaluations = 0;  ///< Calls of the derivative f.
  /// Smallest and largest accepted step (a final step shortened to land on t1 excluded from
  /// the minimum). +inf and 0 when no step was accepted.
  Scalar minStep = std::numeric_limits<Scalar>::infinity();
  Scalar maxStep = Scalar(0);
  Scalar nextStep = Scalar(0);  ///< The controller's proposal for a step after the last one.
  bool ok() const { return status == AdaptiveStatus::Success; }
};

/// The outcome of one attempted adaptive step (the step-by-step interface, tryStep).
template <class Scalar>
struct StepAttempt {
  bool accepted = false;        ///< If true, y now holds y(t + step).
  bool finite = true;           ///< False if the trial produced a non-finite value (then rejected).
  Scalar step = Scalar(0);      ///< The step size tried.
  Scalar error = Scalar(0);     ///< Normalised error estimate: accepted iff <= 1; +inf if !finite.
  Scalar nextStep = Scalar(0);  ///< Proposed size of the next attempt (retry or next step).
};

/// Final state and statistics of integrate().
template <class Scalar, int N = Eigen::Dynamic>
struct Solution {
  Vector<Scalar, N> y;
  AdaptiveStats<Scalar> stats;
};

namespace detail {

template <class Scalar>
void checkAdaptiveOptions(const AdaptiveOptions<Scalar>& o) {
  const auto finiteNonNegative = [](Scalar x) { return std::isfinite(x) && x >= Scalar(0); };
  if (!finiteNonNegative(o.absoluteTolerance) || !finiteNonNegative(o.relativeTolerance) ||
      !(o.absoluteTolerance > Scalar(0) || o.relativeTolerance > Scalar(0)))
    throw InvalidArgument(
        "ode: AdaptiveOptions tolerances must be finite and >= 0, and one of them > 0");
  if (!finiteNonNegative(o.initialStep))
    throw InvalidArgument("ode: AdaptiveOptions::initialStep must be finite and >= 0");
  if (!finiteNonNegative(o.minStep))
    throw InvalidArgument("ode: AdaptiveOptions::minStep must be finite and >= 0");
  if (!(o.maxStep > Scalar(0)) || !(o.maxStep >= o.minStep))
    throw InvalidArgument("ode: AdaptiveOptions::maxStep must be > 0 and >= minStep");
  if (!(o.safety > Scalar(0) && o.safety <= Scalar(1)))
    throw InvalidArgument("ode: AdaptiveOptions::safety must be in (0, 1]");
  if (!(o.maxGrowth >= Scalar(1) && std::isfinite(o.maxGrowth)))
    throw InvalidArgument("ode: AdaptiveOptions::maxGrowth must be finite and >= 1");
  if (!(o.maxShrink > Scalar(0) && o.maxShrink <= Scalar(1)))
    throw InvalidArgument("ode: AdaptiveOptions::maxShrink must be in (0, 1]");
  if (o.maxSteps <= 0) throw InvalidArgument("ode: AdaptiveOptions::maxSteps must be > 0");
}

/// max_i |e_i| / (atol + rtol max(|y_i|, |yNew_i|)); +inf if any value is not finite.
template <class Scalar, class E, class Y, class YNew>
Scalar errorNorm(const E& e, const Y& y, const YNew& yNew, const AdaptiveOptions<Scalar>& o) {
  Scalar norm = Scalar(0);
  for (Eigen::Index i = 0; i < e.size(); ++i) {
    const Scalar scale =
        o.absoluteTolerance + o.relativeTolerance * std::max(std::abs(y[i]), std::abs(yNew[i]));
    const Scalar ei = std::abs(e[i]);
    if (!std::isfinite(ei) || !std::isfinite(yNew[i]))
      return std::numeric_limits<Scalar>::infinity();
    // A zero scale (pure relative control at y = 0) accepts only an exact zero error.
    const Scalar ratio = scale > Scalar(0) ? ei / scale
                         : ei == Scalar(0) ? Scalar(0)
                                           : std::numeric_limits<Scalar>::infinity();
    norm = std::max(norm, ratio);
  }
  return norm;
}

/// Fills the accept/reject decision and the next step: h * clamp(safety err^(-1/(p+1)), ...),
/// never growing after a rejection (Hairer, Norsett & Wanner, II.4).
template <class Scalar>
StepAttempt<Scalar> decide(Scalar h, Scalar error, int estimateOrder,
                           const AdaptiveOptions<Scalar>& o) {
  StepAttempt<Scalar> attempt;
  attempt.step = h;
  attempt.error = error;
  attempt.finite = std::isfinite(error);
  attempt.accepted = attempt.finite && error <= Scalar(1);
  Scalar factor = o.maxShrink;
  if (attempt.finite) {
    factor = error == Scalar(0)
                 ? o.maxGrowth
                 : o.safety * std::pow(error, Scalar(-1) / Scalar(estimateOrder + 1));
    factor = std::clamp(factor, o.maxShrink, o.maxGrowth);
  }
  if (!attempt.accepted) factor = std::min(factor, Scalar(1));
  attempt.nextStep = std::min(h * factor, o.maxStep);
  return attempt;
}

/// Counts the calls of a derivative for the statistics.
template <class F>
struct CountingDerivative {
  F& f;
  long& count;
  template <class... Args>
  void operator()(Args&&... args) const {
    ++count;
    f(std::forward<Args>(args)...);
  }
};

}  // namespace detail

/// The integration loop and the state-returning integrate(), shared by the adaptive
/// controllers. `Controller` provides `tryStep(f, t, y, h, options)` and `evaluations()`.
template <class Controller, class Scalar>
class AdaptiveIntegrator {
 public:
  /// Integrates y' = f(t, y) from (t0, y) to t1 in place: y holds y(t1) on success, the state
  /// at stats.t otherwise. Returns the statistics; never loops forever (maxSteps, minStep).
  /// Throws InvalidArgument for bad options, non-finite t0/t1 or y, or t1 < t0.
  template <class F, MutableState S>
  requires std::same_as<ScalarOf<S>, Scalar> && Derivative<F, Scalar, sizeOf<S>>
      AdaptiveStats<Scalar> integrateInPlace(F&& f, Scalar t0, S&& y, Scalar t1,
                                             const AdaptiveOptions<Scalar>& options = {}) {
    detail::checkAdaptiveOptions(options);
    if (!std::isfinite(t0) || !std::isfinite(t1) || t1 < t0)
      throw InvalidArgument("ode: integrate needs finite t0 <= t1 (got t0 = " + std::to_string(t0) +
                            ", t1 = " + std::to_string(t1) + ")");
    auto state = detail::view(y);
    if (!state.allFinite())
      throw InvalidArgument("ode: integrate: the initial state y0 is not finite");

    auto& self = static_cast<Controller&>(*this);
    const long evaluations0 = self.evaluations();
    const Scalar eps = std::numeric_limits<Scalar>::epsilon();
    AdaptiveStats<Scalar> stats;
    Scalar t = t0;
    Scalar h = options.initialStep > Scalar(0) ? options.initialStep : (t1 - t0) / Scalar(100);
    h = std::min(h, options.maxStep);
    bool lastRejectNonFinite = false;
    while (t < t1) {
      if (stats.accepted + stats.rejected >= options.maxSteps) {
        stats.status = AdaptiveStatus::TooManySteps;
        stats.message = "ode: the maximum number of steps (" + std::to_string(options.maxSteps) +
                        ") was reached at t = " + std::to_string(t) +
                        " before t1 = " + std::to_string(t1);
        break;
      }
      const Scalar floor =
          std::max(options.minStep, Scalar(16) * eps * std::max(std::abs(t), std::abs(t1)));
      if (!(h >= floor)) {
        stats.status =
            lastRejectNonFinite ? AdaptiveStatus::NonFinite : AdaptiveStatus::StepTooSmall;
        stats.message = (lastRejectNonFinite
                             ? "ode: the derivative or the trial state is not finite at t = "
                             : "ode: the error control needs a step below the minimum at t = ") +
                        std::to_string(t) + " (h = " + std::to_string(h) + " < minimum " +
                        std::to_string(floor) + ")";
        break;
      }
      // Land exactly on t1, stretching the step by at most 1% rather than leaving a sliver.
      const Scalar remaining = t1 - t;
      const bool last = h * Scalar(1.01) >= remaining;
      const Scalar hTry = last ? remaining : h;
      const StepAttempt<Scalar> attempt = self.tryStep(f, t, state, hTry, options);
      if (attempt.accepted) {
        t = last ? t1 : t + hTry;
        ++stats.accepted;
        if (!last || hTry >= h) stats.minStep = std::min(stats.minStep, hTry);
        stats.maxStep = std::max(stats.maxStep, hTry);
        lastRejectNonFinite = false;
      } else {
        ++stats.rejected;
        lastRejectNonFinite = !attempt.finite;
      }
      h = attempt.nextStep;
    }
    stats.t = t;
    stats.nextStep = h;
    stats.evaluations = self.evaluations() - evaluations0;
    return stats;
  }

  /// Integrates from (t0, y0) to t1 and returns the final state with the statistics: the
  /// seeds' "state in, state out" form. y0 is copied (an Eigen vector, span, std::vector...).
  template <class F, class S>
  requires StateTraits<std::remove_cvref_t<S>>::valid && std::same_as<ScalarOf<S>, Scalar> &&
      Derivative<F, Scalar, sizeOf<S>>
          Solution<Scalar, sizeOf<S>> integrate(F&& f, Scalar t0, const S& y0, Scalar t1,
                                                const AdaptiveOptions<Scalar>& options = {}) {
    Solution<Scalar, sizeOf<S>> solution;
    solution.y = ConstView<Scalar, sizeOf<S>>(y0.data(), static_cast<Eigen::Index>(y0.size()));
    solution.stats = integrateInPlace(f, t0, solution.y, t1, options);
    return solution;
  }
};

/// Step-doubling error control over a fixed-order stepper (seed 002 "Adaptive Step Sizes",
/// seed 003 "Adaptive Euler method"): one step of h gives x_a, two of h/2 give x_b, the error
/// is e = |x_a - x_b| and the next step h (tol/e)^(1/(p+1)), with p = Stepper::order, a safety
/// factor and growth/shrink limits (AdaptiveOptions). The more accurate x_b is kept; its own
/// local error is about e / (2^p - 1), so the test is conservative by that factor.
/// Three steps per attempt. `Stepper` is any object with `static constexpr int order` and
/// `operator()(f, t, h, y, Workspace&)`: explicitEuler, midpoint, heun, rk4, dormandPrince5,
/// or backward Euler with its Jacobian bound by withJacobian (implicit.h).
template <class Scalar, class Stepper = Rk4Stepper>
class StepDoubling : public AdaptiveIntegrator<StepDoubling<Scalar, Stepper>, Scalar> {
 public:
  static constexpr int order = Stepper::order;

  explicit StepDoubling(Stepper stepper = {}) : stepper_(stepper) {}

  /// Step-by-step interface: tries one step of size h from (t, y). If accepted, y holds
  /// y(t + h); if rejected, y is unchanged. Either way `nextStep` is the proposed next h.
  /// Throws InvalidArgument for h not finite or <= 0 or bad options.
  template <class F, MutableState S>
  requires std::same_as<ScalarOf<S>, Scalar> && Derivative<F, Scalar, sizeOf<S>> StepAttempt<Scalar>
  tryStep(F&& f, Scalar t, S&& y, Scalar h, const AdaptiveOptions<Scalar>& options = {}) {
    constexpr int N = sizeOf<S>;
    detail::checkStep(t, h);
    detail::checkAdaptiveOptions(options);
    auto state = detail::view(y);
    const Eigen::Index n = state.size();
    grow(n);
    View<Scalar, N> xa(xa_.data(), n);
    View<Scalar, N> xb(xb_.data(), n);
    detail::CountingDerivative<std::remove_reference_t<F>> counted{f, evaluations_};
    const Scalar half = h / Scalar(2);
    xa = state;
    stepper_(counted, t, h, xa, ws_);
    xb = state;
    stepper_(counted, t, half, xb, ws_);
    stepper_(counted, t + half, half, xb, ws_);
    const Scalar error = detail::errorNorm(xa - xb, state, xb, options);
    const StepAttempt<Scalar> attempt = detail::decide(h, error, order, options);
    if (attempt.accepted) state = xb;
    return attempt;
  }

  /// Calls of f since construction.
  long evaluations() const { return evaluations_; }

 private:
  void grow(Eigen::Index n) {
    if (xa_.size() < n) {
      xa_.resize(n);
      xb_.resize(n);
    }
  }

  Stepper stepper_;
  Workspace<Scalar> ws_;
  Vector<Scalar> xa_, xb_;
  long evaluations_ = 0;
};

}  // namespace inertia::ode
