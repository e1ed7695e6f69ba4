// Deformables in a World: created, stepped with it, colliding with its static bodies, state
// read back; ids that go stale.
#include <gtest/gtest.h>

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
