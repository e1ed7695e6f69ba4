// The harmonic oscillator x'' = -w^2 x (w = 2 pi: a period of 1 s; x(0) = 1, v(0) = 0) under
// every integrator of the ode layer, h = 0.02 s for 10 s, in double. The energy
// E = (v^2 + w^2 x^2) / 2 shows each method's character at a glance:
//
//     integrator_energy [OUT.csv]    # time,method,energy; plot: scripts/plot_integrators.py
//
// and is checked against what each method promises. In the coordinates (w x, v) a step of a
// Runge-Kutta method multiplies the state by R(i w h) times a rotation, so the energy is
// multiplied by |R(i w h)|^2 exactly, z = w h:
//   explicit Euler 1 + z^2; midpoint and Heun 1 + z^4 / 4; RK4 1 - z^6 / 72 + z^8 / 576;
//   backward Euler 1 / (1 + z^2).
// Symplectic Euler and the Verlet pair conserve a modified energy: E stays within a band of
// relative width about z (symplectic Euler, first order) or z^2 (Verlet, second order) for ever.
// The exit code is 0 when every check holds.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <Eigen/Core>

#include <inertia/ode/ode.h>

namespace ode = inertia::ode;

int main(int argc, char** argv) {
  constexpr double w = 2 * std::numbers::pi, h = 0.02, duration = 10;
  const int steps = int(std::lround(duration / h));
  const double z = w * h, e0 = w * w / 2;
  // The acceleration and its Jacobians (as products with a direction), which backward Euler's
  // Newton step needs.
  auto accel = [](double, const auto& x, const auto&, auto a) { a = -(w * w) * x; };
  auto dadx = [](double, const auto&, const auto&, const auto& dir, auto out) {
    out = -(w * w) * dir;
  };
  const ode::SecondOrderSystem spring{accel, dadx, ode::ZeroJacobian{}};
  std::FILE* out = argc > 1 ? std::fopen(argv[1], "w") : nullptr;
  if (argc > 1 && !out) {
    std::fprintf(stderr, "integrator_energy: cannot write %s\n", argv[1]);
    return 2;
  }
  if (out) std::fprintf(out, "time,method,energy\n");
  bool ok = true;
  for (ode::Method m : ode::kMethods) {
    const std::string name(ode::methodName(m));
    Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 1), v = Eigen::VectorXd::Zero(1);
    ode::Workspace<double> ws;
    double lowest = e0, highest = e0, energy = e0;
    if (out) std::fprintf(out, "0,%s,%.17g\n", name.c_str(), e0);
    for (int k = 1; k <= steps; ++k) {
      ode::step(m, spring, (k - 1) * h, h, x, v, ws);
      energy = (v[0] * v[0] + w * w * x[0] * x[0]) / 2;
      lowest = std::min(lowest, energy);
      highest = std::max(highest, energy);
      if (out) std::fprintf(out, "%.17g,%s,%.17g\n", k * h, name.c_str(), energy);
    }
    // The closed-form energy factor per step, where the method has one.
    double factor = 0;
    switch (m) {
      case ode::Method::ExplicitEuler: factor = 1 + z * z; break;
      case ode::Method::Midpoint:
      case ode::Method::Heun: factor = 1 + std::pow(z, 4) / 4; break;
      case ode::Method::Rk4: factor = 1 - std::pow(z, 6) / 72 + std::pow(z, 8) / 576; break;
      case ode::Method::BackwardEuler: factor = 1 / (1 + z * z); break;
      default: break;
    }
    bool pass = true;
    std::string claim;
    if (factor > 0) {
      // Rounding: a few ulps per step, over `steps` steps.
      const double expected = e0 * std::pow(factor, steps);
      pass = std::abs(energy - expected) <= 1e-9 * expected;
      claim = "E(10 s) / E0 = " + std::to_string(energy / e0) + ", closed form " +
              std::to_string(expected / e0);
    } else {
      // Symplectic: bounded for ever. Symplectic Euler conserves w^2 x^2 + v^2 - h w^2 x v
      // exactly, which puts E / E0 in [1 / (1 + z / 2), 1 / (1 - z / 2)] (a band of width
      // z / (1 - z^2 / 4), first order); the Verlet pair stays within a band of width z^2.
      double lo = 1 - z * z, hi = 1 + z * z;
      if (m == ode::Method::SymplecticEuler) lo = 1 / (1 + z / 2), hi = 1 / (1 - z / 2);
      pass = lowest >= (lo - 1e-9) * e0 && highest <= (hi + 1e-9) * e0 &&
             highest - lowest <= (hi - lo) * e0;
      claim = "E in [" + std::to_string(lowest / e0) + ", " + std::to_string(highest / e0) +
              "] E0, bound [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    }
    std::printf("%-16s %s: %s\n", name.c_str(), pass ? "ok  " : "FAIL", claim.c_str());
    ok = ok && pass;
  }
  if (out) std::fclose(out);
  return ok ? 0 : 1;
}
