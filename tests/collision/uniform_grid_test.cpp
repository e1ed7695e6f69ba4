#include "inertia/collision/uniform_grid.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "inertia/core/error.h"
#include "../draws.h"

using namespace inertia;

TEST(UniformGrid, NearQueriesCoverBruteForceAndVisitEachPointOnce) {
  // Clustered and spread points, including negative coordinates (cell indices below zero)
  // and more points than buckets would suggest, so bucket collisions happen.
  std::mt19937 rng(17);
  std::uniform_real_distribution<Real> wide(-20, 20), tight(-1, 1);
  std::vector<Real> xs;
  for (int i = 0; i < 3000; ++i) {
    const bool cluster = i % 3 == 0;
    for (int k = 0; k < 3; ++k) xs.push_back(cluster ? tight(rng) : wide(rng));
  }
  const std::size_t n = xs.size() / 3;
  const Real cell = Real(0.7);
  UniformGrid grid;
  grid.build(xs, cell);
  std::vector<int> visits(n);
  for (int q = 0; q < 500; ++q) {
    const Vec3 p = q % 2 ? inertia::test::draw3<Vec3>([&] { return tight(rng); }) : inertia::test::draw3<Vec3>([&] { return wide(rng); });
    std::fill(visits.begin(), visits.end(), 0);
    grid.forEachNear(p, [&](std::uint32_t j) { ++visits[j]; });
    for (std::size_t j = 0; j < n; ++j) {
      ASSERT_LE(visits[j], 1) << "point " << j << " visited twice";
      const Vec3 x(xs[3 * j], xs[3 * j + 1], xs[3 * j + 2]);
      // Everything within one cell size must be found (the 27 cells cover that ball).
      if ((x - p).norm() <= cell) {
        ASSERT_EQ(visits[j], 1) << "point " << j << " missed";
      }
    }
  }
}

TEST(UniformGrid, SameInputSameOrder) {
  std::vector<Real> xs{0, 0, 0, 0.1f, 0, 0, 5, 5, 5, -3, 2, 1};
  UniformGrid a, b;
  a.build(xs, 1);
  b.build(xs, 1);
  std::vector<std::uint32_t> va, vb;
  a.forEachNear(Vec3(0, 0, 0), [&](std::uint32_t j) { va.push_back(j); });
  b.forEachNear(Vec3(0, 0, 0), [&](std::uint32_t j) { vb.push_back(j); });
  EXPECT_EQ(va, vb);
  EXPECT_GE(va.size(), 2u);
}

TEST(UniformGrid, RejectsBadInput) {
  UniformGrid g;
  std::vector<Real> xs{0, 0, 0};
  EXPECT_THROW(g.build(xs, 0), InvalidArgument);
  EXPECT_THROW(g.build(std::vector<Real>{0, 0}, 1), InvalidArgument);
}
