// Deformables in a World: created, stepped with it, colliding with its static bodies, state
// read back; ids that go stale.
#include <gtest/gtest.h>

#include "../deformable/crossings.h"
#include "inertia/collision/queries.h"
#include "inertia/core/error.h"
#include "inertia/deformable/generators.h"
#include "inertia/world/world.h"

namespace inertia {
namespace {

// A cloth dropped on a static ball in a world settles on it: the world steps it with its own
// dt and gives it the bodies' shapes; no vertex comes closer to the ball than the thickness.
TEST(WorldDeformables, ClothFallsOntoAStaticBodyAndStaysOutside) {
  World world({.dt = Real(1) / 60});
  const BodyId ball = world.createBody({.type = BodyType::Static});
  world.addShape(ball, Sphere{Real(0.4)});
  const DeformableId id =
      world.createDeformable({.name = "sheet", .thickness = Real(0.015)},
                             cloth({.pose = {Vec3(0, Real(0.8), 0), Quat::Identity()},
                                    .size = {1, 1},
                                    .resolution = {12, 12},
                                    .mass = Real(0.2),
                                    .stiffness = {.stretch = 3000, .shear = 300, .bend = 2},
                                    .damping = Real(0.02)}));
  world.deformable(id).addField({GravityField{}});
  const Collider sphere(Sphere{Real(0.4)});
  for (int s = 0; s < 90; ++s) {
    world.step(Real(1) / 60);
    const Deformable& d = world.deformable(id);
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      ASSERT_GE(queryPoint(sphere, Transform{}, d.position(i)).distance, Real(0.015) - Real(1e-6))
          << "step " << s;
  }
  const Deformable& d = world.deformable(id);
  EXPECT_NEAR(d.time(), world.time(), 1e-9);
  // The middle vertex rests on top of the ball.
  EXPECT_NEAR(d.position(6 + 6 * 13).y(), Real(0.4 + 0.015), Real(0.005));
  ASSERT_EQ(world.deformables().size(), 1u);
  EXPECT_EQ(world.deformables()[0], id);
}

// A cloth dropped onto another, pinned all round below it: with self-collision (which in a
// world makes deformables collide with each other too) no vertex of either crosses a triangle
// of the other between steps and no edge pierces one after a step (brute force); without it
// the upper one falls through.
TEST(WorldDeformables, ClothDroppedOnAnotherDoesNotPassThroughIt) {
  for (bool collide : {true, false}) {
    World world({.gravity = Vec3(0, Real(-9.81), 0), .dt = Real(1) / 60});
    const int n = 8;
    MassSpringModel lower = cloth({.size = {1, 1},
                                   .resolution = {n, n},
                                   .mass = Real(0.2),
                                   .stiffness = {.stretch = 2000, .shear = 200, .bend = 1}});
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (i == 0 || j == 0 || i == n || j == n)
          lower.pinned.push_back(std::uint32_t(i + j * (n + 1)));
    const MassSpringModel upper =
        cloth({.pose = {Vec3(Real(0.05), Real(0.3), Real(0.03)), Quat::Identity()},
               .size = {Real(0.6), Real(0.6)},
               .resolution = {n, n},
               .mass = Real(0.1),
               .stiffness = {.stretch = 2000, .shear = 200, .bend = 1}});
    const DeformableSettings settings{.thickness = Real(0.01), .selfCollision = collide};
    const DeformableId a = world.createDeformable(settings, lower);
    const DeformableId b = world.createDeformable(settings, upper);
    for (DeformableId id : {a, b}) world.deformable(id).addField({GravityField{}});
    const Deformable& da = world.deformable(a);
    const Deformable& db = world.deformable(b);
    int crossings = 0;
    for (int s = 0; s < 60; ++s) {
      const auto beforeA = test::positions(da), beforeB = test::positions(db);
      world.step(Real(1) / 60);
      const test::Crossings ab = test::countCrossings(da, beforeA, db, beforeB);
      const test::Crossings ba = test::countCrossings(db, beforeB, da, beforeA);
      const int now = ab.vertexTriangle + ab.edgeTriangle + ba.vertexTriangle + ba.edgeTriangle;
      if (collide) {
        ASSERT_EQ(now, 0) << "step " << s;
      }
      crossings += now;
    }
    if (collide) {
      // The upper cloth lies on the lower one: its middle above the lower one's middle.
      EXPECT_GT(db.position(std::size_t(n / 2 + n / 2 * (n + 1))).y(),
                da.position(std::size_t(n / 2 + n / 2 * (n + 1))).y());
    } else {
      EXPECT_GT(crossings, 0);
    }
  }
}

TEST(WorldDeformables, DestroyedIdsGoStale) {
  World world;
  const DeformableId a = world.createDeformable({}, rope({}));
  EXPECT_TRUE(world.isValid(a));
  world.destroyDeformable(a);
  EXPECT_FALSE(world.isValid(a));
  EXPECT_THROW(world.deformable(a), InvalidArgument);
  const DeformableId b = world.createDeformable({}, rope({}));
  EXPECT_EQ(b.index, a.index);
  EXPECT_NE(b.generation, a.generation);
  EXPECT_THROW(world.createDeformable({.friction = -1}, rope({})), InvalidArgument);
}

}  // namespace
}  // namespace inertia
