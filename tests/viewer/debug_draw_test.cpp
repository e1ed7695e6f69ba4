// Debug lines: which lines each toggle adds (contacts, bounds, velocities, centres of mass),
// and the GL line program drawing them (offscreen, EGL).
#include "debug_draw.h"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <vector>

#include "camera.h"
#include "inertia/collision/mesh_bvh.h"
#include "inertia/geometry/bounds.h"
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

// The corners of the boxes drawn: each box's 12 edges start at its corners, so the component
// minima and maxima over a box's lines are its bounds.
std::vector<Aabb> drawnBoxes(const DebugLines& lines) {
  std::vector<Aabb> boxes;
  for (std::size_t first = 0; first + 12 <= lines.lineCount(); first += 12) {
    Aabb b{Vec3::Constant(Real(1e30)), Vec3::Constant(Real(-1e30))};
    for (std::size_t i = first; i < first + 12; ++i)
      for (int end = 0; end < 2; ++end) {
        const float* v = &lines.vertices[12 * i + 6 * std::size_t(end)];
        const Vec3 p(v[0], v[1], v[2]);
        b.lower = b.lower.cwiseMin(p);
        b.upper = b.upper.cwiseMax(p);
      }
    boxes.push_back(b);
  }
  return boxes;
}

TEST(DebugDraw, BroadPhaseTreeHasEveryNodeAndContainsTheShapes) {
  Scene s;
  DebugLines lines;
  buildDebugLines(s.world, {.broadPhaseTree = true}, 1, lines);
  // Two proxies (the plane is kept out of the tree): two leaves under one root.
  ASSERT_EQ(lines.lineCount(), 12u * 3);
  const std::vector<Aabb> boxes = drawnBoxes(lines);
  const RigidBodySystem& rb = s.world.rigidBodies();
  // The root (drawn first) holds the leaves. A leaf holds its shape as it was when the last
  // step began: the resting box lies inside one now; the falling ball, which has moved since,
  // at least overlaps one.
  for (std::size_t k = 1; k < boxes.size(); ++k) EXPECT_TRUE(boxes[0].contains(boxes[k]));
  auto bounds = [&](BodyId body) {
    const ShapeId shape = rb.shapes(body)[0];
    return worldBounds(rb.collider(shape).shape(), rb.shapeTransform(shape));
  };
  EXPECT_TRUE(boxes[1].contains(bounds(s.box)) || boxes[2].contains(bounds(s.box)));
  EXPECT_TRUE(boxes[1].overlaps(bounds(s.ball)) || boxes[2].overlaps(bounds(s.ball)));
}

TEST(DebugDraw, MeshBvhDrawsItsLevelsPosedWithTheShape) {
  World world;
  // A 4 x 4 grid of squares (32 triangles) turned a quarter turn about y and raised by 2 m.
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) vertices.emplace_back(Real(i), 0, Real(j));
  for (std::uint32_t i = 0; i < 4; ++i)
    for (std::uint32_t j = 0; j < 4; ++j) {
      const std::uint32_t a = i * 5 + j;
      triangles.push_back({a, a + 1, a + 6});
      triangles.push_back({a, a + 6, a + 5});
    }
  const BodyId body = world.createBody(
      {.type = BodyType::Static,
       .position = {0, 2, 0},
       .orientation = Quat(Eigen::AngleAxis<Real>(Real(std::numbers::pi / 2), Vec3::UnitY()))});
  world.addShape(body, TriangleMesh(vertices, triangles));
  DebugLines root;
  buildDebugLines(world, {.meshBvh = true, .bvhDepth = 0}, 1, root);
  ASSERT_EQ(root.lineCount(), 12u);
  // The root box is the grid's bounds [0, 4] x [0, 0] x [0, 4], turned: x -> -z, z -> x. The
  // BVH pads its boxes by 16 ulps of the mesh's size, and the pose rounds a few ulps more:
  // 64 ulps of 4 m per corner.
  const Aabb b = drawnBoxes(root)[0];
  const double tol = 64 * std::numeric_limits<Real>::epsilon() * 4;
  EXPECT_LT((b.lower - Vec3(0, 2, -4)).norm(), tol);
  EXPECT_LT((b.upper - Vec3(4, 2, 0)).norm(), tol);
  // Every level: one box per node of the hierarchy.
  const MeshBvh* bvh = world.rigidBodies().collider(world.rigidBodies().shapes(body)[0]).meshBvh();
  ASSERT_NE(bvh, nullptr);
  DebugLines all;
  buildDebugLines(world, {.meshBvh = true, .bvhDepth = MeshBvh::kMaxDepth}, 1, all);
  EXPECT_EQ(all.lineCount(), 12 * bvh->nodes().size());
  EXPECT_GT(bvh->nodes().size(), 3u);
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

// A hinged pendulum: B's bone to its anchor at the pivot, the pivot's cross, the hinge axis
// through it, and the two limit spokes perpendicular to the axis; broken, only red crosses.
TEST(DebugDraw, JointsBonesAxisAndLimits) {
  World world;
  const BodyId bob = world.createBody({.position = {0, -1, 0}});
  world.addShape(bob, Sphere{Real(0.1)});
  const JointId j = world.createJoint(HingeJointSettings{
      .bodyB = bob, .anchorB = {0, 1, 0}, .limits = JointLimits{Real(-0.5), Real(0.5)}});
  DebugLines lines;
  buildDebugLines(world, {.joints = true}, 1, lines);
  ASSERT_EQ(lines.lineCount(), 7u);
  // The bone: from the bob's centre to the pivot.
  EXPECT_TRUE(Eigen::Vector3f(lines.vertices[0], lines.vertices[1], lines.vertices[2])
                  .isApprox(Eigen::Vector3f(0, -1, 0), 1e-5f));
  int spokes = 0;
  for (std::size_t i = 0; i < lines.lineCount(); ++i) {
    const float* v = &lines.vertices[12 * i];
    if (v[3] != 1.0f) continue;  // the limit colour's red channel
    const Eigen::Vector3f d(v[6] - v[0], v[7] - v[1], v[8] - v[2]);
    EXPECT_NEAR(d.z(), 0, 1e-6);  // perpendicular to the hinge axis z
    EXPECT_NEAR(d.norm(), 0.3, 1e-5);
    ++spokes;
  }
  EXPECT_EQ(spokes, 2);
  world.rigidBodies().setJointEnabled(j, false);
  lines.clear();
  buildDebugLines(world, {.joints = true}, 1, lines);
  EXPECT_EQ(lines.lineCount(), 6u);
}

}  // namespace
}  // namespace inertia::viewer
