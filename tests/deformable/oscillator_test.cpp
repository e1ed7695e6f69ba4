// A single spring-mass oscillator (vertex 0 pinned at the origin, vertex 1 of mass m on the x
// axis) against closed forms: every method's exact discrete solution of the linear recurrence
// it reduces to, the continuous frequency sqrt(k/m) and damping, and the measured order of
// convergence of the explicit methods.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "inertia/deformable/deformable.h"

namespace inertia {
namespace {

using Eigen::Matrix2d;
using Eigen::Vector2d;

struct Oscillator {
  double rest = 0.1;        // L (m)
  double amplitude = 0.05;  // initial stretch (m), released from rest
  double mass = 0.5;        // kg
  double stiffness =
      2 * std::numbers::pi * 2 * std::numbers::pi * 0.5;  // k: omega = 2 pi (T = 1 s)
  double damping = 0;                                     // c (N s/m)

  double omega() const { return std::sqrt(stiffness / mass); }
  double gamma() const { return damping / mass; }

  Deformable make(ode::Method method) const {
    MassSpringModel m;
    m.positions = {Vec3::Zero(), Vec3(Real(rest + amplitude), 0, 0)};
    m.masses = {Real(mass), Real(mass)};
    m.springs = {{0, 1, Real(rest), Real(stiffness), Real(damping), SpringKind::Stretch}};
    m.pinned = {0};
    return Deformable({.integrator = method, .solverTolerance = 1e-12}, m);
  }
};

// The stretch xi = x - L of vertex 1 after each of `steps` steps of h.
std::vector<Vector2d> simulate(const Oscillator& o, ode::Method method, double h, int steps) {
  Deformable d = o.make(method);
  std::vector<Vector2d> out;
  for (int s = 0; s < steps; ++s) {
    d.step(Real(h));
    out.push_back({double(d.position(1).x()) - o.rest, double(d.velocity(1).x())});
  }
  return out;
}

// The one-step map G of each method on z = (xi, v), z' = J z, J = [[0, 1], [-w^2, -gamma]]:
// Taylor polynomials for the explicit Runge-Kutta methods, the kick-drift matrix for
// symplectic Euler, (I - h J)^-1 for backward Euler (Baraff-Witkin's step is exact backward
// Euler on a linear system: the linearisation is exact).
Matrix2d stepMatrix(ode::Method method, const Oscillator& o, double h) {
  Matrix2d j;
  j << 0, 1, -o.omega() * o.omega(), -o.gamma();
  const Matrix2d hj = h * j, i = Matrix2d::Identity();
  switch (method) {
    case ode::Method::ExplicitEuler:
      return i + hj;
    case ode::Method::Midpoint:
    case ode::Method::Heun:
      return i + hj + hj * hj / 2;
    case ode::Method::Rk4:
      return i + hj + hj * hj / 2 + hj * hj * hj / 6 + hj * hj * hj * hj / 24;
    case ode::Method::SymplecticEuler: {
      Matrix2d kick = i, drift = i;  // v += h a(x, v), then x += h v
      kick.row(1) += hj.row(1);
      drift(0, 1) = h;
      return drift * kick;
    }
    case ode::Method::BackwardEuler:
      return (i - hj).inverse();
    default:
      return Matrix2d::Constant(std::nan(""));
  }
}

constexpr ode::Method kClosedFormMethods[] = {
    ode::Method::ExplicitEuler, ode::Method::Midpoint,        ode::Method::Heun,
    ode::Method::Rk4,           ode::Method::SymplecticEuler, ode::Method::BackwardEuler};

// Each method follows its own exact discrete solution G^n z0, damped or not, for 100 steps
// (explicit Euler's amplitude grows by 2.2 meanwhile, staying below L: the spring never
// inverts). Float rounding of l - L costs eps L per force evaluation, relative
// eps L / A = 2.4e-7 of the amplitude, summed over 4 evaluations and 100 steps: 1e-4; 3e-4
// leaves room for the rounding of the state itself.
TEST(DeformableOscillator, EveryMethodFollowsItsClosedFormRecurrence) {
  for (double damping : {0.0, 0.4}) {
    Oscillator o;
    o.rest = 0.2;
    o.damping = damping;
    const double h = 0.02;
    for (ode::Method method : kClosedFormMethods) {
      const auto run = simulate(o, method, h, 100);
      const Matrix2d g = stepMatrix(method, o, h);
      Vector2d z(o.amplitude, 0);
      for (std::size_t s = 0; s < run.size(); ++s) {
        z = g * z;
        ASSERT_NEAR(run[s][0], z[0], 3e-4 * o.amplitude)
            << ode::methodName(method) << " damping " << damping << " step " << s;
        ASSERT_NEAR(run[s][1], z[1], 3e-4 * o.amplitude * o.omega())
            << ode::methodName(method) << " damping " << damping << " step " << s;
      }
    }
  }
}

// The period measured between upward zero crossings (interpolated linearly) against 2 pi /
// sqrt(k/m). At h = 1/400 s (omega h = 0.016) each method's phase error per period is below
// (omega h)^2 / 3 = 8e-5 (backward Euler's, the largest: atan(omega h) = omega h (1 - (omega h)^2 /
// 3)); the linear interpolation of a crossing errs by O(h^2 omega^2 / 8) of a step. Well inside
// 0.5%.
TEST(DeformableOscillator, PeriodIsTwoPiOverSqrtKOverM) {
  Oscillator o;
  const double h = 1.0 / 400, period = 2 * std::numbers::pi / o.omega();
  for (ode::Method method : {ode::Method::SymplecticEuler, ode::Method::Rk4,
                             ode::Method::BackwardEuler, ode::Method::VelocityVerlet}) {
    const auto run = simulate(o, method, h, 1200);
    std::vector<double> crossings;
    for (std::size_t s = 1; s < run.size(); ++s)
      if (run[s - 1][0] < 0 && run[s][0] >= 0)
        crossings.push_back(h * (double(s) + run[s - 1][0] / (run[s - 1][0] - run[s][0])));
    ASSERT_GE(crossings.size(), 2u) << ode::methodName(method);
    const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
    EXPECT_NEAR(measured / period, 1, 0.005) << ode::methodName(method);
  }
}

// Damped: the amplitude of the continuous solution falls as exp(-zeta omega t); RK4 at
// omega h = 0.06 follows the continuous solution to O((omega h)^4) ~ 1e-5 per period.
TEST(DeformableOscillator, DampedDecayMatchesTheContinuousClosedForm) {
  Oscillator o;
  o.damping = 0.6;  // zeta = c / (2 sqrt(k m)) = 0.095
  const double h = 0.01, w = o.omega(), zeta = o.damping / (2 * std::sqrt(o.stiffness * o.mass));
  const double wd = w * std::sqrt(1 - zeta * zeta);
  const auto run = simulate(o, ode::Method::Rk4, h, 300);
  for (std::size_t s = 0; s < run.size(); ++s) {
    const double t = h * double(s + 1);
    const double exact = o.amplitude * std::exp(-zeta * w * t) *
                         (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
    ASSERT_NEAR(run[s][0], exact, 2e-4 * o.amplitude) << "t = " << t;
  }
}

// Backward Euler's numerical damping: on the undamped oscillator every step multiplies the
// energy (w^2 xi^2 + v^2) / 2 by exactly 1 / (1 + (w h)^2), stiff or not. Here w h = 6 at
// 1/60 s (k = 1e5 N/m, m = 0.77 kg). Tolerance: the solve's residual (1e-12) and float
// rounding of the state: x = L + xi is stored to ulp(L) = eps L, so xi^2 to 2 eps L / |xi|
// relative (the velocity to eps), before and after the step.
TEST(DeformableOscillator, BackwardEulerDampsEnergyByOnePlusOmegaHSquaredPerStep) {
  Oscillator o;
  o.stiffness = 1e5;
  o.mass = o.stiffness / (360.0 * 360.0);
  o.rest = 0.05;
  o.amplitude = 0.04;
  const double h = 1.0 / 60, wh = o.omega() * h;
  Deformable d = o.make(ode::Method::BackwardEuler);
  auto energy = [&] {
    const double xi = double(d.position(1).x()) - o.rest, v = double(d.velocity(1).x());
    return 0.5 * (o.omega() * o.omega() * xi * xi + v * v);
  };
  const double eps = std::numeric_limits<Real>::epsilon();
  for (int s = 0; s < 4; ++s) {
    const double before = energy();
    const double xiBefore = std::abs(double(d.position(1).x()) - o.rest);
    d.step(Real(h));
    const double xiAfter = std::abs(double(d.position(1).x()) - o.rest);
    const double tol = 4 * eps + 2 * eps * o.rest * (1 / xiBefore + 1 / xiAfter);
    EXPECT_NEAR(energy() / before * (1 + wh * wh), 1, tol) << "step " << s;
    EXPECT_LE(d.lastSolve().error, 1e-10);
  }
}

// The explicit methods' measured order: the error at t = 0.75 s (3/4 of a period: at whole and
// half periods symplectic Euler's first-order errors cancel and it looks second order)
// against the continuous solution
// for h, h/2, h/4 (order 1: h = 1/64 s, omega h <= 0.1; order 2: 1/16; order 4: 1/8), log2 of
// the ratio of the two finer steps' errors. There the leading error term dominates (the next
// is smaller by a factor ~ omega h <= 0.4, and explicit Euler's growth exp(w^2 h t / 2) - 1 is
// linear in h to 4%), so the estimate lies within 0.3 of the order; float rounding (eps L per
// evaluation, below 1e-8 m a step against errors >= 3e-6 m) does not reach it.
TEST(DeformableOscillator, ExplicitMethodsConvergeAtTheirOrder) {
  Oscillator o;
  const double w = o.omega();
  for (ode::Method method :
       {ode::Method::ExplicitEuler, ode::Method::SymplecticEuler, ode::Method::Midpoint,
        ode::Method::Heun, ode::Method::VelocityVerlet, ode::Method::Rk4}) {
    std::vector<double> errors;
    const int coarsest = ode::methodOrder(method) == 1   ? 64
                         : ode::methodOrder(method) == 2 ? 16
                                                         : 8;
    for (int n : {coarsest, 2 * coarsest, 4 * coarsest}) {
      const auto run = simulate(o, method, 1.0 / n, 3 * n / 4);
      errors.push_back(std::hypot(run.back()[0] - o.amplitude * std::cos(0.75 * w),
                                  (run.back()[1] + o.amplitude * w * std::sin(0.75 * w)) / w));
    }
    const double order = std::log2(errors[1] / errors[2]);
    EXPECT_NEAR(order, ode::methodOrder(method), 0.3)
        << ode::methodName(method) << " errors " << errors[0] << " " << errors[1] << " "
        << errors[2];
  }
}

// Stability limits: symplectic Euler is stable for omega h < 2 (|trace G| < 2) and grows beyond;
// explicit Euler multiplies the energy by 1 + (omega h)^2 every step, whatever h.
TEST(DeformableOscillator, ExplicitStabilityLimitsMatchTheory) {
  Oscillator o;
  o.rest = 1;  // the spring never inverts within the bounded swing
  for (double wh : {1.9, 2.1}) {
    const double h = wh / o.omega();
    const auto run = simulate(o, ode::Method::SymplecticEuler, h, 200);
    double peak = 0;
    for (const Vector2d& z : run) peak = std::max(peak, std::abs(z[0]));
    // Bounded: the invariant ellipse of G (at w h = 1.9 it stretches xi by at most
    // 1 / sqrt(1 - (w h / 2)^2) = 3.2); unbounded: the larger eigenvalue of G,
    // |lambda| = 1.55 at w h = 2.1, grows any start by 1.55^200.
    if (wh < 2)
      EXPECT_LT(peak, 3.3 * o.amplitude);
    else
      EXPECT_GT(peak, 1e6 * o.amplitude);
  }
  const double h = 0.05, wh = o.omega() * h;
  const auto run = simulate(o, ode::Method::ExplicitEuler, h, 20);
  double before = o.omega() * o.omega() * o.amplitude * o.amplitude;
  for (const Vector2d& z : run) {
    const double e = o.omega() * o.omega() * z[0] * z[0] + z[1] * z[1];
    EXPECT_NEAR(e / before, 1 + wh * wh, 1e-4);
    before = e;
  }
}

// The undo of an explicit step that overflows (integration.cpp): springs so stiff for so light a
// vertex that the first step's acceleration k xi / m (12.5 times the largest Real) overflows
// in every explicit method. The step is undone: positions and velocities are the step's start,
// bit for bit, and lastSolve() says so. The same oscillator at the stiffness of the tests above
// takes its step and reports it converged: the report tells the two apart.
TEST(DeformableOscillator, AnExplicitStepThatOverflowsIsUndoneAndReported) {
  Oscillator o;
  o.mass = 1e-3;
  o.stiffness = double(std::numeric_limits<Real>::max()) / 4;
  const Real h = Real(1.0 / 60.0);
  for (ode::Method method : ode::kMethods) {
    if (method == ode::Method::BackwardEuler) continue;
    Deformable d = o.make(method);
    const std::vector<Real> start(d.positions().begin(), d.positions().end());
    d.step(h);
    EXPECT_FALSE(d.lastSolve().converged) << ode::methodName(method);
    EXPECT_EQ(std::vector<Real>(d.positions().begin(), d.positions().end()), start)
        << ode::methodName(method);
    for (Real c : d.velocities()) EXPECT_EQ(c, 0) << ode::methodName(method);
  }
  Deformable tame = Oscillator{}.make(ode::Method::SymplecticEuler);
  const Real before = tame.position(1).x();
  tame.step(h);
  EXPECT_TRUE(tame.lastSolve().converged);
  EXPECT_LT(tame.position(1).x(), before);  // pulled back towards its rest length
}

}  // namespace
}  // namespace inertia
