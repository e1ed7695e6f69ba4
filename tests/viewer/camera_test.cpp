// View and projection matrices against their definitions, and the default camera's framing.
#include "camera.h"

#include <gtest/gtest.h>

#include "inertia/world/world.h"

namespace inertia::viewer {
namespace {

Eigen::Vector3f project(const Eigen::Matrix4f& m, const Eigen::Vector3f& p) {
  const Eigen::Vector4f h = m * Eigen::Vector4f(p.x(), p.y(), p.z(), 1);
  return h.head<3>() / h.w();
}

TEST(Camera, ViewPutsTheEyeAtTheOriginLookingDownMinusZ) {
  CameraView c;
  c.position = {3, 4, 5};
  c.target = {1, 0, -2};
  const Eigen::Matrix4f v = viewMatrix(c);
  EXPECT_LT((project(v, c.position)).norm(), 1e-5f);
  const Eigen::Vector3f t = project(v, c.target);
  EXPECT_NEAR(t.x(), 0, 1e-5f);
  EXPECT_NEAR(t.y(), 0, 1e-5f);
  EXPECT_NEAR(t.z(), -(c.target - c.position).norm(), 1e-4f);
  // World up stays up on screen.
  EXPECT_GT(project(v, c.target + Eigen::Vector3f::UnitY()).y(), 0.5f);
}

TEST(Camera, ViewLookingStraightDownIsFinite) {
  CameraView c;
  c.position = {0, 10, 0};
  c.target = {0, 0, 0};
  EXPECT_TRUE(viewMatrix(c).allFinite());
}

TEST(Camera, ProjectionMapsNearAndFarToTheDepthRange) {
  CameraView c;
  c.nearPlane = 0.5f;
  c.farPlane = 50;
  c.fovY = 90;
  const Eigen::Matrix4f p = projectionMatrix(c, 2.0f);
  EXPECT_NEAR(project(p, {0, 0, -0.5f}).z(), -1, 1e-5f);
  EXPECT_NEAR(project(p, {0, 0, -50}).z(), 1, 1e-4f);
  // At 90 degrees, y = -z is the top edge; x = -2z the right edge at aspect 2.
  EXPECT_NEAR(project(p, {0, 3, -3}).y(), 1, 1e-5f);
  EXPECT_NEAR(project(p, {6, 0, -3}).x(), 1, 1e-5f);
}

TEST(Camera, FramedBoundsAreInView) {
  const Aabb b{Vec3(-4, 0, -1), Vec3(6, 3, 2)};
  for (float aspect : {0.5f, 1.0f, 16.0f / 9.0f}) {
    const CameraView c = frameBounds(b, 45, aspect);
    const Eigen::Matrix4f m = projectionMatrix(c, aspect) * viewMatrix(c);
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner(i & 1 ? b.upper.x() : b.lower.x(), i & 2 ? b.upper.y() : b.lower.y(),
                        i & 4 ? b.upper.z() : b.lower.z());
      const Eigen::Vector3f ndc = project(m, corner.cast<float>());
      EXPECT_LE(ndc.cwiseAbs().maxCoeff(), 1.0f) << "corner " << i << " aspect " << aspect;
    }
    EXPECT_GT(c.position.y(), c.target.y());  // from above
  }
}

TEST(Camera, SceneBoundsSkipPlanesButKeepTheirFoot) {
  World world;
  BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{{0, 1, 0}, 0});
  BodyId ball = world.createBody({.position = {2, 5, 0}});
  world.addShape(ball, Sphere{Real(0.5)});
  const Aabb b = sceneBounds(world);
  ASSERT_TRUE(b.isValid());
  EXPECT_NEAR(b.upper.y(), 5.5, 1e-5);
  EXPECT_NEAR(b.lower.y(), 0.0, 1e-5);  // the ground below the ball
  EXPECT_NEAR(b.lower.x(), 1.5, 1e-5);
  EXPECT_NEAR(b.upper.x(), 2.5, 1e-5);

  World empty;
  EXPECT_FALSE(sceneBounds(empty).isValid());
}

TEST(Camera, SceneBoundsHoldParticles) {
  World world;
  ParticleSystem& ps = world.particleSystem(world.createParticleSystem({.capacity = 16}));
  EmitterSettings e;
  e.pose.p = Vec3(-3, 7, 1);
  e.burst = 4;
  e.speed = {0, 0};
  ps.addEmitter(e);
  world.step(Real(0.001));
  const Aabb b = sceneBounds(world);
  ASSERT_TRUE(b.isValid());
  EXPECT_NEAR(b.center().x(), -3, 1e-3);
  EXPECT_NEAR(b.center().y(), 7, 1e-2);
}

}  // namespace
}  // namespace inertia::viewer
