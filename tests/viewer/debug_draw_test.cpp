// Debug lines: which lines each toggle adds (contacts, bounds, velocities, centres of mass),
// and the GL line program drawing them (offscreen, EGL).
#include "debug_draw.h"

#include <gtest/gtest.h>

#include "camera.h"
#include "offscreen.h"

namespace inertia::viewer {
namespace {

// A box resting on the ground (4 touching points after a few steps) and a flying sphere.
struct Scene {
  World world{WorldSettings{.sleeping = false}};
  BodyId box, ball;
  Scene() {
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{{0, 1, 0}, 0});
    box = world.createBody({.position = {0, 0.5, 0}});
    world.addShape(box, Box{Vec3::Constant(Real(0.5))});
    ball = world.createBody({.position = {0, 5, 0}, .linearVelocity = {3, 0, 0}});
    world.addShape(ball, Sphere{Real(0.5)});
    for (int i = 0; i < 5; ++i) world.step(Real(1.0 / 60));
  }
};

TEST(DebugDraw, NothingByDefault) {
  Scene s;
  DebugLines lines;
  buildDebugLines(s.world, {}, 1, lines);
  EXPECT_EQ(lines.lineCount(), 0u);
}

TEST(DebugDraw, ContactPointsAndNormals) {
  Scene s;
  DebugLines lines;
  buildDebugLines(s.world, {.contacts = true}, 1, lines);
  // Per touching point: a cross (3 lines) and a normal (1 line). The box has 4 on the ground.
  ASSERT_EQ(lines.lineCount(), 16u);
  int normals = 0;
  for (std::size_t i = 0; i < lines.lineCount(); ++i) {
    const float* v = &lines.vertices[12 * i];
    const Eigen::Vector3f a(v[0], v[1], v[2]), b(v[6], v[7], v[8]);
    if ((b - a).isApprox(Eigen::Vector3f(0, 1, 0), 1e-3f)) {
      ++normals;
      EXPECT_NEAR(a.y(), 0, 0.01);  // at the ground
    }
  }
  EXPECT_EQ(normals, 4);
}

TEST(DebugDraw, BoundsSkipPlanes) {
  Scene s;
  DebugLines lines;
  buildDebugLines(s.world, {.aabbs = true}, 1, lines);
  EXPECT_EQ(lines.lineCount(), 24u);  // box and sphere, 12 edges each; the plane has none
  float maxY = -1e9f;
  for (std::size_t i = 1; i < lines.vertices.size(); i += 6)
    maxY = std::max(maxY, lines.vertices[i]);
  EXPECT_NEAR(maxY, s.world.transform(s.ball).p.y() + 0.5, 1e-3);
}

TEST(DebugDraw, VelocitiesAndCentresOfMass) {
  Scene s;
  DebugLines lines;
  buildDebugLines(s.world, {.velocities = true}, 1, lines);
  ASSERT_EQ(lines.lineCount(), 4u);  // linear and angular, two dynamic bodies
  // The ball's linear velocity line: from its centre, 0.1 s of its motion.
  const Vec3 c = s.world.rigidBodies().centerOfMass(s.ball);
  const Vec3 v = s.world.linearVelocity(s.ball);
  bool found = false;
  for (std::size_t i = 0; i < lines.lineCount(); ++i) {
    const float* p = &lines.vertices[12 * i];
    if (Eigen::Vector3f(p[0], p[1], p[2]).isApprox(c.cast<float>()) &&
        Eigen::Vector3f(p[6], p[7], p[8]).isApprox((c + Real(0.1) * v).cast<float>()))
      found = true;
  }
  EXPECT_TRUE(found);
  lines.clear();
  buildDebugLines(s.world, {.centersOfMass = true}, 1, lines);
  EXPECT_EQ(lines.lineCount(), 6u);  // a 3-line cross per dynamic body
}

TEST(DebugDraw, LineRendererDrawsColouredLines) {
  EglContext context;
  constexpr int kW = 64, kH = 48;
  OffscreenTarget target(kW, kH, 1);
  LineRenderer renderer;
  CameraView camera;
  camera.position = {0, 0, 5};
  camera.target = {0, 0, 0};
  DebugLines lines;
  for (int k = -4; k <= 4; ++k)  // a red horizontal band of lines across the view
    lines.add(Vec3(-3, Real(0.02) * Real(k), 0), Vec3(3, Real(0.02) * Real(k), 0),
              Eigen::Vector3f(1, 0, 0));
  target.bind();
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  renderer.draw(lines, projectionMatrix(camera, float(kW) / kH) * viewMatrix(camera));
  const std::vector<std::uint8_t> rgb = target.readRgb();
  int redInMiddleRow = 0, redElsewhere = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const std::uint8_t* p = &rgb[3 * (std::size_t(y) * kW + x)];
      if (p[0] > 128 && p[1] < 50) (std::abs(y - kH / 2) <= 2 ? redInMiddleRow : redElsewhere)++;
    }
  EXPECT_GT(redInMiddleRow, kW - 4);
  EXPECT_EQ(redElsewhere, 0);
}

}  // namespace
}  // namespace inertia::viewer
