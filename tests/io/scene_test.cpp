#include "inertia/io/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "scene_error_test_util.h"

using namespace inertia;
using inertia::io::parseScene;
using inertia::io::SceneError;
using inertia::test::BadCase;
using inertia::test::errorOf;

TEST(Scene, DefaultsWhenWorldIsAbsent) {
  io::Scene s = parseScene("{}", "empty.json");
  EXPECT_EQ(s.world.gravity, Vec3(0, Real(-9.81), 0));
  EXPECT_EQ(s.world.substeps, 4);
  EXPECT_EQ(s.world.solver.type, SolverType::SoftStep);
  EXPECT_EQ(s.world.integrator, ode::Method::SymplecticEuler);
  EXPECT_FALSE(s.camera.has_value());
}

TEST(Scene, NamesNeedBeUniqueOnlyAmongTheirKind) {
  // Bodies, joints and particle systems are recorded in files of their own: one name may serve
  // one of each (the duplicates within a kind are BadScene cases).
  io::Scene s = parseScene(R"({"bodies": [{"name": "x"}, {"name": "y"}, {},
                                          {"type": "pyramid", "base": 2},
                                          {"type": "pyramid", "base": 2, "name": "p2"}],
                               "joints": [{"name": "x", "type": "ball", "body_b": "x"}, {"type": "ball", "body_b": "y"}],
                               "particle_systems": [{"name": "x"}, {}]})",
                           "names.json");
  ASSERT_EQ(s.bodies.size(), 9u);
  EXPECT_EQ(s.bodies[2].settings.name, "2");            // unnamed: its index
  EXPECT_EQ(s.bodies[3].settings.name, "pyramid_0_0");  // a generator's: NAME_row_i
  EXPECT_EQ(s.bodies[6].settings.name, "p2_0_0");
  ASSERT_EQ(s.joints.size(), 2u);
  ASSERT_EQ(s.particleSystems.size(), 2u);
  EXPECT_EQ(s.particleSystems[1].settings.name, "1");
}

TEST(Scene, ReadsEveryWorldKey) {
  io::Scene s = parseScene(R"({
    "world": { "gravity": [0, 0, -3.5], "dt": 0.01, "substeps": 2,
               "solver": { "type": "pgs", "iterations": 20, "relax_iterations": 3,
                           "joint_hertz": 60, "joint_damping_ratio": 5 },
               "integrator": "rk4", "threads": 2, "sleeping": false },
    "camera": { "position": [1, 2, 3], "target": [0, 1, 0], "fov": 60 },
    "materials": {}, "bodies": [], "joints": [], "particle_systems": [], "deformables": []
  })", "full.json");
  EXPECT_EQ(s.world.gravity, Vec3(0, 0, Real(-3.5)));
  EXPECT_EQ(s.world.dt, Real(0.01));
  EXPECT_EQ(s.world.substeps, 2);
  EXPECT_EQ(s.world.solver.type, SolverType::Pgs);
  EXPECT_EQ(s.world.solver.iterations, 20);
  EXPECT_EQ(s.world.solver.relaxIterations, 3);
  EXPECT_EQ(s.world.solver.jointHertz, Real(60));
  EXPECT_EQ(s.world.solver.jointDampingRatio, Real(5));
  EXPECT_EQ(s.world.integrator, ode::Method::Rk4);
  EXPECT_EQ(s.world.threads, 2);
  EXPECT_FALSE(s.world.sleeping);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->fov, Real(60));
}

TEST(Scene, EveryIntegratorNameIsAccepted) {
  for (std::string_view name : ode::kMethodNames) {
    io::Scene s = parseScene(R"({"world": {"integrator": ")" + std::string(name) + R"("}})", "i.json");
    EXPECT_EQ(ode::methodName(s.world.integrator), name);
  }
}

// The direct LCP solvers are accepted (they were refused before they were built).
TEST(Scene, LcpSolversAreAccepted) {
  for (std::string_view name : {"lcp_dantzig", "lcp_lemke"}) {
    io::Scene s = parseScene(R"({"world": {"solver": {"type": ")" + std::string(name) + R"("}}})",
                             "s.json");
    EXPECT_EQ(solverName(s.world.solver.type), name);
  }
}

class BadScene : public testing::TestWithParam<BadCase> {};

TEST_P(BadScene, NamesThePointerAndTheReason) {
  const BadCase& c = GetParam();
  SceneError e = errorOf(c.text);
  EXPECT_EQ(e.pointer(), c.pointer) << e.what();
  EXPECT_NE(e.reason().find(c.words), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("test.json"), std::string::npos) << e.what();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadScene,
    testing::Values(
        BadCase{R"({"wrold": {}})", "/wrold", "did you mean \"world\""},
        BadCase{R"({"world": {"dt": -0.01}})", "/world/dt", "out of range"},
        BadCase{R"({"world": {"dt": 0}})", "/world/dt", "out of range"},
        BadCase{R"({"world": {"dt": "fast"}})", "/world/dt", "expected a number, got a string"},
        BadCase{R"({"world": {"gravity": [0, -9.81]}})", "/world/gravity", "3 numbers"},
        BadCase{R"({"world": {"gravity": [0, null, 0]}})", "/world/gravity/1", "expected a number"},
        BadCase{R"({"world": {"substeps": 2.5}})", "/world/substeps", "integer"},
        BadCase{R"({"world": {"substeps": 0}})", "/world/substeps", "out of range"},
        BadCase{R"({"world": {"threads": 18446744073709551615}})", "/world/threads",
                "out of range"},
        BadCase{R"({"world": {"solver": {"type": "magic"}}})", "/world/solver/type",
                "unknown solver"},
        BadCase{R"({"world": {"solver": {"iters": 3}}})", "/world/solver/iters", "unknown key"},
        BadCase{R"({"world": {"solver": {"joint_hertz": 0}}})", "/world/solver/joint_hertz",
                "out of range"},
        BadCase{R"({"world": {"solver": {"joint_damping_ratio": -1}}})",
                "/world/solver/joint_damping_ratio", "out of range"},
        BadCase{R"({"world": {"integrator": "euler"}})", "/world/integrator", "explicit_euler"},
        BadCase{R"({"world": {"sleeping": 1}})", "/world/sleeping", "true or false"},
        BadCase{R"({"world": []})", "/world", "expected an object, got an array"},
        BadCase{R"({"camera": {"position": [1, 1, 1], "target": [1, 1, 1]}})", "/camera",
                "coincide"},
        BadCase{R"({"camera": {"fov": 180.5}})", "/camera/fov", "out of range"},
        BadCase{R"({"bodies": {}})", "/bodies", "expected an array"},
        BadCase{R"({"bodies": [{"type": "rigid"}]})", "/bodies/0/type", "unknown body type"},
        BadCase{
            R"({"bodies": [{"shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]}]})",
            "/bodies/0/shapes/0", "static body"},
        BadCase{
            R"({"bodies": [{"shapes": [{"type": "sphere", "radius": 1, "material": "rubber"}]}]})",
            "/bodies/0/shapes/0/material", "unknown material"},
        BadCase{R"({"materials": {"ice": {"friction": -0.1}}, "bodies": []})",
                "/materials/ice/friction", "out of range"},
        BadCase{R"({"materials": {"ice": {"restitution": 1.5}}})", "/materials/ice/restitution",
                "out of range"},
        BadCase{R"({"bodies": [{"mass": -2}]})", "/bodies/0/mass", "out of range"},
        BadCase{R"({"bodies": [{"inertia": [1, 1, 1]}]})", "/bodies/0/inertia", "needs \"mass\""},
        BadCase{R"({"bodies": [{"velocity": [1, 2]}]})", "/bodies/0/velocity", "3 numbers"},
        BadCase{R"({"bodies": [{"type": "pyramid", "base": 0}]})", "/bodies/0/base",
                "out of range"},
        BadCase{
            R"({"bodies": [{"type": "grid", "counts": [2, 2], "shape": {"type": "sphere", "radius": 1}}]})",
            "/bodies/0/counts", "expected [nx, ny, nz]"},
        BadCase{R"({"bodies": [{"type": "rain", "count": 5, "lower": [0, 0, 0], "upper": [1, -1, 1],
                    "shape": {"type": "sphere", "radius": 1}}]})",
                "/bodies/0/upper", "upper must be"},
        BadCase{
            R"({"bodies": [{"shapes": [{"type": "sphere", "radius": 1, "color": [2, 0, 0]}]}]})",
            "/bodies/0/shapes/0/color", "[0, 1]"},
        BadCase{R"({"world": {"solver": {"type": "lemke"}}})", "/world/solver/type",
                "unknown solver"},
        BadCase{R"({"world": {"a/b~c": 1}})", "/world/a~1b~0c", "unknown key"},
        BadCase{R"([1, 2])", "", "expected an object"},
        BadCase{R"({"particle_systems": [{"capacity": 0}]})", "/particle_systems/0/capacity",
                "out of range"},
        BadCase{R"({"particle_systems": [{"emitters": [{"type": "point", "rate": -5}]}]})",
                "/particle_systems/0/emitters/0/rate", "out of range"},
        BadCase{R"({"particle_systems": [{"emitters": [{"type": "fountain"}]}]})",
                "/particle_systems/0/emitters/0/type", "unknown emitter type"},
        BadCase{R"({"particle_systems": [{"emitters": [{"type": "point", "speed": [5, 1]}]}]})",
                "/particle_systems/0/emitters/0/speed", "exceeds"},
        BadCase{R"({"particle_systems": [{"fields": [{"type": "magnetism"}]}]})",
                "/particle_systems/0/fields/0/type", "unknown field type"},
        BadCase{R"({"particle_systems": [{"fields": [{"type": "drag", "k": -1}]}]})",
                "/particle_systems/0/fields/0/k", "out of range"},
        BadCase{
            R"({"particle_systems": [{"fields": [{"type": "vortex", "angular_speed": 1, "axis": [0, 0, 0]}]}]})",
            "/particle_systems/0/fields/0", "axis"},
        BadCase{R"({"particle_systems": [{"obstacles": [{"type": "sphere", "radius": 0}]}]})",
                "/particle_systems/0/obstacles/0/radius", "out of range"},
        BadCase{R"({"particle_systems": [{"obstacles": [{"type": "box", "radius": 1}]}]})",
                "/particle_systems/0/obstacles/0/radius", "unknown key"},
        BadCase{
            R"({"particle_systems": [{"obstacles": [{"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}]}]})",
            "/particle_systems/0/obstacles/0", "invalid hull"},
        BadCase{R"({"particle_systems": [{"integrator": "leapfrog"}]})",
                "/particle_systems/0/integrator", "unknown integrator"},
        BadCase{R"({"particle_systems": [{"collide_with_bodies": 1}]})",
                "/particle_systems/0/collide_with_bodies", "expected true or false"},
        BadCase{
            R"({"bodies": [{"name": "cart"}], "particle_systems": [{"emitters": [{"type": "point", "attach_to": "kart"}]}]})",
            "/particle_systems/0/emitters/0/attach_to", "no body is named \"kart\""},
        // Issue 21, defect 4: names tell bodies, joints and particle systems apart in
        // recordings; the second holder of a name is refused, named by its pointer.
        BadCase{R"({"bodies": [{"name": "cart"}, {"name": "cart"}],
                    "particle_systems": [{"emitters": [{"type": "point", "attach_to": "cart"}]}]})",
                "/bodies/1/name", "duplicate body name \"cart\", already /bodies/0's"},
        BadCase{R"({"bodies": [{"name": "c", "position": [0, 1, 0]}, {"name": "c"}]})",
                "/bodies/1/name", "duplicate body name \"c\", already /bodies/0's"},
        BadCase{R"({"bodies": [{"name": "1"}, {}]})", "/bodies/1",
                "duplicate body name \"1\" (a name made for it, as it has no \"name\")"},
        BadCase{R"({"bodies": [{"type": "pyramid", "base": 2},
                               {"type": "pyramid", "base": 2, "position": [5, 0, 0]}]})",
                "/bodies/1", "duplicate body name \"pyramid_0_0\" (a name made for it"},
        BadCase{R"({"bodies": [{"type": "tower", "height": 2, "name": "t"},
                               {"type": "grid", "counts": [2, 1, 1], "name": "t",
                                "shape": {"type": "sphere", "radius": 0.1}}]})",
                "/bodies/1/name", "duplicate body name \"t_0\", already /bodies/0's"},
        BadCase{R"({"bodies": [{"type": "ragdoll", "name": "r"},
                               {"type": "ragdoll", "name": "r", "position": [3, 0, 0]}]})",
                "/bodies/1/name", "duplicate body name \"r_"},
        BadCase{R"({"bodies": [{"name": "a"}, {"name": "b"}],
                    "joints": [{"name": "j", "type": "ball", "body_b": "a"},
                               {"name": "j", "type": "ball", "body_a": "a", "body_b": "b"}]})",
                "/joints/1/name", "duplicate joint name \"j\", already /joints/0's"},
        BadCase{R"({"bodies": [{"type": "ragdoll", "name": "r"}],
                    "joints": [{"name": "r_neck", "type": "ball", "body_b": "r_head"}]})",
                "/joints/0/name", "duplicate joint name \"r_neck\", already /bodies/0's"},
        BadCase{R"({"particle_systems": [{"name": "sparks"}, {"name": "sparks"}]})",
                "/particle_systems/1/name", "duplicate particle system name \"sparks\""},
        BadCase{
            R"({"bodies": [{"name": "cart"}], "particle_systems": [{"emitters": [{"type": "point", "attach_to": 0}]}]})",
            "/particle_systems/0/emitters/0/attach_to", "string"}));

// The ragdoll generator's keys.
INSTANTIATE_TEST_SUITE_P(
    Ragdolls, BadScene,
    testing::Values(BadCase{R"({"bodies": [{"type": "ragdoll", "count": 0}]})", "/bodies/0/count",
                            "out of range"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "count": [2, 0, 1]}]})",
                            "/bodies/0/count/1", "out of range"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "count": [2, 2]}]})",
                            "/bodies/0/count", "[nx, ny, nz]"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "count": [100, 10, 11]}]})",
                            "/bodies/0/count", "at most 10000 ragdolls"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "scale": 0}]})", "/bodies/0/scale",
                            "out of range"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "spacing": [1, 2]}]})",
                            "/bodies/0/spacing", "3 numbers"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "joint_friction": -1}]})",
                            "/bodies/0/joint_friction", "out of range"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "orientation": [1, 1, 0, 0]}]})",
                            "/bodies/0/orientation", "unit length"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "material": "bone"}]})",
                            "/bodies/0/material", "unknown material"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "arms": 3}]})", "/bodies/0/arms",
                            "unknown key"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "color": [0, 2, 0]}]})",
                            "/bodies/0/color", "[0, 1]"},
                    BadCase{R"({"bodies": [{"type": "ragdoll", "count": 2}],
                    "joints": [{"type": "ball", "body_b": "ragdoll_head"}]})",
                            "/joints/0/body_b", "no body is named \"ragdoll_head\""}));

TEST(Scene, ParticlesCollideWithBodiesAndRideOnThem) {
  io::Scene s = parseScene(R"({
    "bodies": [ {"name": "ground", "type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
                {"name": "wheel", "type": "kinematic", "position": [0, 1, 0], "angular_velocity": [0, 0, 3],
                 "shapes": [{"type": "cylinder", "radius": 0.5, "half_height": 0.1}]} ],
    "particle_systems": [ { "collide_with_bodies": true,
      "emitters": [ { "type": "point", "position": [0.6, 0, 0], "rate": 100, "attach_to": "wheel" } ] } ] })",
                           "wheel.json");
  const io::ParticleSystemDesc& d = s.particleSystems.at(0);
  EXPECT_TRUE(d.settings.collideWithBodies);
  EXPECT_EQ(d.emitters.at(0).attachToName, "wheel");
  auto world = io::instantiate(s);
  ParticleSystem& ps = world->particleSystem(world->particleSystems().at(0));
  const BodyId wheel = ps.emitter(0).settings().attachTo;
  ASSERT_TRUE(world->isValid(wheel));
  EXPECT_EQ(world->rigidBodies().name(wheel), "wheel");
}

TEST(Scene, ReadsParticleSystems) {
  io::Scene s = parseScene(R"({
    "particle_systems": [ {
      "name": "fountain", "capacity": 5000, "integrator": "rk4", "radius": 0.02,
      "restitution": 0.3, "friction": 0.2, "particle_collisions": true,
      "emitters": [ { "type": "cone", "position": [0, 1, 0], "angle": 0.2, "rate": 100,
                      "burst": 10, "speed": [4, 6], "lifetime": "inf", "mass": 0.001,
                      "color": [[1, 0, 0], [1, 1, 0]], "seed": 3 } ],
      "fields": [ { "type": "gravity", "g": [0, -9.81, 0] }, { "type": "drag", "k": 0.1 },
                  { "type": "vortex", "angular_speed": 2, "region": {"min": [-1, -1, -1], "max": [1, 1, 1]} },
                  { "type": "attractor", "strength": 5, "falloff": "linear" },
                  { "type": "turbulence", "amplitude": 1 }, { "type": "wind", "velocity": [1, 0, 0], "k": 0.5 },
                  { "type": "quadratic_drag", "k": 0.01 } ],
      "obstacles": [ { "type": "plane", "normal": [0, 1, 0], "offset": 0 },
                     { "type": "sphere", "radius": 0.5, "position": [0, 2, 0] },
                     { "type": "box", "half_extents": [1, 0.1, 1], "orientation": [1, 0, 0, 0] } ]
    } ] })", "p.json");
  ASSERT_EQ(s.particleSystems.size(), 1u);
  const io::ParticleSystemDesc& d = s.particleSystems[0];
  EXPECT_EQ(d.settings.name, "fountain");
  EXPECT_EQ(d.settings.capacity, 5000u);
  EXPECT_EQ(d.settings.integrator, ode::Method::Rk4);
  EXPECT_TRUE(d.settings.particleCollisions);
  ASSERT_EQ(d.emitters.size(), 1u);
  EXPECT_EQ(d.emitters[0].shape, EmitterShape::Cone);
  EXPECT_EQ(d.emitters[0].speed.min, 4);
  EXPECT_TRUE(std::isinf(d.emitters[0].lifetime.max));
  EXPECT_EQ(d.emitters[0].size.min, Real(0.02));  // the system's radius
  EXPECT_EQ(d.fields.size(), 7u);
  EXPECT_TRUE(d.fields[2].region.has_value());
  EXPECT_EQ(d.obstacles.size(), 3u);
  auto world = io::instantiate(s);
  EXPECT_EQ(world->particleSystems().size(), 1u);
}

TEST(Scene, ReadsBodiesMaterialsAndGenerators) {
  io::Scene s = parseScene(R"({
    "materials": {"rubber": {"density": 1100, "friction": 0.8, "restitution": 0.9}},
    "bodies": [
      {"name": "ground", "type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
      {"name": "ball", "position": [0, 5, 0], "velocity": [1, 0, 0], "bullet": true,
       "shapes": [{"type": "sphere", "radius": 0.5, "material": "rubber"}]},
      {"type": "pyramid", "base": 3, "half_extents": [0.5, 0.5, 0.5], "position": [10, 0, 0]},
      {"type": "grid", "counts": [2, 1, 2], "spacing": 1.5, "shape": {"type": "box", "half_extents": [0.2, 0.2, 0.2]}}
    ]})", "b.json");
  ASSERT_EQ(s.bodies.size(), 2u + 6u + 4u);
  EXPECT_EQ(s.bodies[0].settings.type, BodyType::Static);
  EXPECT_EQ(s.bodies[1].settings.name, "ball");
  EXPECT_TRUE(s.bodies[1].settings.bullet);
  EXPECT_FLOAT_EQ(s.bodies[1].shapes[0].material.restitution, Real(0.9));
  EXPECT_FLOAT_EQ(s.bodies[1].settings.linearVelocity.x(), 1);
  // The pyramid's top box sits on two rows of unit boxes: centre at 2.5 m.
  EXPECT_FLOAT_EQ(s.bodies[7].settings.position.y(), Real(2.5));
  EXPECT_FLOAT_EQ(s.bodies[11].settings.position.z(), Real(1.5));
  auto world = io::instantiate(s);
  EXPECT_EQ(world->bodyCount(), 12);
}

// The ragdoll generator: the builder's ragdolls, bodies and joints, on a lattice; the joints
// come before the "joints" section's and can name the parts.
TEST(Scene, RagdollGeneratorMakesBodiesAndJoints) {
  io::Scene s = parseScene(R"({
    "materials": {"light": {"density": 500}},
    "bodies": [
      {"name": "ground", "type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
      {"type": "ragdoll", "count": [2, 1, 3], "position": [0, 1, 0], "spacing": [1, 2, 0.7],
       "scale": 1.0, "velocity": [0, 0, 1], "joint_friction": 0.5, "material": "light"},
      {"name": "hook", "type": "static", "position": [0, 3, 0]},
      {"type": "ragdoll", "name": "bob", "position": [5, 2, 0], "scale": 0.5, "color": [1, 0, 0]}
    ],
    "joints": [{"type": "ball", "body_a": "hook", "body_b": "ragdoll_5_head",
                "anchor_a": [1, -1.32, 1.4]}] })",
                           "ragdolls.json");
  constexpr std::size_t kParts = kRagdollParts, kJoints = 10;  // RagdollSettings' doc
  ASSERT_EQ(s.bodies.size(), 1 + 6 * kParts + 1 + kParts);
  ASSERT_EQ(s.joints.size(), 6 * kJoints + kJoints + 1);
  // Numbered along x, then y, then z; the lattice in world axes from `position`.
  EXPECT_EQ(s.bodies[1].settings.name, "ragdoll_0_pelvis");
  EXPECT_TRUE(s.bodies[1].settings.position.isApprox(Vec3(0, 1, 0)));
  EXPECT_EQ(s.bodies[1 + kParts].settings.name, "ragdoll_1_pelvis");
  EXPECT_TRUE(s.bodies[1 + kParts].settings.position.isApprox(Vec3(1, 1, 0)));
  EXPECT_EQ(s.bodies[1 + 5 * kParts].settings.name, "ragdoll_5_pelvis");
  EXPECT_TRUE(s.bodies[1 + 5 * kParts].settings.position.isApprox(Vec3(1, 1, Real(1.4))));
  EXPECT_TRUE(s.bodies[1].settings.linearVelocity.isApprox(Vec3(0, 0, 1)));
  EXPECT_FLOAT_EQ(s.bodies[1].shapes[0].material.density, 500);
  const std::size_t bob = 1 + 6 * kParts + 1;
  EXPECT_EQ(s.bodies[bob].settings.name, "bob_pelvis");  // one ragdoll: no number
  EXPECT_TRUE(s.bodies[bob].settings.position.isApprox(Vec3(5, 2, 0)));
  for (std::size_t i = bob; i < bob + kParts; ++i) {
    ASSERT_TRUE(s.bodies[i].shapes[0].color.has_value());
    EXPECT_EQ(*s.bodies[i].shapes[0].color, Vec3(1, 0, 0));
  }
  EXPECT_FALSE(s.bodies[1].shapes[0].color.has_value());
  // Each ragdoll's joints join its own parts and carry the generator's pointer; the joints
  // section's come last.
  for (std::size_t j = 0; j < 7 * kJoints; ++j) {
    const std::size_t doll = j / kJoints;
    const std::size_t first = doll < 6 ? 1 + doll * kParts : bob;
    SCOPED_TRACE(j);
    EXPECT_EQ(s.joints[j].pointer, doll < 6 ? "/bodies/1" : "/bodies/3");
    ASSERT_TRUE(s.joints[j].bodyA.has_value());
    EXPECT_GE(*s.joints[j].bodyA, first);
    EXPECT_LT(*s.joints[j].bodyA, first + kParts);
    EXPECT_GE(s.joints[j].bodyB, first);
    EXPECT_LT(s.joints[j].bodyB, first + kParts);
  }
  EXPECT_EQ(std::get<HingeJointSettings>(s.joints[0].settings).name, "ragdoll_0_waist");
  EXPECT_EQ(std::get<HingeJointSettings>(s.joints[0].settings).friction, Real(0.5));
  EXPECT_EQ(s.joints.back().pointer, "/joints/0");
  EXPECT_EQ(s.bodies[s.joints.back().bodyB].settings.name, "ragdoll_5_head");

  auto world = io::instantiate(s);
  EXPECT_EQ(world->bodyCount(), int(s.bodies.size()));
  const RigidBodySystem& rb = world->rigidBodies();
  ASSERT_EQ(rb.jointCount(), int(s.joints.size()));
  for (JointId j : rb.joints()) {
    EXPECT_LT(rb.jointError(j).position, Real(1e-5)) << rb.jointName(j);
    EXPECT_LT(rb.jointError(j).angle, Real(1e-5)) << rb.jointName(j);
  }
}

// A joint a generator made that createJoint refuses is reported at the generator.
TEST(Scene, GeneratorJointErrorsNameTheGenerator) {
  io::Scene s = parseScene(R"({"bodies": [{"name": "a"}, {"type": "ragdoll"}]})", "made.json");
  ASSERT_EQ(s.joints.size(), 10u);
  std::get<HingeJointSettings>(s.joints.at(0).settings).axisA = Vec3::Zero();
  try {
    io::instantiate(s);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/bodies/1") << e.what();
    EXPECT_NE(e.reason().find("axisA"), std::string::npos) << e.what();
  }
}

TEST(Scene, SyntaxErrorsGiveLineAndColumn) {
  SceneError e = errorOf("{\n  \"world\": {\n    \"dt\": NaN\n  }\n}");
  EXPECT_EQ(e.pointer(), "");
  // The bad token starts on line 3, column 11.
  EXPECT_EQ(e.file(), "test.json:3:11") << e.what();
  EXPECT_NE(e.reason().find("syntax error"), std::string::npos) << e.what();
}

TEST(Scene, NumberOverflowGivesLineAndColumn) {
  SceneError e = errorOf("{\"world\": {\n \"dt\": 1e999}}");
  EXPECT_EQ(e.file(), "test.json:2:8") << e.what();
  EXPECT_NE(e.reason().find("not a finite number"), std::string::npos) << e.what();
}

TEST(Scene, MissingFileIsNamed) {
  try {
    io::loadScene("/nonexistent/scene.json");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/scene.json");
    EXPECT_NE(e.reason().find("no such file"), std::string::npos);
  }
}

TEST(Scene, ShippedScenesLoad) {
  const char* root = std::getenv("INERTIA_SOURCE_DIR");
  ASSERT_NE(root, nullptr);
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(root) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    EXPECT_NO_THROW(io::instantiate(io::loadScene(entry.path()))) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 1);
}

TEST(Scene, ShapeColorsAreKeptForDrawing) {
  io::Scene s = parseScene(R"({"bodies": [{"shapes": [
      {"type": "sphere", "radius": 0.5, "color": [0.25, 0.5, 1]},
      {"type": "box", "half_extents": [1, 1, 1]}]}]})",
                           "colors.json");
  ASSERT_EQ(s.bodies.size(), 1u);
  ASSERT_EQ(s.bodies[0].shapes.size(), 2u);
  ASSERT_TRUE(s.bodies[0].shapes[0].color.has_value());
  EXPECT_TRUE(s.bodies[0].shapes[0].color->isApprox(Vec3(Real(0.25), Real(0.5), 1)));
  EXPECT_FALSE(s.bodies[0].shapes[1].color.has_value());
  SceneError e = errorOf(R"({"bodies": [{"shapes": [{"type": "sphere", "radius": 1, "color": [2, 0, 0]}]}]})");
  EXPECT_EQ(e.pointer(), "/bodies/0/shapes/0/color") << e.what();
}
