// The "articulations" section of scene files (src/io/articulations_section.cpp): inline links
// read into the model, shapes and state the file gives, built into a World whose link bodies
// are named ARTICULATION/LINK, and every error named by its JSON pointer and reason.
#include <gtest/gtest.h>

#include <string>

#include "inertia/io/scene.h"
#include "scene_error_test_util.h"

using namespace inertia;
using inertia::io::parseScene;
using inertia::io::SceneError;
using inertia::test::BadCase;
using inertia::test::errorOf;

namespace {

const char* kPendulum = R"({
  "articulations": [ { "name": "pendulum", "base": "fixed", "position": [0, 2, 0],
    "links": [ { "name": "l1", "parent": null,
                 "joint": { "type": "revolute", "axis": [0, 0, 1], "limits": [-1, 1],
                            "damping": 0.5, "q": 0.5 },
                 "mass": 1, "com": [0.5, 0, 0], "inertia": [0.01, 0.1, 0.1],
                 "shapes": [ { "type": "sphere", "radius": 0.1, "position": [1, 0, 0] } ] },
               { "name": "l2", "parent": "l1",
                 "joint": { "type": "prismatic", "axis": [1, 0, 0],
                            "origin": { "position": [1, 0, 0] } },
                 "shapes": [ { "type": "box", "half_extents": [0.1, 0.1, 0.1],
                               "material": { "density": 500 } } ] } ],
    "qd": { "l2": 0.25 }, "drives": { "l2": { "stiffness": 10, "damping": 1 } } } ] })";

}  // namespace

TEST(ArticulationsSection, ReadsLinksJointsShapesAndState) {
  const io::Scene scene = parseScene(kPendulum, "test.json");
  ASSERT_EQ(scene.articulations.size(), 1u);
  const WorldArticulationSettings& s = scene.articulations[0].settings;
  EXPECT_EQ(s.model.linkCount(), 2);
  EXPECT_EQ(s.model.nv(), 2);
  EXPECT_EQ(s.base.p, Vec3(0, 2, 0));
  EXPECT_EQ(s.q(0), Real(0.5));
  EXPECT_EQ(s.qd(1), Real(0.25));
  EXPECT_EQ(s.model.lower()(0), Real(-1));
  EXPECT_EQ(s.model.damping()(0), Real(0.5));
  EXPECT_EQ(s.model.drives()[1].stiffness, Real(10));
  EXPECT_EQ(s.model.link(0).mass, Real(1));
  // l2's mass from its box: 500 kg/m^3 times 0.008 m^3.
  EXPECT_NEAR(s.model.link(1).mass, Real(4), Real(1e-5));
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[1].link, 1);
  EXPECT_FALSE(s.selfCollision);  // off unless the file says so
}

TEST(ArticulationsSection, SelfCollisionIsOptIn) {
  const io::Scene scene = parseScene(R"({"articulations": [{"name": "a", "self_collision": true,
      "links": [{"name": "l", "joint": {"type": "revolute"}, "mass": 1}]}]})",
                                     "test.json");
  EXPECT_TRUE(scene.articulations[0].settings.selfCollision);
}

// Built, the links are bodies named ARTICULATION/LINK at the joints' poses: l1 turned by 0.5
// rad about z at (0, 2, 0), so its sphere's centre (1, 0, 0) is at (cos 0.5, 2 + sin 0.5, 0).
TEST(ArticulationsSection, InstantiatesLinkBodiesNamedArticulationSlashLink) {
  auto world = io::instantiate(parseScene(kPendulum, "test.json"));
  ASSERT_EQ(world->articulations().size(), 1u);
  const ArticulationId id = world->articulations()[0];
  const BodyId l1 = world->linkBody(id, 0);
  EXPECT_EQ(world->rigidBodies().name(l1), "pendulum/l1");
  EXPECT_EQ(world->rigidBodies().name(world->linkBody(id, 1)), "pendulum/l2");
  const Vec3 ball = world->transform(l1).apply(Vec3(1, 0, 0));
  EXPECT_NEAR(ball.x(), std::cos(Real(0.5)), Real(1e-6));
  EXPECT_NEAR(ball.y(), 2 + std::sin(Real(0.5)), Real(1e-6));
  world->step(Real(1) / 60);
  EXPECT_TRUE(world->articulation(id).q().allFinite());
}

TEST(ArticulationsSection, FloatingBaseStartsAtThePosition) {
  const io::Scene scene = parseScene(R"({"articulations": [{"name": "crate", "base": "floating",
      "position": [1, 2, 3], "links": [{"name": "body", "mass": 2,
      "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}]}]})",
                                     "test.json");
  const WorldArticulationSettings& s = scene.articulations[0].settings;
  EXPECT_EQ(s.model.nq(), 7);
  EXPECT_EQ(s.q.head<3>(), Vec3(1, 2, 3));
  EXPECT_EQ(s.q(3), Real(1));  // identity orientation, w first
}

class BadArticulation : public testing::TestWithParam<BadCase> {};

TEST_P(BadArticulation, NamesThePointerAndTheReason) {
  const BadCase& c = GetParam();
  SceneError e = errorOf(std::string(R"({"articulations": [)") + c.text + "]}");
  EXPECT_EQ(e.pointer(), c.pointer) << e.what();
  EXPECT_NE(e.reason().find(c.words), std::string::npos) << e.what();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadArticulation,
    testing::Values(
        BadCase{R"({"name": "a", "links": [], "colour": 1})", "/articulations/0/colour", "unknown"},
        BadCase{R"({"name": "a", "links": []})", "/articulations/0/links", "at least one link"},
        BadCase{R"({"name": "a", "urdf": "robot.urdf", "links": []})", "/articulations/0/links",
                "not both"},
        BadCase{R"({"name": "a", "urdf": "absent.urdf"})", "/articulations/0/urdf",
                "absent.urdf: no such file"},
        BadCase{R"({"name": "a", "base": "wobbly", "links": []})", "/articulations/0/base",
                "fixed"},
        BadCase{R"({"name": "a", "links": [{"name": "l", "joint": {"type": "hinge"}, "mass": 1}]})",
                "/articulations/0/links/0/joint/type", "unknown joint type"},
        BadCase{R"({"name": "a", "links": [{"name": "l", "parent": "x",
                    "joint": {"type": "revolute"}, "mass": 1}]})",
                "/articulations/0/links/0/parent", "no earlier link"},
        BadCase{R"({"name": "a", "links": [{"name": "l", "joint": {"type": "revolute"}}]})",
                "/articulations/0/links/0", "mass"},
        BadCase{R"({"name": "a", "links": [{"name": "l", "joint": {"type": "revolute",
                    "limits": [1, -1]}, "mass": 1}]})",
                "/articulations/0/links/0/joint/limits", "lower"},
        BadCase{R"({"name": "a", "links": [{"name": "l", "joint": {"type": "revolute"},
                    "mass": -1}]})",
                "/articulations/0/links/0/mass", ""},
        BadCase{R"({"name": "a", "links": [{"name": "l", "joint": {"type": "fixed", "limits":
                    [0, 1]}, "mass": 1}]})",
                "/articulations/0/links/0", "limits"},
        BadCase{R"({"name": "a", "q": {"m": 1}, "links": [{"name": "l",
                    "joint": {"type": "revolute"}, "mass": 1}]})",
                "/articulations/0/q/m", "no link named"},
        BadCase{R"({"name": "a", "links": [{"name": "l", "joint": {"type": "revolute"},
                    "mass": 1, "shapes": [{"type": "plane", "normal": [0, 1, 0]}]}]})",
                "/articulations/0/links/0/shapes/0", "plane"},
        BadCase{R"({"name": "a", "self_collision": 1, "links": [{"name": "l",
                    "joint": {"type": "revolute"}, "mass": 1}]})",
                "/articulations/0/self_collision", "expected true or false"}));

// Two articulations of one name, or a link body named as a body already is, clash.
TEST(ArticulationsSection, NamesAreUnique) {
  SceneError e = errorOf(R"({"bodies": [{"name": "a/l"}], "articulations": [{"name": "a",
      "links": [{"name": "l", "joint": {"type": "revolute"}, "mass": 1}]}]})");
  EXPECT_EQ(e.pointer(), "/articulations/0/name") << e.what();
  EXPECT_NE(e.reason().find("duplicate"), std::string::npos) << e.what();
}
