// The shared scene builders: counts, touching placements, seeded randomness.
#include "inertia/world/builders.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "inertia/core/error.h"

using namespace inertia;

TEST(Builders, PyramidRowsTouch) {
  const auto boxes = pyramid({.base = 40});
  ASSERT_EQ(boxes.size(), 820u);  // 40 * 41 / 2, the peer benchmark's pyramid
  // Row r's boxes rest on row r-1: centres at (2 r + 1) h, neighbours 2 h apart.
  EXPECT_FLOAT_EQ(boxes[0].settings.position.y(), Real(0.5));
  EXPECT_FLOAT_EQ(boxes[1].settings.position.x() - boxes[0].settings.position.x(), 1);
  EXPECT_FLOAT_EQ(boxes.back().settings.position.y(), Real(0.5) * 79);
  EXPECT_FLOAT_EQ(boxes.back().settings.position.x(), 0);
}

TEST(Builders, TowerWallAndGridPlacement) {
  const auto t = tower({.height = 3, .halfExtents = Vec3(1, Real(0.25), 1)});
  ASSERT_EQ(t.size(), 3u);
  EXPECT_FLOAT_EQ(t[2].settings.position.y(), Real(1.25));
  const auto w = wall({.rows = 2, .columns = 4});
  ASSERT_EQ(w.size(), 8u);
  EXPECT_FLOAT_EQ(w[4].settings.position.x() - w[0].settings.position.x(), Real(0.5));  // staggered
  const auto g = grid({.counts = {2, 3, 4}, .spacing = Vec3(1, 2, 3)});
  ASSERT_EQ(g.size(), 24u);
  EXPECT_TRUE(g.back().settings.position.isApprox(Vec3(1, 4, 9)));
}

TEST(Builders, RainIsSeededAndInsideItsBox) {
  const RainSettings s{.count = 500, .lower = Vec3(-1, 2, -3), .upper = Vec3(1, 4, 3), .seed = 9};
  const auto a = rain(s), b = rain(s);
  auto other = s;
  other.seed = 10;
  const auto c = rain(other);
  ASSERT_EQ(a.size(), 500u);
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3& p = a[i].settings.position;
    EXPECT_TRUE((p.array() >= s.lower.array()).all() && (p.array() <= s.upper.array()).all());
    EXPECT_NEAR(a[i].settings.orientation.norm(), 1, 1e-5);
    EXPECT_EQ(p, b[i].settings.position);
    differs = differs || p != c[i].settings.position;
  }
  EXPECT_TRUE(differs);
}

TEST(Builders, BadSettingsThrow) {
  EXPECT_THROW(pyramid({.base = 0}), InvalidArgument);
  EXPECT_THROW(rain({.lower = Vec3(1, 1, 1), .upper = Vec3(0, 0, 0)}), InvalidArgument);
  EXPECT_THROW(grid({.spacing = Vec3(std::numeric_limits<Real>::quiet_NaN(), 1, 1)}), InvalidArgument);
}
