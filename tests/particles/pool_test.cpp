#include "inertia/particles/pool.h"

#include <vector>

#include <gtest/gtest.h>

#include "inertia/core/error.h"

using namespace inertia;

namespace {
ParticlePool::Spawn at(Real x) {
  ParticlePool::Spawn s;
  s.position = Vec3(x, 0, 0);
  return s;
}
}  // namespace

TEST(ParticlePool, AddsUntilFullThenRefuses) {
  ParticlePool pool(3);
  EXPECT_TRUE(pool.add(at(0)));
  EXPECT_TRUE(pool.add(at(1)));
  EXPECT_TRUE(pool.add(at(2)));
  EXPECT_TRUE(pool.full());
  EXPECT_FALSE(pool.add(at(3)));
  EXPECT_EQ(pool.size(), 3u);
}

TEST(ParticlePool, RemovalKeepsOrderAndReusesStorage) {
  ParticlePool pool(5);
  for (int i = 0; i < 5; ++i) pool.add(at(Real(i)));
  const std::vector<std::uint8_t> flags{0, 1, 0, 1, 0};
  EXPECT_EQ(pool.removeFlagged(flags), 2u);
  ASSERT_EQ(pool.size(), 3u);
  // Survivors keep their order and ids; ids stay increasing along the pool.
  EXPECT_EQ(pool.position(0).x(), 0);
  EXPECT_EQ(pool.position(1).x(), 2);
  EXPECT_EQ(pool.position(2).x(), 4);
  EXPECT_EQ(pool.ids()[0], 0u);
  EXPECT_EQ(pool.ids()[1], 2u);
  EXPECT_EQ(pool.ids()[2], 4u);
  // The freed storage takes new particles, appended after the survivors with fresh ids.
  EXPECT_TRUE(pool.add(at(10)));
  EXPECT_TRUE(pool.add(at(11)));
  EXPECT_FALSE(pool.add(at(12)));
  EXPECT_EQ(pool.ids()[3], 5u);
  EXPECT_EQ(pool.ids()[4], 6u);
  EXPECT_EQ(pool.position(4).x(), 11);
}

TEST(ParticlePool, UserAttributesFollowCompaction) {
  ParticlePool pool(4);
  const std::size_t heat = pool.addAttribute("heat");
  EXPECT_THROW(pool.addAttribute("heat"), InvalidArgument);
  for (int i = 0; i < 4; ++i) pool.add(at(Real(i)));
  for (int i = 0; i < 4; ++i) pool.attribute(heat)[std::size_t(i)] = Real(10 * i);
  pool.removeFlagged(std::vector<std::uint8_t>{1, 0, 1, 0});
  EXPECT_EQ(pool.attribute(heat)[0], 10);
  EXPECT_EQ(pool.attribute(heat)[1], 30);
  EXPECT_EQ(pool.attributeIndex("heat"), heat);
  EXPECT_THROW(pool.addAttribute("late"), InvalidArgument);  // particles exist already
}

TEST(ParticlePool, RejectsBadCapacity) {
  EXPECT_THROW(ParticlePool(0), InvalidArgument);
}
