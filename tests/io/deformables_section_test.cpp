// The "deformables" section of scene files: each generator's keys, and errors that name the
// JSON pointer.
#include <gtest/gtest.h>

#include <cmath>

#include "inertia/io/scene.h"

namespace inertia::io {
namespace {

Scene parse(const std::string& deformables) {
  return parseScene(R"({"deformables": [)" + deformables + "]}", "test.json");
}

// The error's pointer for a scene that must be refused.
std::string pointerOf(const std::string& deformables) {
  try {
    parse(deformables);
  } catch (const SceneError& e) {
    return e.pointer();
  }
  return "(accepted)";
}

TEST(DeformablesSection, ClothAsInTheDesignDocument) {
  const Scene s = parse(
      R"({ "name": "flag", "type": "cloth", "position": [0, 3, 0], "orientation": [1, 0, 0, 0],
      "size": [2, 1], "resolution": [40, 20], "mass": 0.5, "thickness": 0.01,
      "stiffness": { "stretch": 5000, "shear": 500, "bend": 5 }, "damping": 0.01,
      "integrator": "implicit_euler", "self_collision": true, "friction": 0.3,
      "pinned": [0, 20], "attach": [], "tear_strain": 0,
      "fields": [ { "type": "gravity" }, { "type": "wind", "velocity": [3, 0, 0], "k": 0.01 } ] })");
  ASSERT_EQ(s.deformables.size(), 1u);
  const DeformableDesc& d = s.deformables[0];
  EXPECT_EQ(d.settings.name, "flag");
  EXPECT_EQ(d.settings.integrator, ode::Method::BackwardEuler);
  EXPECT_TRUE(d.settings.selfCollision);
  EXPECT_EQ(d.model.vertexCount(), 41u * 21u);
  EXPECT_FLOAT_EQ(d.model.masses[0] * Real(41 * 21), Real(0.5));
  EXPECT_EQ(d.model.pinned, (std::vector<std::uint32_t>{0, 20}));
  EXPECT_TRUE(d.model.positions[0].isApprox(Vec3(-1, 3, -0.5f)));
  EXPECT_EQ(d.fields.size(), 2u);
  auto world = instantiate(s);
  ASSERT_EQ(world->deformables().size(), 1u);
  EXPECT_EQ(world->deformable(world->deformables()[0]).fields().size(), 2u);
}

// "attach" holds a vertex to a named body's point, both ways, in the instantiated world.
TEST(DeformablesSection, AttachmentsToBodies) {
  const Scene s = parseScene(R"({
    "bodies": [ { "name": "weight", "type": "dynamic", "position": [0, -1, 0],
                  "shapes": [ { "type": "sphere", "radius": 0.1 } ] } ],
    "deformables": [ { "type": "rope", "from": [0, 0, 0], "to": [0, -1, 0], "segments": 4,
                       "pinned": [0],
                       "attach": [ { "vertex": 4, "body": "weight", "anchor": [0, 0.1, 0],
                                     "stiffness": 3000, "damping": 2 } ] } ] })",
                             "test.json");
  ASSERT_EQ(s.deformables[0].attachments.size(), 1u);
  EXPECT_EQ(s.deformables[0].attachments[0].vertex, 4u);
  EXPECT_FLOAT_EQ(s.deformables[0].attachments[0].stiffness, 3000);
  auto world = instantiate(s);
  const Deformable& d = world->deformable(world->deformables()[0]);
  ASSERT_EQ(d.attachments().size(), 1u);
  EXPECT_EQ(d.attachments()[0].body, world->rigidBodies().bodies()[0]);
  EXPECT_TRUE(d.attachments()[0].anchor.isApprox(Vec3(0, Real(0.1), 0)));
}

TEST(DeformablesSection, RopeSoftBodiesAndMesh) {
  const Scene s = parse(R"(
    { "type": "rope", "from": [0, 0, 0], "to": [0, -2, 0], "segments": 8, "pinned": [0], "integrator": "rk4" },
    { "type": "soft_body", "shape": { "type": "box", "half_extents": [0.5, 0.5, 0.5] }, "resolution": [2, 3, 4] },
    { "type": "soft_body", "shape": { "type": "sphere", "radius": 0.5 }, "resolution": 1 },
    { "type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "springs": [[0, 1], [1, 2], [2, 0]],
      "triangles": [[0, 1, 2]], "mass": 0.3 })");
  ASSERT_EQ(s.deformables.size(), 4u);
  EXPECT_EQ(s.deformables[0].model.vertexCount(), 9u);
  EXPECT_EQ(s.deformables[0].settings.integrator, ode::Method::Rk4);
  EXPECT_EQ(s.deformables[0].settings.name, "0");
  EXPECT_EQ(s.deformables[1].model.vertexCount(), 3u * 4 * 5);
  EXPECT_EQ(s.deformables[2].model.vertexCount(), 43u);
  EXPECT_EQ(s.deformables[3].model.springs.size(), 3u);
  EXPECT_FLOAT_EQ(s.deformables[3].model.springs[0].restLength, 1);
}

// A unit cube as an inline mesh shape (12 faces, counter-clockwise from outside).
constexpr const char* kInlineCube = R"("vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                                             [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    "triangles": [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [3, 7, 6], [3, 6, 2], [0, 4, 7], [0, 7, 3], [1, 2, 6], [1, 6, 5]])";

TEST(DeformablesSection, HairAndSoftBodiesFromMeshes) {
  const Scene s = parse(R"(
    { "type": "hair", "position": [0, 1.7, 0], "radius": 0.1, "cap_angle": 1.2, "strands": 30,
      "segments": 5, "length": 0.2, "mass": 0.01 },
    { "type": "soft_body", "position": [0, 1, 0], "resolution": 2,
      "shape": { "type": "mesh", )" +
                        std::string(kInlineCube) + R"( } })");
  ASSERT_EQ(s.deformables.size(), 2u);
  const MassSpringModel& hair = s.deformables[0].model;
  EXPECT_EQ(hair.vertexCount(), 30u * 6u);
  EXPECT_EQ(hair.pinned.size(), 30u);
  EXPECT_NEAR((hair.positions[0] - Vec3(0, Real(1.7), 0)).norm(), 0.1, 1e-6);
  const MassSpringModel& cube = s.deformables[1].model;
  EXPECT_EQ(cube.vertexCount(), 8u + 8u);  // the corners, then 2 x 2 x 2 cell centres
  EXPECT_EQ(cube.triangles.size(), 12u);
  EXPECT_TRUE(cube.positions[8].isApprox(Vec3(Real(0.25), Real(1.25), Real(0.25))));
}

// Hair's "root_body": the roots are attached to the head where they start, not pinned, so a
// turning head carries them round: after a quarter turn at 1 rad/s a root is where the turn
// puts it, within the spring's lag (m w^2 r / k, 1e-10 m here) and the float positions'
// rounding, eps |x| per step at most (314 steps: 4e-5 m; 6e-8 measured).
// The head is smaller than the roots' sphere by more than twice the thickness, so that the
// roots do not also rest on it.
TEST(DeformablesSection, HairRootsFollowTheirBody) {
  const Scene s = parseScene(R"({
    "world": { "gravity": [0, 0, 0], "dt": 0.005 },
    "bodies": [ { "name": "head", "type": "kinematic", "position": [0, 1, 0],
                  "orientation": [0.9238795, 0, 0.3826834, 0], "angular_velocity": [0, 1, 0],
                  "shapes": [ { "type": "sphere", "radius": 0.09 } ] } ],
    "deformables": [ { "type": "hair", "position": [0, 1, 0], "radius": 0.1, "cap_angle": 1.2,
                       "strands": 6, "segments": 4, "length": 0.1, "mass": 0.001,
                       "thickness": 0.004,
                       "root_body": "head", "root_stiffness": 2e4 } ] })",
                             "test.json");
  const DeformableDesc& d = s.deformables[0];
  EXPECT_TRUE(d.model.pinned.empty());
  ASSERT_EQ(d.attachments.size(), 6u);
  EXPECT_FLOAT_EQ(d.attachments[0].stiffness, 2e4f);
  auto world = instantiate(s);
  const Deformable& hair = world->deformable(world->deformables()[0]);
  const Vec3 root = hair.position(5);  // strand 1's root
  const Real quarter = Real(3.14159265358979 / 2);
  const int steps = int(std::lround(quarter / 0.005));
  for (int i = 0; i < steps; ++i) world->step(Real(0.005));
  const Real turned = Real(steps) * Real(0.005);
  const Vec3 expected =
      Vec3(0, 1, 0) + Quat(Eigen::AngleAxis<Real>(turned, Vec3::UnitY())) * (root - Vec3(0, 1, 0));
  EXPECT_GT((root - expected).norm(), Real(0.05));  // it moved
  EXPECT_LT((hair.position(5) - expected).norm(), Real(4e-5));
}

TEST(DeformablesSection, ErrorsNameTheJsonPointer) {
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "sise": [1, 1]})"), "/deformables/0/sise");
  EXPECT_EQ(pointerOf(R"({"type": "sheet"})"), "/deformables/0/type");
  EXPECT_EQ(pointerOf(R"({"type": "rope", "from": [0, 0, 0], "to": [1, 0, 0], "size": [1, 1]})"),
            "/deformables/0/size");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "resolution": [4, 0]})"), "/deformables/0/resolution/1");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "resolution": [2, 2], "pinned": [0, 9]})"),
            "/deformables/0/pinned/1");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "stiffness": {"stretch": -1}})"),
            "/deformables/0/stiffness/stretch");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "integrator": "leapfrog"})"),
            "/deformables/0/integrator");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "self_collision": 1})"),
            "/deformables/0/self_collision");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "attach": [{"vertex": 0}]})"),
            "/deformables/0/attach/0");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "attach": [{"vertex": 0, "body": "pole"}]})"),
            "/deformables/0/attach/0/body");
  EXPECT_EQ(pointerOf(R"({"type": "cloth", "resolution": [2, 2], "attach": [{"vertex": 9}]})"),
            "/deformables/0/attach/0/vertex");
  EXPECT_EQ(pointerOf(R"({"type": "rope", "from": [0, 0, 0], "to": [0, 0, 0]})"), "/deformables/0");
  EXPECT_EQ(pointerOf(R"({"type": "hair", "root_body": "head"})"), "/deformables/0/root_body");
  EXPECT_EQ(pointerOf(R"({"type": "hair", "root_stiffness": 10})"),
            "/deformables/0/root_stiffness");
  EXPECT_EQ(pointerOf(R"({"type": "rope", "from": [0, 0, 0], "to": [1, 0, 0], "root_body": "a"})"),
            "/deformables/0/root_body");
  EXPECT_EQ(pointerOf(R"({"type": "soft_body", "shape": {"type": "cone"}})"),
            "/deformables/0/shape/type");
  // A cube without its last face is not closed.
  std::string open(kInlineCube);
  open.erase(open.rfind(", [1, 6, 5]"), std::string(", [1, 6, 5]").size());
  EXPECT_EQ(pointerOf(R"({"type": "soft_body", "shape": {"type": "mesh", )" + open + "}}"),
            "/deformables/0/shape");
  EXPECT_EQ(pointerOf(R"({"type": "soft_body", "shape": {"type": "mesh", "obj": "none.obj"}})"),
            "/deformables/0/shape/obj");
  EXPECT_EQ(pointerOf(R"({"type": "hair", "strands": 0})"), "/deformables/0/strands");
  EXPECT_EQ(pointerOf(R"({"type": "hair", "cap_angle": 4})"), "/deformables/0/cap_angle");
  EXPECT_EQ(
      pointerOf(R"({"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0]], "springs": [[0, 2]]})"),
      "/deformables/0/springs/0/1");
  EXPECT_EQ(
      pointerOf(R"({"type": "cloth"}, {"type": "cloth", "fields": [{"type": "drag", "k": -1}]})"),
      "/deformables/1/fields/0/k");
}

}  // namespace
}  // namespace inertia::io
