// Mouse interaction without a window: picking by ray, the mouse spring pulling a body to the
// cursor (and letting it settle there), and shooting a ball along a ray.
#include "interaction.h"

#include <gtest/gtest.h>

namespace inertia::viewer {
namespace {

struct Scene {
  World world{WorldSettings{.sleeping = false}};
  BodyId ground, box;
  Scene() {
    ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{{0, 1, 0}, 0});
    box = world.createBody({.position = {0, 0.5, 0}});
    world.addShape(box, Box{Vec3::Constant(Real(0.5))});
  }
};

TEST(Interaction, PickingHoldsTheHitPointOfDynamicBodiesOnly) {
  Scene s;
  const Ray ray{.origin = Vec3(0, 0.7, 10), .direction = Vec3(0, 0, -100)};
  const std::optional<MouseSpring> spring = pickBody(s.world, ray);
  ASSERT_TRUE(spring);
  EXPECT_EQ(spring->body, s.box);
  EXPECT_TRUE(spring->localAnchor.isApprox(Vec3(0, 0.2, 0.5), 1e-4f));
  EXPECT_NEAR(spring->distance, 9.5, 1e-4);
  // The ground (static) and empty space are not picked.
  EXPECT_FALSE(pickBody(s.world, {.origin = Vec3(3, 5, 0), .direction = Vec3(0, -100, 0)}));
  EXPECT_FALSE(pickBody(s.world, {.origin = Vec3(3, 5, 0), .direction = Vec3(0, 100, 0)}));
  // The target for a mouse ray is at the grab distance along it.
  const Vec3 target =
      springTarget(*spring, {.origin = Vec3(0, 0, 10), .direction = Vec3(0, 0, -2)});
  EXPECT_TRUE(target.isApprox(Vec3(0, 0, 0.5)));
}

TEST(Interaction, SpringLiftsTheBodyToTheTargetAndSettles) {
  Scene s;
  MouseSpring spring =
      *pickBody(s.world, {.origin = Vec3(0, 0.5, 10), .direction = Vec3(0, 0, -100)});
  spring.target = Vec3(0, 2.5, 0.5);
  const Real m = s.world.rigidBodies().mass(s.box);
  EXPECT_NEAR(springForce(s.world, spring).norm(),
              std::min<Real>(m * spring.maxAcceleration, m * Real(4 * 9.8696 * 9) * 2), 1e-2 * m);
  for (int i = 0; i < 300; ++i) {
    applySpring(s.world, spring);
    s.world.step(Real(1.0 / 60));
  }
  // At rest, hanging: the anchor sits below the target by g / omega^2 (2.8 cm), with the centre
  // of mass straight below it.
  const Vec3 anchor = s.world.transform(s.box).apply(spring.localAnchor);
  const Real sag = Real(9.81) / (Real(4 * 9.8696) * spring.frequency * spring.frequency);
  EXPECT_NEAR(spring.target.y() - anchor.y(), sag, 0.003);
  EXPECT_NEAR((anchor - spring.target).norm(), sag, 0.003);
  const Vec3 com = s.world.rigidBodies().centerOfMass(s.box);
  EXPECT_NEAR(com.x(), anchor.x(), 0.01);
  EXPECT_NEAR(com.z(), anchor.z(), 0.01);
  EXPECT_NEAR(anchor.y() - com.y(), 0.5, 0.01);
  EXPECT_LT(s.world.linearVelocity(s.box).norm(), 0.01);
  // A destroyed body is left alone.
  s.world.destroyBody(s.box);
  EXPECT_NO_THROW(applySpring(s.world, spring));
}

TEST(Interaction, ShotBallFliesAlongTheRay) {
  Scene s;
  const int before = s.world.bodyCount();
  const BodyId ball = shootBall(s.world, {.origin = Vec3(0, 1, 10), .direction = Vec3(0, 0, -5)},
                                {.radius = Real(0.2), .speed = 40});
  EXPECT_EQ(s.world.bodyCount(), before + 1);
  EXPECT_TRUE(s.world.linearVelocity(ball).isApprox(Vec3(0, 0, -40)));
  EXPECT_NEAR(s.world.rigidBodies().mass(ball), 2000 * 4.18879 * 0.008, 0.05);
  // It hits the box (and pushes it) within a second.
  for (int i = 0; i < 60; ++i) s.world.step(Real(1.0 / 60));
  EXPECT_LT(s.world.transform(s.box).p.z(), -0.01);
}

}  // namespace
}  // namespace inertia::viewer
