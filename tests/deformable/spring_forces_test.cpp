// Spring forces against their definition's consequences (Newton's third law, momentum), and
// the analytic Jacobians against central finite differences.
#include "deformable/spring_forces.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"
#include "inertia/ode/method.h"
#include "../draws.h"

namespace inertia {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Central differences of F_a with respect to x_a (or v_a), column by column. In double with
// step 1e-6 m the truncation error is O(k delta^2 / l^2) ~ 1e-10 k and rounding
// O(eps |F| / delta) ~ 1e-10 |F|: far below the 1e-6 relative tolerance used.
Matrix3d finiteDifference(const Spring& s, Vector3d xa, const Vector3d& xb, Vector3d va,
                          const Vector3d& vb, bool wrtVelocity) {
  Matrix3d j;
  const double delta = 1e-6;
  for (int c = 0; c < 3; ++c) {
    Vector3d& p = wrtVelocity ? va : xa;
    const double keep = p[c];
    p[c] = keep + delta;
    const Vector3d plus = detail::springForce<double>(s, xa, xb, va, vb);
    p[c] = keep - delta;
    const Vector3d minus = detail::springForce<double>(s, xa, xb, va, vb);
    p[c] = keep;
    j.col(c) = (plus - minus) / (2 * delta);
  }
  return j;
}

TEST(SpringJacobian, StretchedSpringMatchesFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Spring s{0, 1, Real(0.5), Real(300 + 100 * trial), Real(2), SpringKind::Stretch};
    const Vector3d xb = inertia::test::draw3<Vector3d>([&] { return u(rng); });
    const Vector3d dir = inertia::test::draw3<Vector3d>([&] { return u(rng); }).normalized();
    const Vector3d xa = xb + dir * (0.5 * (1.05 + 0.5 * (u(rng) + 1)));  // stretched: l > L
    // The damping force depends on x through u; B-W leave that term out, so compare dF/dx at
    // zero relative velocity, where it vanishes.
    const Vector3d v = inertia::test::draw3<Vector3d>([&] { return u(rng); });
    const detail::SpringJacobian j = detail::springJacobian(s, xa, xb);
    const Matrix3d fx = finiteDifference(s, xa, xb, v, v, false);
    const Matrix3d fv = finiteDifference(s, xa, xb, v, v, true);
    EXPECT_LE((j.dx - fx).norm(), 1e-6 * fx.norm()) << "trial " << trial;
    EXPECT_LE((j.dv - fv).norm(), 1e-6 * fv.norm()) << "trial " << trial;
    EXPECT_TRUE(j.dx.isApprox(j.dx.transpose())) << "symmetric";
  }
}

TEST(SpringJacobian, CompressedSpringKeepsTheAxialTermAndDropsTheIndefiniteOne) {
  const Spring s{0, 1, Real(1), Real(1000), Real(0), SpringKind::Stretch};
  const Vector3d xb(0, 0, 0), xa(0.6, 0.3, 0.2);  // l ~ 0.70 < L
  const Vector3d u = xa.normalized();
  const detail::SpringJacobian j = detail::springJacobian(s, xa, xb);
  const Matrix3d fx = finiteDifference(s, xa, xb, Vector3d::Zero(), Vector3d::Zero(), false);
  // Along the spring the exact derivative is -k; across it the exact one is -k (1 - L/l) > 0
  // (destabilising), which the clamp replaces by 0.
  EXPECT_NEAR(u.dot(j.dx * u), u.dot(fx * u), 1e-6 * 1000);
  EXPECT_NEAR(u.dot(j.dx * u), -1000, 1e-9);
  const Vector3d t = u.cross(Vector3d::UnitZ()).normalized();
  EXPECT_NEAR(t.dot(j.dx * t), 0, 1e-9);
  EXPECT_GT(t.dot(fx * t), 0);
  Eigen::SelfAdjointEigenSolver<Matrix3d> eig(j.dx);
  EXPECT_LE(eig.eigenvalues().maxCoeff(), 1e-9) << "negative semi-definite";
}

// Internal forces come in opposite pairs, so with springs alone the total momentum of a free
// body is conserved by every integrator: exactly by the explicit ones (forces sum to zero up
// to rounding), and by the implicit one up to its solve's residual (the spring blocks of A
// cancel in the sum over vertices, so sum m dv = sum of b minus the residual's sum).
TEST(DeformableMomentum, SpringsAloneConserveMomentum) {
  for (ode::Method method :
       {ode::Method::SymplecticEuler, ode::Method::Rk4, ode::Method::BackwardEuler}) {
    // omega_max ~ sqrt(12 k / m) ~ 110/s: h = 1/600 s keeps the explicit methods stable.
    MassSpringModel m = softSphere({.radius = 0.5f,
                                    .subdivisions = 1,
                                    .mass = 2,
                                    .stiffness = {.stretch = 50, .shear = 0, .bend = 5},
                                    .damping = 0.05f});
    std::mt19937 rng(3);
    std::uniform_real_distribution<Real> u(-1, 1);
    m.velocities.resize(m.vertexCount());
    for (Vec3& v : m.velocities) v = inertia::test::draw3<Vec3>([&] { return u(rng); });
    Deformable d({.integrator = method, .solverTolerance = 1e-12}, m);
    auto momentum = [&] {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      double scale = 0;
      for (std::size_t i = 0; i < d.vertexCount(); ++i) {
        p += double(d.masses()[i]) * d.velocity(i).cast<double>();
        scale += double(d.masses()[i]) * d.velocity(i).cast<double>().norm();
      }
      return std::pair{p, scale};
    };
    const auto [p0, scale] = momentum();
    const int steps = 60;
    for (int s = 0; s < steps; ++s) d.step(Real(1) / 600);
    // Velocities are stored in Real: each step rounds every velocity by eps relative, a
    // random walk bounded by steps * eps * sum m |v|. Backward Euler's linear solve stops at a
    // relative residual of solverTolerance, and its residual's sum is a momentum error (the
    // springs' Jacobians sum to zero over the vertices, so only the residual breaks the
    // balance): at most solverTolerance of the step's change, below sum m |v| here, per step.
    // That term is what double precision sees (2e-13 against rounding's 1e-13).
    const double eps = std::numeric_limits<Real>::epsilon();
    const double solve = method == ode::Method::BackwardEuler ? 1e-12 : 0;
    EXPECT_LE((momentum().first - p0).norm(), (4 * eps + solve) * steps * scale)
        << ode::methodName(method);
  }
}

}  // namespace
}  // namespace inertia
