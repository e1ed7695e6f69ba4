// The implicit step: the modified PCG against the linear system built independently (dense,
// from finite differences of the forces), backward Euler's residual, pinned vertices that stay.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>

#include "deformable/implicit_euler.h"
#include "deformable/spring_forces.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"
#include "../draws.h"

namespace inertia {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// The total spring force on every vertex, in double.
VectorXd forces(const MassSpringModel& m, const std::vector<std::uint8_t>& broken,
                const VectorXd& x, const VectorXd& v) {
  VectorXd f = VectorXd::Zero(x.size());
  detail::addSpringForces<double>(m.springs, broken, x.data(), v.data(), f.data());
  return f;
}

// dF/dx by central differences of the whole force vector (step 1e-7 m; truncation O(delta^2),
// rounding O(eps |F| / delta) ~ 1e-9 relative).
MatrixXd forceJacobian(const MassSpringModel& m, const std::vector<std::uint8_t>& broken,
                       const VectorXd& x, const VectorXd& v) {
  MatrixXd k(x.size(), x.size());
  const double delta = 1e-7;
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    VectorXd plus = x, minus = x;
    plus[c] += delta, minus[c] -= delta;
    k.col(c) = (forces(m, broken, plus, v) - forces(m, broken, minus, v)) / (2 * delta);
  }
  return k;
}

struct ClothCase {
  MassSpringModel model;
  std::vector<std::uint8_t> broken, pinned;
  std::vector<Real> masses, acceleration, damping;
  VectorXd x, v;
};

// A 4 x 3 cloth stretched by 8% (every spring longer than its rest length, where the analytic
// Jacobian is exact), moving, undamped (so that dF/dv = 0 and F does not depend on v), under
// gravity, two corners pinned.
ClothCase stretchedCloth() {
  ClothCase s;
  s.model = cloth({.size = {1, 0.8f},
                   .resolution = {4, 3},
                   .mass = 0.4f,
                   .stiffness = {.stretch = 3000, .shear = 300, .bend = 20}});
  const std::size_t n = s.model.vertexCount();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  s.x.resize(3 * Eigen::Index(n));
  s.v.resize(3 * Eigen::Index(n));
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = s.model.positions[i].cast<double>() * 1.08;
    s.x.segment<3>(3 * Eigen::Index(i)) =
        Eigen::Vector3d(Real(p.x()), Real(p.y() + 0.001 * u(rng)), Real(p.z()));
    s.v.segment<3>(3 * Eigen::Index(i)) = inertia::test::draw3<Eigen::Vector3d>([&] { return Real(u(rng)); });
  }
  s.pinned.assign(n, 0);
  s.pinned[0] = s.pinned[4] = 1;
  for (std::size_t i : {0, 4}) s.v.segment<3>(3 * Eigen::Index(i)).setZero();
  s.broken.assign(s.model.springs.size(), 0);
  s.masses = s.model.masses;
  s.acceleration.assign(3 * n, 0);
  for (std::size_t i = 0; i < n; ++i) s.acceleration[3 * i + 1] = Real(-9.81);
  s.damping.assign(n, 0);
  return s;
}

// The modified PCG solves Baraff and Witkin's system A dv = b, built here densely from finite
// differences of the forces (A = M - h^2 dF/dx, SPD on the stretched cloth), on the free
// components, to its tolerance: it stops on the preconditioned residual
// r^T P^-1 r <= tol^2 b^T P^-1 b, which bounds |r| / |b| by tol sqrt(max P / min P).
TEST(ImplicitEuler, ModifiedPcgConvergesToItsTolerance) {
  ClothCase s = stretchedCloth();
  const std::size_t n = s.masses.size();
  const double h = 1.0 / 60, tol = 1e-8;
  const MatrixXd k = forceJacobian(s.model, s.broken, s.x, s.v);
  MatrixXd a = -h * h * k;
  VectorXd external(3 * Eigen::Index(n));
  for (std::size_t i = 0; i < 3 * n; ++i) {
    a(Eigen::Index(i), Eigen::Index(i)) += double(s.masses[i / 3]);
    external[Eigen::Index(i)] = double(s.masses[i / 3]) * double(s.acceleration[i]);
  }
  const VectorXd b = h * (forces(s.model, s.broken, s.x, s.v) + external + h * k * s.v);
  const auto filter = [&](VectorXd& w) {
    for (std::size_t i = 0; i < n; ++i)
      if (s.pinned[i]) w.segment<3>(3 * Eigen::Index(i)).setZero();
  };
  const auto apply = [&](const VectorXd& w, VectorXd& out) { out = a * w; };
  const VectorXd inverseDiagonal = a.diagonal().cwiseInverse();
  const auto jacobi = [&](const VectorXd& r, VectorXd& out) {
    out = inverseDiagonal.cwiseProduct(r);
  };
  VectorXd dv = VectorXd::Zero(b.size());
  detail::PcgBuffers buffers;
  const ode::LinearSolveReport report =
      detail::modifiedPcg(apply, filter, jacobi, b, dv, tol, 1000, buffers);
  EXPECT_TRUE(report.converged);
  EXPECT_GT(report.iterations, 3);
  VectorXd residual = a * dv - b, filteredB = b;
  filter(residual);
  filter(filteredB);
  const double bound = tol * std::sqrt(a.diagonal().maxCoeff() / a.diagonal().minCoeff());
  EXPECT_LE(residual.norm() / filteredB.norm(), bound);
  EXPECT_GT(residual.norm() / filteredB.norm(), 0);
  for (std::size_t i : {0, 4}) EXPECT_TRUE(dv.segment<3>(3 * Eigen::Index(i)).isZero(0));
}

// The implicit step solves backward Euler itself, M (v1 - v0) = h (F(x0 + h v1) + m g), not
// its linearisation: on the stretched cloth held all round (whose springs stay stretched, where
// the step's convex spring energy is the true one) the residual, computed here from the forces
// alone, is at most the Newton tolerance times its scale plus what rounding v1 to Real leaves, |H|
// eps |v1| with |H| <= max over rows of m + 2 sqrt(3) h^2 sum k (Gershgorin). Whichever way the
// Newton systems are solved (PCG, or the sparse LDL^T).
class StepSolvesBackwardEuler : public testing::TestWithParam<DeformableLinearSolver> {};

TEST_P(StepSolvesBackwardEuler, ToTheNewtonTolerance) {
  ClothCase s = stretchedCloth();
  // Pinned all round (the 6 inner vertices free), so that no spring can contract to its rest
  // length within the step.
  for (std::size_t i = 0; i < s.masses.size(); ++i) {
    const std::size_t column = i % 5, row = i / 5;
    if (column == 0 || column == 4 || row == 0 || row == 3) {
      s.pinned[i] = 1;
      s.v.segment<3>(3 * Eigen::Index(i)).setZero();
    }
  }
  const std::size_t n = s.masses.size();
  const double h = 1.0 / 60, tol = 1e-9;
  std::vector<Real> x(3 * n), v(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i)
    x[i] = Real(s.x[Eigen::Index(i)]), v[i] = Real(s.v[Eigen::Index(i)]);
  const VectorXd x0 = Eigen::Map<const VecX>(x.data(), Eigen::Index(3 * n)).cast<double>();
  const VectorXd v0 = Eigen::Map<const VecX>(v.data(), Eigen::Index(3 * n)).cast<double>();
  detail::ImplicitEuler solver;
  detail::ImplicitEulerInput in{s.model.springs, s.broken, s.masses, s.pinned, s.acceleration,
                                s.damping,       {},       {},       tol,      1000};
  in.linearSolver = GetParam();
  const ImplicitSolveReport report = solver.step(in, Real(h), x, v);
  EXPECT_TRUE(report.converged);
  EXPECT_GT(report.newtonIterations, 1);
  if (GetParam() == DeformableLinearSolver::Direct) {  // one factorisation a Newton step
    EXPECT_EQ(report.iterations, report.newtonIterations);
  }
  const VectorXd v1 = Eigen::Map<const VecX>(v.data(), Eigen::Index(3 * n)).cast<double>();
  const VectorXd x1 = x0 + h * v1;
  VectorXd residual = -h * forces(s.model, s.broken, x1, v1), scale(3 * Eigen::Index(n));
  // The solver's reference: |M v0 + h m g| plus its first gradient's norm, both filtered.
  VectorXd first = -h * forces(s.model, s.broken, x0 + h * v0, v0);
  std::vector<double> rowSum(n);
  for (std::size_t i = 0; i < n; ++i) rowSum[i] = double(s.masses[i]);
  for (const Spring& sp : s.model.springs)
    for (std::uint32_t e : {sp.a, sp.b}) rowSum[e] += 2 * std::sqrt(3.0) * h * h * sp.stiffness;
  for (std::size_t i = 0; i < 3 * n; ++i) {
    const Eigen::Index j = Eigen::Index(i);
    const double m = double(s.masses[i / 3]), ma = m * double(s.acceleration[i]);
    residual[j] += m * (v1[j] - v0[j]) - h * ma;
    scale[j] = m * v0[j] + h * ma;
    first[j] -= h * ma;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (s.pinned[i]) {
      for (VectorXd* w : {&residual, &scale, &first}) w->segment<3>(3 * Eigen::Index(i)).setZero();
      EXPECT_TRUE(v1.segment<3>(3 * Eigen::Index(i)).isZero(0));
    }
  const double start = scale.norm() + first.norm();
  const double eps = double(std::numeric_limits<Real>::epsilon());
  const double rounding = *std::max_element(rowSum.begin(), rowSum.end()) * eps * v1.norm();
  EXPECT_LE(residual.norm(), tol * start + rounding);
}

INSTANTIATE_TEST_SUITE_P(ImplicitEuler, StepSolvesBackwardEuler,
                         testing::Values(DeformableLinearSolver::ConjugateGradient,
                                         DeformableLinearSolver::Direct));

// A unit cloth of n x n cells, stiff (stretch 1e4 N/m) and lightly damped.
MassSpringModel stiffCloth(int n, Real mass) {
  return cloth({.size = {1, 1},
                .resolution = {n, n},
                .mass = mass,
                .stiffness = {.stretch = 1e4f, .shear = 1e3f, .bend = 10},
                .damping = 0.05f});
}

// Pinned vertices keep their positions to the bit, whatever pulls on them, and free ones move.
TEST(ImplicitEuler, PinnedVerticesDoNotMove) {
  const int n = 8;
  MassSpringModel m = stiffCloth(n, 0.3f);
  m.pinned = {0, std::uint32_t(n), std::uint32_t(n * (n + 1) / 2 + n / 2)};
  Deformable d({}, m);
  d.addField({GravityField{}});
  d.addField({WindField{Vec3(3, 0, 1), Real(0.02)}});
  std::vector<Vec3> start;
  for (std::uint32_t i : m.pinned) start.push_back(d.position(i));
  for (int s = 0; s < 90; ++s) {
    d.step(Real(1) / 60);
    ASSERT_TRUE(d.lastSolve().converged) << "step " << s;
    for (std::size_t k = 0; k < m.pinned.size(); ++k) {
      ASSERT_EQ(d.position(m.pinned[k]), start[k]);
      ASSERT_EQ(d.velocity(m.pinned[k]), Vec3::Zero());
    }
  }
  EXPECT_LT(d.position(std::size_t(n * (n + 1))).y(), -0.3f);
}

// A quadratic drag far stiffer than the step (vertices of 5 g in k = 20: k |v| / m = 4,000 |v|
// per second), which the implicit step takes explicitly: its rate is capped at 1 / h (FieldBatch::
// step). Uncapped, a vertex moved at 0.73 m/s after two steps, twice free fall's 0.33 (and
// scenes/flag.json with such a drag reached 1e23 m within 3 s). Oracle: a drag only
// removes energy, so no vertex ever moves faster than free fall from rest over the run allows
// (g t; 1% for the solve's tolerance, which the first step's free fall meets to 1e-5), and the
// cloth hangs below its pins.
TEST(ImplicitEuler, StiffQuadraticDragStaysBounded) {
  const int n = 8;
  MassSpringModel m = stiffCloth(n, 0.4f);
  m.pinned = {0, std::uint32_t(n)};
  Deformable d({}, m);
  d.addField({GravityField{}});
  d.addField({QuadraticDragField{Real(20)}});
  const Real h = Real(1) / 60, g = Real(9.81);
  for (int s = 0; s < 120; ++s) {
    d.step(h);
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      ASSERT_LE(d.velocity(i).norm(), Real(1.01) * g * h * Real(s + 1))
          << "step " << s << " vertex " << i;
  }
  EXPECT_LT(d.position(std::size_t(n * (n + 1))).y(), 0);
}

// The solve's passes on several threads (a pass over the vertices in place of the serial
// scatter, sums in spring order) give the same bytes as in sequence: a cloth of more vertices
// and springs than one block of a pass, pinned, falling onto a sphere, in wind, and without
// (then its motion starts in a plane, with components that are zeros of either sign).
TEST(ImplicitEuler, ThreadsGiveTheSameBytes) {
  const int n = 24;  // 625 vertices, about 3,400 springs: two to four blocks per pass
  MassSpringModel m = cloth({.pose = {Vec3(0, Real(0.3), 0), Quat::Identity()},
                             .size = {1, 1},
                             .resolution = {n, n},
                             .mass = 0.5f,
                             .stiffness = {.stretch = 5000, .shear = 500, .bend = 5},
                             .damping = 0.01f});
  m.pinned = {0, std::uint32_t(n)};
  const auto run = [&](ThreadPool* pool, bool wind) {
    Deformable d({.thickness = Real(0.01)}, m);
    d.addField({GravityField{}});
    if (wind) d.addField({WindField{Vec3(2, 0, 1), Real(0.02)}});
    d.addObstacle({Collider(Sphere{Real(0.25)}), Transform{}});
    std::vector<Real> trace;
    for (int s = 0; s < 15; ++s) {  // on the sphere from the 6th step
      d.step(Real(1) / 60, pool);
      for (std::size_t i = 0; i < d.vertexCount(); ++i)
        for (const Vec3& value : {d.position(i), d.velocity(i)})
          trace.insert(trace.end(), value.data(), value.data() + 3);
    }
    return trace;
  };
  for (bool wind : {true, false}) {
    const std::vector<Real> serial = run(nullptr, wind);
    for (int threads : {2, 3}) {
      ThreadPool pool(threads);
      const std::vector<Real> parallel = run(&pool, wind);
      ASSERT_EQ(parallel.size(), serial.size());
      EXPECT_EQ(std::memcmp(parallel.data(), serial.data(), serial.size() * sizeof(Real)), 0)
          << threads << " threads, wind " << wind;
    }
  }
}

}  // namespace
}  // namespace inertia
