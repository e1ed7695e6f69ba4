// Collision filters (body.h): the rule against its spelled-out cases and its symmetry, and
// bodies that the filter keeps apart falling through each other as freely as the closed form of
// free fall says, while the bodies it lets meet still stand on each other.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "inertia/world/builders.h"
#include "inertia/world/world.h"

using namespace inertia;

namespace {

constexpr Real kFilterStep = Real(1) / 60;

// Box2D's own examples of its rule.
static_assert(shouldCollide({}, {}));
static_assert(!shouldCollide({.category = 2, .mask = ~2u}, {.category = 2, .mask = ~2u}));
static_assert(shouldCollide({.category = 2, .mask = ~2u}, {}));
static_assert(!shouldCollide({.category = 1, .mask = 2}, {.category = 2, .mask = 2}));  // one way
static_assert(!shouldCollide({.group = -3}, {.group = -3}));
static_assert(shouldCollide({.group = -3}, {.group = -4}));
static_assert(shouldCollide({.category = 1, .mask = 0, .group = 5},
                            {.category = 1, .mask = 0, .group = 5}));  // the group wins
static_assert(!shouldCollide({.category = 1, .mask = 0, .group = 5},
                             {.category = 1, .mask = 0, .group = 6}));

// A box of half extent 0.5 m resting on the ground (category 4), a second dropped onto it from
// 1 m above its top, each with its filter: the second's centre height after 2 s.
Real dropOnBox(const CollisionFilter& lower, const CollisionFilter& upper) {
  World world({.sleeping = false});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.rigidBodies().setFilter(world.addShape(ground, Plane{Vec3::UnitY(), 0}), {.category = 4});
  const Box box{Vec3::Constant(Real(0.5))};
  const BodyId a = world.createBody({.position = Vec3(0, Real(0.5), 0)});
  world.rigidBodies().setFilter(world.addShape(a, box), lower);
  const BodyId b = world.createBody({.position = Vec3(0, Real(2.5), 0)});
  world.rigidBodies().setFilter(world.addShape(b, box), upper);
  for (int i = 0; i < 120; ++i) world.step(kFilterStep);
  return world.transform(b).p.y();
}

}  // namespace

TEST(CollisionFilter, RuleIsSymmetric) {
  std::mt19937 random(7);
  std::uniform_int_distribution<std::uint32_t> bits(0, 7);
  std::uniform_int_distribution<std::int32_t> group(-2, 2);
  for (int i = 0; i < 2000; ++i) {
    const CollisionFilter a{bits(random), bits(random), group(random)};
    const CollisionFilter b{bits(random), bits(random), group(random)};
    EXPECT_EQ(shouldCollide(a, b), shouldCollide(b, a));
  }
}

// The upper box stands on the lower one (centre at 1.5 m) when the filters let them meet, and
// falls through it to the ground (centre at 0.5 m) when not. Both within the resting contact's
// slop and softness, a few millimetres: 2 cm separates "standing" from 1 m away.
TEST(CollisionFilter, FilteredBoxesFallThroughEachOther) {
  const Real onTop = Real(1.5), onGround = Real(0.5), tolerance = Real(0.02);
  EXPECT_NEAR(dropOnBox({}, {}), onTop, tolerance);
  EXPECT_NEAR(dropOnBox({.category = 2, .mask = ~2u}, {.category = 2, .mask = ~2u}), onGround,
              tolerance);
  EXPECT_NEAR(dropOnBox({.mask = ~1u}, {}), onGround, tolerance);  // refused by one side
  EXPECT_NEAR(dropOnBox({.group = -1}, {.group = -1}), onGround, tolerance);
  // Masks that leave each other out, overruled by a shared positive group.
  EXPECT_NEAR(dropOnBox({.mask = 4, .group = 1}, {.mask = 4, .group = 1}), onTop, tolerance);
  EXPECT_NEAR(dropOnBox({.mask = 4, .group = 1}, {.mask = 4, .group = 2}), onGround, tolerance);
}

// A sphere whose mask leaves out the ground's category falls through the plane as in free
// fall. Each substep h of the default integrator (symplectic Euler) moves it by -g h^2 k at its
// k-th substep, so after N substeps y = y0 - g h^2 N (N + 1) / 2. Rounding: N = 480 float
// additions to a height of up to 20 m, 480 * 20 m * 6e-8 = 6e-4 m at worst.
TEST(CollisionFilter, FilteredSphereFallsFreelyThroughThePlane) {
  const int substeps = 4, steps = 120;
  World world({.substeps = substeps, .sleeping = false});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.rigidBodies().setFilter(world.addShape(ground, Plane{Vec3::UnitY(), 0}), {.category = 4});
  const BodyId ball = world.createBody({.position = Vec3(0, 1, 0)});
  const ShapeId shape = world.addShape(ball, Sphere{Real(0.1)});
  world.rigidBodies().setFilter(shape, {.mask = ~4u});
  EXPECT_EQ(world.rigidBodies().filter(shape).mask, ~4u);
  for (int i = 0; i < steps; ++i) world.step(kFilterStep);
  const double h = double(kFilterStep) / substeps, n = double(steps * substeps);
  EXPECT_NEAR(double(world.transform(ball).p.y()), 1 - 9.81 * h * h * n * (n + 1) / 2, 6e-4);
}

// A box asleep on another: a filter that lets it meet the ground only wakes it, and it falls
// through the lower box onto the ground.
TEST(CollisionFilter, NewFilterWakesTheBodyAndHoldsFromTheNextStep) {
  World world;
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.rigidBodies().setFilter(world.addShape(ground, Plane{Vec3::UnitY(), 0}), {.category = 4});
  const Box box{Vec3::Constant(Real(0.5))};
  const BodyId a = world.createBody({.position = Vec3(0, Real(0.5), 0)});
  world.addShape(a, box);
  const BodyId b = world.createBody({.position = Vec3(0, Real(1.5), 0)});
  const ShapeId top = world.addShape(b, box);
  for (int i = 0; i < 300 && world.rigidBodies().isAwake(b); ++i) world.step(kFilterStep);
  ASSERT_FALSE(world.rigidBodies().isAwake(b));
  world.rigidBodies().setFilter(top, {.mask = 4});
  EXPECT_TRUE(world.rigidBodies().isAwake(b));
  for (int i = 0; i < 120; ++i) world.step(kFilterStep);
  EXPECT_NEAR(world.transform(b).p.y(), Real(0.5), Real(0.02));
}

// Described bodies (builders.h, and so scene files) carry their shapes' filters into the world.
TEST(CollisionFilter, DescribedShapesKeepTheirFilters) {
  World world({.sleeping = false});
  const Box box{Vec3::Constant(Real(0.5))};
  const CollisionFilter apart{.group = -2};
  addBody(world,
          {.settings = {.type = BodyType::Static}, .shapes = {{.shape = Plane{Vec3::UnitY(), 0}}}});
  addBody(world, {.settings = {.position = Vec3(0, Real(0.5), 0)},
                  .shapes = {{.shape = box, .filter = apart}}});
  const BodyId b = addBody(world, {.settings = {.position = Vec3(0, Real(2.5), 0)},
                                   .shapes = {{.shape = box, .filter = apart}}});
  for (int i = 0; i < 120; ++i) world.step(kFilterStep);
  EXPECT_NEAR(world.transform(b).p.y(), Real(0.5), Real(0.02));  // through, onto the ground
}

// A box asleep on the ground: when the ground's filter stops taking it, the box wakes (a static
// body cannot) and falls freely through.
TEST(CollisionFilter, GroundsNewFilterWakesWhatItHeld) {
  World world;
  const BodyId ground = world.createBody({.type = BodyType::Static});
  const ShapeId plane = world.addShape(ground, Plane{Vec3::UnitY(), 0});
  const BodyId box = world.createBody({.position = Vec3(0, Real(0.5), 0)});
  world.addShape(box, Box{Vec3::Constant(Real(0.5))});
  for (int i = 0; i < 300 && world.rigidBodies().isAwake(box); ++i) world.step(kFilterStep);
  ASSERT_FALSE(world.rigidBodies().isAwake(box));
  world.rigidBodies().setFilter(plane, {.mask = 0});
  EXPECT_TRUE(world.rigidBodies().isAwake(box));
  for (int i = 0; i < 60; ++i) world.step(kFilterStep);
  EXPECT_LT(world.transform(box).p.y(), Real(-3));  // fell about g t^2 / 2 = 4.9 m in 1 s
}
