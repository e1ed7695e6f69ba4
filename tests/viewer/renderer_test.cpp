// Drawing worlds offscreen: shapes appear where the camera sees them, in their colours,
// and particles are drawn.
#include "renderer.h"

#include <gtest/gtest.h>

#include "inertia/deformable/generators.h"
#include "offscreen.h"

namespace inertia::viewer {
namespace {

constexpr int kW = 96, kH = 72;

struct Image {
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * kW + x)]; }
  // Centroid (x, y) of pixels where red dominates (r > 2 g and r > 2 b).
  Eigen::Vector2d redCentroid(int* count = nullptr) const {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int n = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const std::uint8_t* p = at(x, y);
        if (p[0] > 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2]) sum += Eigen::Vector2d(x, y), ++n;
      }
    if (count) *count = n;
    return n ? Eigen::Vector2d(sum / n) : Eigen::Vector2d(-1, -1);
  }
};

class RendererTest : public testing::Test {
 protected:
  Image draw(const World& world, const CameraView& camera) {
    target_.bind();
    renderer_.draw(world, camera, kW, kH);
    return {target_.readRgb()};
  }
  CameraView camera() {
    CameraView c;
    c.position = {0, 2, 10};
    c.target = {0, 2, 0};
    return c;
  }
  EglContext context_;
  OffscreenTarget target_{kW, kH, 1};
  Renderer renderer_;
};

TEST_F(RendererTest, EmptyWorldIsTheBackground) {
  World world;
  const Image img = draw(world, camera());
  const Eigen::Vector3f bg = renderer_.style().background * 255;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(img.at(kW / 2, kH / 2)[k], bg[k], 1.5);
}

TEST_F(RendererTest, BodyIsDrawnInItsColourWhereItIs) {
  World world;
  BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{{0, 1, 0}, 0});
  BodyId ball = world.createBody({.position = {0, 3, 0}});
  world.addShape(ball, Sphere{Real(0.6)});
  renderer_.setShapeColors({{}, {Vec3(1, 0, 0)}});
  int count = 0;
  const Eigen::Vector2d high = draw(world, camera()).redCentroid(&count);
  EXPECT_GT(count, 30);
  EXPECT_NEAR(high.x(), kW / 2.0, 1.5);
  EXPECT_LT(high.y(), kH / 2.0);  // above the target height: upper half of the image
  world.rigidBodies().setTransform(ball, {Vec3(0, 1, 0), Quat::Identity()});
  const Eigen::Vector2d low = draw(world, camera()).redCentroid();
  EXPECT_GT(low.y(), kH / 2.0);
  // The ground plane (grey, with a grid) fills the bottom of the image.
  const Image image = draw(world, camera());
  const std::uint8_t* bottom = image.at(5, kH - 2);
  EXPECT_LT(std::abs(int(bottom[0]) - int(bottom[2])), 30);
}

TEST_F(RendererTest, GivenPosesAndSleepingColourAreDrawn) {
  World world;
  BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{{0, 1, 0}, 0});
  BodyId ball = world.createBody({.position = {0, 3, 0}});
  world.addShape(ball, Sphere{Real(0.6)}, {}, {Vec3(0.5, 0, 0), Quat::Identity()});
  renderer_.setShapeColors({{}, {Vec3(1, 0, 0)}});
  const Eigen::Vector2d now = [&] {
    target_.bind();
    renderer_.draw(world, camera(), kW, kH);
    return Image{target_.readRgb()}.redCentroid();
  }();
  // The same body drawn at a given pose 2 m lower and 2 m to the left: its offset shape follows.
  const std::vector<Transform> poses = {world.transform(ground),
                                        {Vec3(-2, 1, 0), Quat::Identity()}};
  target_.bind();
  renderer_.draw(world, camera(), kW, kH, poses);
  int count = 0;
  const Eigen::Vector2d moved = Image{target_.readRgb()}.redCentroid(&count);
  EXPECT_GT(count, 30);
  EXPECT_LT(moved.x(), now.x() - 5);
  EXPECT_GT(moved.y(), now.y() + 5);
  EXPECT_TRUE(world.transform(ball).p.isApprox(Vec3(0, 3, 0)));  // drawing moves nothing

  // A sleeping body takes the sleeping colour when one is set (blue here: no red left).
  for (int i = 0; i < 400 && world.rigidBodies().isAwake(ball); ++i) world.step(Real(1.0 / 60));
  ASSERT_FALSE(world.rigidBodies().isAwake(ball));
  renderer_.style().sleepingColor = Eigen::Vector3f(0, 0, 1);
  count = 0;
  draw(world, camera()).redCentroid(&count);
  EXPECT_EQ(count, 0);
  renderer_.style().sleepingColor.reset();
  draw(world, camera()).redCentroid(&count);
  EXPECT_GT(count, 30);
}

TEST_F(RendererTest, EveryShapeTypeDraws) {
  std::vector<Vec3> cube;
  for (int i = 0; i < 8; ++i)
    cube.emplace_back(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  const std::vector<Shape> shapes = {
      Sphere{Real(0.5)},
      Capsule{Real(0.3), Real(0.4)},
      Box{Vec3(0.4, 0.5, 0.4)},
      Cylinder{Real(0.5), Real(0.5)},
      ConvexHull(cube),
      Compound({{Box{Vec3::Constant(Real(0.3))}, Transform{}},
                {Sphere{Real(0.3)}, {Vec3(0, 0.5, 0), Quat::Identity()}}})};
  for (const Shape& s : shapes) {
    World world;
    BodyId b = world.createBody({.position = {0, 2, 0}});
    world.addShape(b, s);
    renderer_.setShapeColors({{Vec3(1, 0, 0)}});
    int count = 0;
    draw(world, camera()).redCentroid(&count);
    EXPECT_GT(count, 20) << shapeTypeName(s.type());
  }
  World terrain;
  BodyId t = terrain.createBody({.type = BodyType::Static, .position = {-2, 1, -2}});
  terrain.addShape(t, HeightField({{0, 0.5f, 0}, {0, 1, 0}, {0, 0.5f, 0}}, Real(2)));
  renderer_.setShapeColors({{Vec3(1, 0, 0)}});
  int count = 0;
  draw(terrain, camera()).redCentroid(&count);
  EXPECT_GT(count, 20) << "heightfield";
}

TEST_F(RendererTest, ParticlesAreDrawn) {
  World world;
  ParticleSystem& ps = world.particleSystem(world.createParticleSystem({.capacity = 64}));
  EmitterSettings e;
  e.shape = EmitterShape::Box;
  e.pose.p = Vec3(0, 2, 0);
  e.halfExtents = Vec3(1, 1, 0.1);
  e.burst = 64;
  e.speed = {0, 0};
  e.size = {Real(0.08), Real(0.08)};
  e.colorMin = e.colorMax = Vec3(1, 0, 0);
  ps.addEmitter(e);
  world.step(Real(0.001));
  int count = 0;
  const Eigen::Vector2d c = draw(world, camera()).redCentroid(&count);
  EXPECT_GT(count, 64);
  EXPECT_NEAR(c.x(), kW / 2.0, 6);
  EXPECT_NEAR(c.y(), kH / 2.0, 6);
  renderer_.style().particles = false;
  draw(world, camera()).redCentroid(&count);
  EXPECT_EQ(count, 0);
}

TEST(RendererColors, DefaultColoursAreDeterministicAndDistinct) {
  EXPECT_EQ(defaultBodyColor(3, BodyType::Dynamic), defaultBodyColor(3, BodyType::Dynamic));
  EXPECT_GT(
      (defaultBodyColor(0, BodyType::Dynamic) - defaultBodyColor(1, BodyType::Dynamic)).norm(),
      0.1f);
  const Eigen::Vector3f s = defaultBodyColor(5, BodyType::Static);
  EXPECT_NEAR(s.x(), s.z(), 0.05f);  // grey
}

// A deformable is drawn: a cloth turned to face the camera covers the image's centre, which is
// the background without it.
TEST_F(RendererTest, ClothIsDrawnFacingTheCamera) {
  World world;
  const Eigen::Vector3f bg = renderer_.style().background * 255;
  const auto differs = [&](const Image& image) {
    const std::uint8_t* p = image.at(kW / 2, kH / 2);
    return std::abs(p[0] - bg[0]) + std::abs(p[1] - bg[1]) + std::abs(p[2] - bg[2]) > 30;
  };
  EXPECT_FALSE(differs(draw(world, camera())));
  const Quat upright(Eigen::AngleAxis<Real>(Real(1.5707963), Vec3::UnitX()));
  world.createDeformable({}, cloth({.pose = {Vec3(0, 2, 0), upright},
                                    .size = {2, 2},
                                    .resolution = {4, 4}}));
  EXPECT_TRUE(differs(draw(world, camera())));
}

}  // namespace
}  // namespace inertia::viewer
