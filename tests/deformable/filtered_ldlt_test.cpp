// The implicit step's direct solve (src/deformable/filtered_ldlt.h) against the filtered
// system built independently, and the step it gives against the PCG's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "deformable/filtered_ldlt.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"
#include "../draws.h"

namespace inertia {
namespace {

using Eigen::Matrix3d;
using Eigen::VectorXd;

// Hair of `strands` strands of 32 segments, plus a 10 x 10 cloth after it: components of 33
// and 121 vertices, more than one part's worth (FilteredDirectSolve::kPartVertices).
MassSpringModel strandsAndSheet(int strands) {
  MassSpringModel m = hair({.strands = strands, .segments = 32});
  const MassSpringModel sheet = cloth({.resolution = {10, 10}});
  const std::uint32_t offset = std::uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(), sheet.positions.begin(), sheet.positions.end());
  m.masses.insert(m.masses.end(), sheet.masses.begin(), sheet.masses.end());
  for (Spring s : sheet.springs) {
    s.a += offset, s.b += offset;
    m.springs.push_back(s);
  }
  return m;
}

// A = S H S + (I - S) with H = diag(d) + the springs' blocks B_k, solved for random positive
// semi-definite blocks, masses and filters (free vertices, held ones S = 0, sliding ones
// S = I - n n^T): the residual |A p - b|, A assembled here as a sparse matrix from triplets,
// is within a backward-stable Cholesky's rounding, 8 n_c eps |A| |p| (n_c the largest column
// of the factor, a few dozen here), and p has no component where S is 0.
TEST(FilteredDirectSolve, SolvesTheFilteredSystem) {
  const MassSpringModel m = strandsAndSheet(40);  // 1,320 + 121 vertices: two parts
  const std::size_t n = m.positions.size();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  VectorXd diagonal(3 * Eigen::Index(n)), b(3 * Eigen::Index(n));
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) diagonal[i] = 1e-3 * (1.5 + u(rng));
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = u(rng);
  std::vector<detail::SymmetricBlock> blocks(m.springs.size());
  std::vector<Matrix3d> dense(m.springs.size());
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const auto draw = [&] { return u(rng); };
    const Eigen::Vector3d a = inertia::test::draw3<Eigen::Vector3d>(draw), c = inertia::test::draw3<Eigen::Vector3d>(draw);
    dense[k] = 10 * (a * a.transpose()) + 0.1 * (c * c.transpose());
    const Matrix3d& d = dense[k];
    blocks[k] = {d(0, 0), d(1, 1), d(2, 2), d(0, 1), d(0, 2), d(1, 2)};
  }
  std::vector<Matrix3d> projection(n, Matrix3d::Identity());
  std::vector<std::uint8_t> constrained(n, 0);
  for (std::size_t i = 0; i < n; i += 7) {
    constrained[i] = 1;
    if (i % 2) {
      projection[i].setZero();
    } else {
      const Eigen::Vector3d normal = inertia::test::draw3<Eigen::Vector3d>([&] { return u(rng); }).normalized();
      projection[i] -= normal * normal.transpose();
    }
  }
  struct Context {
    const std::vector<Matrix3d>* projection;
    const std::vector<std::uint8_t>* constrained;
  } context{&projection, &constrained};
  const detail::ProjectionOf projectionOf = [](const void* c, std::uint32_t i) {
    const Context& s = *static_cast<const Context*>(c);
    return (*s.constrained)[i] ? &(*s.projection)[i] : nullptr;
  };
  b.segment<3>(0).setZero();  // a filtered right-hand side, as the Newton step's -S G is
  for (std::size_t i = 0; i < n; ++i)
    b.segment<3>(3 * Eigen::Index(i)) = projection[i] * b.segment<3>(3 * Eigen::Index(i));

  detail::FilteredDirectSolve solve;
  ASSERT_TRUE(solve.connect(m.springs, n, std::numeric_limits<double>::infinity()));
  VectorXd p;
  ASSERT_TRUE(solve.solve(diagonal, blocks, projectionOf, &context, b, p, nullptr));

  // A, independently: H densely per 3 x 3 block, then filtered, as triplets.
  std::vector<Eigen::Triplet<double>> entries;
  const auto add = [&](std::uint32_t r, std::uint32_t c, const Matrix3d& block) {
    const Matrix3d a = projection[r] * block * projection[c];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) entries.emplace_back(3 * int(r) + i, 3 * int(c) + j, a(i, j));
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    add(i, i, diagonal.segment<3>(3 * Eigen::Index(i)).asDiagonal().toDenseMatrix());
    const Matrix3d complement = Matrix3d::Identity() - projection[i];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        entries.emplace_back(3 * int(i) + r, 3 * int(i) + c, complement(r, c));
  }
  for (std::size_t k = 0; k < m.springs.size(); ++k) {
    const Spring& s = m.springs[k];
    add(s.a, s.a, dense[k]), add(s.b, s.b, dense[k]);
    add(s.a, s.b, -dense[k]), add(s.b, s.a, -dense[k]);
  }
  Eigen::SparseMatrix<double> a(3 * Eigen::Index(n), 3 * Eigen::Index(n));
  a.setFromTriplets(entries.begin(), entries.end());
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_LE((a * p - b).norm(), 8 * 64 * eps * a.norm() * p.norm());
  EXPECT_GT(p.norm(), 0);
  for (std::size_t i = 0; i < n; ++i)
    if (constrained[i]) {
      const Matrix3d held = Matrix3d::Identity() - projection[i];
      EXPECT_LE((held * p.segment<3>(3 * Eigen::Index(i))).norm(), 1e-12 * p.norm()) << i;
    }
}

// Automatic picks the direct solve for strands (one solve per Newton step), whose factor
// stays sparse, and PCG for a cloth, whose factor fills in.
TEST(FilteredDirectSolve, AutomaticSolvesStrandsDirectlyAndSheetsByPcg) {
  const auto solveOf = [](const MassSpringModel& m) {
    Deformable d({}, m);
    d.addField({GravityField{}});
    d.step(Real(1) / 60, nullptr);
    return d.lastSolve();
  };
  const ImplicitSolveReport strands = solveOf(hair({.strands = 20, .segments = 32}));
  EXPECT_EQ(strands.iterations, strands.newtonIterations);
  EXPECT_GT(strands.newtonIterations, 0);
  MassSpringModel sheet = cloth({.resolution = {20, 20}, .stiffness = {.stretch = 5000}});
  sheet.pinned = {0, 20};
  const ImplicitSolveReport pcg = solveOf(sheet);
  EXPECT_GT(pcg.iterations, 2 * pcg.newtonIterations);
}

// The parts factored on several threads give the same bytes as in sequence: hair (many
// parts) falling onto a head and resting on it, held by sticking and sliding contacts.
TEST(FilteredDirectSolve, ThreadsGiveTheSameBytes) {
  const MassSpringModel m = hair({.strands = 100,
                                  .segments = 32,
                                  .length = Real(0.15),
                                  .stiffness = {.stretch = 2000, .bend = Real(0.5)}});
  const auto run = [&](ThreadPool* pool) {
    Deformable d({.thickness = Real(0.002),
                  .friction = Real(0.2),
                  .linearSolver = DeformableLinearSolver::Direct},
                 m);
    d.addField({GravityField{}});
    d.addObstacle({Collider(Sphere{Real(0.1)}), Transform{}});
    std::vector<Real> trace;
    for (int s = 0; s < 12; ++s) {
      d.step(Real(1) / 60, pool);
      EXPECT_EQ(d.lastSolve().iterations, d.lastSolve().newtonIterations);  // all direct
      trace.insert(trace.end(), d.positions().begin(), d.positions().end());
      trace.insert(trace.end(), d.velocities().begin(), d.velocities().end());
    }
    return trace;
  };
  const std::vector<Real> serial = run(nullptr);
  ThreadPool pool(3);
  const std::vector<Real> parallel = run(&pool);
  ASSERT_EQ(parallel.size(), serial.size());
  EXPECT_EQ(std::memcmp(parallel.data(), serial.data(), serial.size() * sizeof(Real)), 0);
}

}  // namespace
}  // namespace inertia
