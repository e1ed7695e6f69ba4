// URDF robots (src/io/urdf.cpp): the reader's mass properties against closed forms from the
// file's numbers, a URDF pendulum's period against the physical pendulum's, collision meshes,
// the scene's "urdf" key, the shipped robots, and bad files named with what is wrong.
#include "inertia/io/urdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "../scratch_dir.h"
#include "inertia/articulation/articulation.h"
#include "inertia/articulation/dynamics.h"
#include "inertia/io/scene.h"

using namespace inertia;
namespace art = inertia::articulation;
namespace fs = std::filesystem;
using io::UrdfError;

// Outside the anonymous namespace: the tests derive from it, and in a unity batch, which
// includes this file, GCC rejects a base of internal linkage (-Wsubobject-linkage).
class Urdf : public test::ScratchDirTest {
 protected:
  // The reason loadUrdf gives for a file holding `text`.
  std::string errorOf(const std::string& text, const std::string& name = "bad.urdf") {
    const fs::path p = write(name, text);
    try {
      io::loadUrdf(p);
    } catch (const UrdfError& e) {
      EXPECT_EQ(e.file(), p.string());
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": ", 0), 0u) << e.what();
      return e.reason();
    }
    ADD_FAILURE() << "no error for " << text;
    return "";
  }
};

namespace {

fs::path sourceDir() {
  const char* root = std::getenv("INERTIA_SOURCE_DIR");
  return root ? fs::path(root) : fs::path(".");
}

// URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Mat3 rpy(double r, double p, double y) {
  return (Eigen::AngleAxis<Real>(Real(y), Vec3::UnitZ()) *
          Eigen::AngleAxis<Real>(Real(p), Vec3::UnitY()) *
          Eigen::AngleAxis<Real>(Real(r), Vec3::UnitX()))
      .toRotationMatrix();
}

// Float builds round the file's numbers to float (6e-8 relative) and sum a few products.
const Real kTight = std::is_same_v<Real, double> ? Real(1e-12) : Real(1e-6);

}  // namespace

// The inertial frame turned by rpy = (0, 0, pi/2): R I R^T swaps xx and yy and moves the
// products of inertia (xy -> -xy, xz -> -yz, yz -> xz), all by hand.
TEST_F(Urdf, InertialFrameTurnsTheFullTensor) {
  const fs::path p = write("one.urdf", R"(<robot name="one"><link name="a"><inertial>
      <origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/><mass value="2"/>
      <inertia ixx="2" ixy="0.1" ixz="0.2" iyy="3" iyz="0.3" izz="4"/></inertial></link></robot>)");
  const io::UrdfRobot robot = io::loadUrdf(p, {.floatingBase = true});
  ASSERT_EQ(robot.model.linkCount(), 1);
  const art::Link<Real>& l = robot.model.link(0);
  EXPECT_EQ(l.mass, Real(2));
  EXPECT_LT((l.centerOfMass - Vec3(Real(0.1), Real(0.2), Real(0.3))).norm(), kTight);
  Mat3 expected;
  expected << 3, -0.1, -0.3, -0.1, 2, 0.2, -0.3, 0.2, 4;
  // The spatial inertia about the link origin holds I_c + m (c^T c 1 - c c^T) (parallel axes).
  const Vec3 c = l.centerOfMass;
  const Mat3 Io = expected + Real(2) * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  EXPECT_LT((l.I.topLeftCorner<3, 3>() - Io).norm(), 10 * kTight) << l.I;
}

// The whole robot's mass and inertia about its root, composed by hand from the file's numbers
// (parallel axes, turned inertial and joint frames, products of inertia), against the top-left
// block of a floating base's mass matrix, which is the composite rigid-body inertia.
TEST_F(Urdf, TotalMassAndInertiaMatchTheFile) {
  const fs::path p = write("three.urdf", R"(<robot name="three">
    <link name="base"><inertial><origin xyz="0.05 0 -0.02" rpy="0.3 0 0"/><mass value="3"/>
      <inertia ixx="0.05" ixy="0.004" ixz="-0.002" iyy="0.06" iyz="0.001" izz="0.07"/></inertial></link>
    <link name="frame"/>
    <link name="arm"><inertial><origin xyz="0 0 0.25" rpy="0.2 -0.4 1.1"/><mass value="1.5"/>
      <inertia ixx="0.03" ixy="-0.002" ixz="0.003" iyy="0.032" iyz="0.0015" izz="0.006"/></inertial></link>
    <joint name="mount" type="fixed"><parent link="base"/><child link="frame"/>
      <origin xyz="0.1 0.2 0.3" rpy="0.5 0.1 -0.7"/></joint>
    <joint name="elbow" type="revolute"><parent link="frame"/><child link="arm"/>
      <origin xyz="0 0 0.1" rpy="0 1.2 0"/><axis xyz="0 1 0"/>
      <limit lower="-1" upper="1" effort="10" velocity="2"/></joint></robot>)");
  const io::UrdfRobot robot = io::loadUrdf(p, {.floatingBase = true});
  ASSERT_EQ(robot.model.linkCount(), 3);
  EXPECT_EQ(robot.model.link(1).mass, Real(0));  // "frame" has no <inertial>
  Mat3 I1, I2;
  I1 << 0.05, 0.004, -0.002, 0.004, 0.06, 0.001, -0.002, 0.001, 0.07;
  I2 << 0.03, -0.002, 0.003, -0.002, 0.032, 0.0015, 0.003, 0.0015, 0.006;
  const Mat3 R1 = rpy(0.3, 0, 0);
  const Vec3 c1(Real(0.05), 0, Real(-0.02));
  // The arm's frame in the base's: mount then elbow's origin (q = 0).
  const Mat3 Rarm = rpy(0.5, 0.1, -0.7) * rpy(0, 1.2, 0);
  const Vec3 parm =
      Vec3(Real(0.1), Real(0.2), Real(0.3)) + rpy(0.5, 0.1, -0.7) * Vec3(0, 0, Real(0.1));
  const Mat3 R2 = Rarm * rpy(0.2, -0.4, 1.1);
  const Vec3 c2 = parm + Rarm * Vec3(0, 0, Real(0.25));
  auto aboutOrigin = [](Real m, const Mat3& R, const Mat3& I, const Vec3& c) {
    return Mat3(R * I * R.transpose() +
                m * (c.squaredNorm() * Mat3::Identity() - c * c.transpose()));
  };
  const Mat3 expected = aboutOrigin(3, R1, I1, c1) + aboutOrigin(Real(1.5), R2, I2, c2);
  const Vec3 moment = 3 * c1 + Real(1.5) * c2;  // total mass times the centre of mass

  const art::MatrixX<Real> H = art::crba(robot.model, robot.model.neutralConfiguration());
  // Spatial order [angular; linear]: H = [I_O, m [c]x; m [c]x^T, m 1].
  EXPECT_LT((H.block<3, 3>(3, 3) - Real(4.5) * Mat3::Identity()).norm(), 10 * kTight);
  EXPECT_LT((H.topLeftCorner<3, 3>() - expected).norm(), 10 * kTight) << H.topLeftCorner<3, 3>();
  const Mat3 cross = H.block<3, 3>(0, 3);
  EXPECT_LT((Vec3(cross(2, 1), cross(0, 2), cross(1, 0)) - moment).norm(), 10 * kTight);
}

// A URDF pendulum (z up, hinge about y, a rod's inertia about its centre) swings with the
// physical pendulum's small-angle period T = 2 pi sqrt((I_c + m L^2) / (m g L)).
TEST_F(Urdf, PendulumSwingsWithThePhysicalPendulumsPeriod) {
  const double m = 2, L = 0.5, Ic = 0.04, g = 9.81;
  const fs::path p = write("pendulum.urdf", R"(<robot name="pendulum">
    <link name="world"/>
    <link name="bob"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
      <inertia ixx="0.04" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.001"/></inertial></link>
    <joint name="hinge" type="continuous"><parent link="world"/><child link="bob"/>
      <origin xyz="0 0 1"/><axis xyz="0 1 0"/></joint></robot>)");
  io::UrdfRobot robot = io::loadUrdf(p);
  ASSERT_EQ(robot.model.nv(), 1);
  robot.model.gravity = Vec3(0, 0, Real(-g));
  art::Articulation<Real> a(robot.model, {.integrator = art::Integrator::Rk4});
  const double theta0 = 0.01;
  art::VectorX<Real> q(1), qd = art::VectorX<Real>::Zero(1);
  q(0) = Real(theta0);
  a.setState(q, qd);
  // Zero crossings of the angle, linearly interpolated; the period is the time between the
  // first and the fifth (two periods).
  const double h = 1e-3;
  std::vector<double> crossings;
  double previous = theta0;
  for (int step = 1; crossings.size() < 5 && step < 100000; ++step) {
    a.step(Real(h));
    const double now = double(a.q()(0));
    if ((previous > 0) != (now > 0))
      crossings.push_back(h * (step - 1 + previous / (previous - now)));
    previous = now;
  }
  ASSERT_EQ(crossings.size(), 5u);
  const double period = (crossings[4] - crossings[0]) / 2;
  const double expected = 2 * std::numbers::pi * std::sqrt((Ic + m * L * L) / (m * g * L));
  // Finite amplitude lengthens the period by theta0^2 / 16 = 6e-6; RK4's phase error at
  // omega h = 4e-3 is ~1e-11; linear interpolation of a sine at a crossing errs by
  // (omega h)^2 theta0 / 8 in angle, 2e-6 h in time. Float rounds the state (6e-8 a step over
  // 2,000 steps): 1e-4 relative holds in both with margin, 0.1% is the issue's bound.
  EXPECT_NEAR(period / expected, 1.0, 1e-4) << period << " vs " << expected;
}

// Mesh collision geometry: OBJ through the OBJ loader and STL through Assimp, each scaled and
// made the convex hull of its vertices; relative to the URDF file's directory.
TEST_F(Urdf, MeshesBecomeScaledConvexHulls) {
  write("cube.obj",
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\n"
        "v -1 1 1\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\n"
        "f 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n");
  write("tet.stl",
        "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\n"
        "vertex 1 0 0\nendloop\nendfacet\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\n"
        "vertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\nfacet normal -1 0 0\nouter loop\n"
        "vertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 1 1 1\n"
        "outer loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
        "endsolid t\n");
  const fs::path p = write("meshes.urdf", R"(<robot name="m"><link name="a">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><mesh filename="cube.obj" scale="2 1 0.5"/></geometry></collision>
    <collision><origin xyz="0 0 3"/><geometry><mesh filename="file://)" +
                                              (dir_ / "tet.stl").string() +
                                              R"(" scale="3 3 3"/></geometry></collision>
    </link></robot>)");
  const io::UrdfRobot robot = io::loadUrdf(p);
  ASSERT_EQ(robot.shapes.size(), 2u);
  const ConvexHull* cube = robot.shapes[0].shape.getIf<ConvexHull>();
  const ConvexHull* tet = robot.shapes[1].shape.getIf<ConvexHull>();
  ASSERT_TRUE(cube && tet);
  EXPECT_EQ(cube->vertices().size(), 8u);
  EXPECT_EQ(tet->vertices().size(), 4u);
  Vec3 hi = Vec3::Constant(-1e9);
  for (const Vec3& v : cube->vertices()) hi = hi.cwiseMax(v.cwiseAbs());
  EXPECT_EQ(hi, Vec3(2, 1, Real(0.5)));
  for (const Vec3& v : tet->vertices()) EXPECT_NEAR(v.sum(), (v.isZero() ? 0 : 3), 1e-6);
  EXPECT_EQ(robot.shapes[1].pose.p, Vec3(0, 0, 3));
}

// Collision primitives: sizes halved, URDF's z-axis cylinders turned onto our y-axis ones.
TEST_F(Urdf, PrimitivesKeepUrdfsSizesAndAxes) {
  const fs::path p = write("prims.urdf", R"(<robot name="p"><link name="a">
    <collision><origin xyz="1 2 3"/><geometry><box size="0.2 0.4 0.6"/></geometry></collision>
    <collision><geometry><cylinder radius="0.1" length="0.8"/></geometry></collision>
    <collision><geometry><sphere radius="0.3"/></geometry></collision></link>
    <link name="b"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <joint name="j" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="0 0 2"/>
      <limit lower="-0.1" upper="0.2" effort="0" velocity="0"/>
      <dynamics damping="0.7" friction="0.3"/></joint></robot>)");
  const io::UrdfRobot robot = io::loadUrdf(p);
  ASSERT_EQ(robot.shapes.size(), 3u);
  EXPECT_EQ(robot.shapes[0].shape.get<Box>().halfExtents, Vec3(Real(0.1), Real(0.2), Real(0.3)));
  EXPECT_EQ(robot.shapes[0].pose.p, Vec3(1, 2, 3));
  const Cylinder& c = robot.shapes[1].shape.get<Cylinder>();
  EXPECT_EQ(c.radius, Real(0.1));
  EXPECT_EQ(c.halfHeight, Real(0.4));
  EXPECT_LT((robot.shapes[1].pose.q * Vec3::UnitY() - Vec3::UnitZ()).norm(), 1e-6);
  EXPECT_EQ(robot.shapes[2].shape.get<Sphere>().radius, Real(0.3));
  // The prismatic joint: axis normalised, limits, damping and friction; effort and velocity 0
  // mean none.
  EXPECT_EQ(robot.model.link(1).joint, art::JointType::Prismatic);
  EXPECT_EQ(robot.model.link(1).axis, Vec3::UnitZ());
  EXPECT_EQ(robot.model.lower()(0), Real(-0.1));
  EXPECT_EQ(robot.model.upper()(0), Real(0.2));
  EXPECT_EQ(robot.model.damping()(0), Real(0.7));
  EXPECT_EQ(robot.model.friction()(0), Real(0.3));
  EXPECT_TRUE(std::isinf(robot.model.velocityLimit()(0)));
  ASSERT_EQ(robot.joints.size(), 1u);
  EXPECT_TRUE(std::isinf(robot.joints[0].effort));
}

// The shipped robots: the arm's seven limited revolute joints with their efforts and speeds,
// its massless flange; the quadruped's floating base from its "world" link, 12 joints.
TEST_F(Urdf, ShippedRobotsRead) {
  const io::UrdfRobot arm = io::loadUrdf(sourceDir() / "robots" / "arm7.urdf");
  EXPECT_EQ(arm.name, "arm7");
  EXPECT_EQ(arm.model.nv(), 7);
  EXPECT_EQ(arm.model.linkCount(), 9);
  EXPECT_FALSE(arm.floatingBase);
  ASSERT_NE(arm.findJoint("joint4"), nullptr);
  EXPECT_EQ(arm.findJoint("joint4")->effort, Real(87));
  EXPECT_EQ(arm.model.upper()(3), Real(-0.0698));
  EXPECT_EQ(arm.model.velocityLimit()(6), Real(2.61));
  EXPECT_EQ(arm.model.link(arm.model.findLink("flange")).mass, Real(0));
  const io::UrdfRobot dog = io::loadUrdf(sourceDir() / "robots" / "quadruped.urdf");
  EXPECT_TRUE(dog.floatingBase);
  EXPECT_EQ(dog.model.link(0).name, "trunk");
  EXPECT_EQ(dog.model.link(0).joint, art::JointType::Floating);
  EXPECT_EQ(dog.model.nv(), 6 + 12);
  EXPECT_EQ(dog.model.findLink("world"), -1);
}

// Bad files: each error names the file and what is wrong.
TEST_F(Urdf, BadFilesSayWhatIsWrong) {
  try {
    io::loadUrdf(dir_ / "absent.urdf");
    ADD_FAILURE();
  } catch (const UrdfError& e) {
    EXPECT_EQ(e.file(), (dir_ / "absent.urdf").string());
    EXPECT_EQ(e.reason(), "no such file");
  }
  const std::string inertial =
      R"(<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)";
  auto twoLinks = [&](const std::string& joint, const std::string& childExtra = "") {
    return R"(<robot name="r"><link name="a">)" + inertial + R"(</link><link name="b">)" +
           inertial + childExtra + "</link>" + joint + "</robot>";
  };
  // Malformed XML: urdfdom's own words.
  std::string reason = errorOf(R"(<robot name="r"><link name="a"></robot>)");
  EXPECT_NE(reason.find("urdfdom cannot parse it"), std::string::npos) << reason;
  EXPECT_NE(reason.find("end tag"), std::string::npos) << reason;  // TinyXML's words
  // Two roots.
  reason = errorOf(R"(<robot name="r"><link name="a"/><link name="b"/></robot>)");
  EXPECT_NE(reason.find("root"), std::string::npos) << reason;
  // A joint to a link that is not there.
  reason = errorOf(
      twoLinks(R"(<joint name="j" type="fixed"><parent link="a"/><child link="c"/></joint>)"));
  EXPECT_NE(reason.find("[c]"), std::string::npos) << reason;
  // Planar and floating joints.
  reason = errorOf(twoLinks(
      R"(<joint name="slide" type="planar"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>)"));
  EXPECT_NE(reason.find("joint 'slide' is planar"), std::string::npos) << reason;
  reason = errorOf(twoLinks(
      R"(<joint name="free" type="floating"><parent link="a"/><child link="b"/></joint>)"));
  EXPECT_NE(reason.find("joint 'free' is floating"), std::string::npos) << reason;
  // Meshes: missing, package://, unreadable.
  const std::string fixed =
      R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>)";
  reason = errorOf(twoLinks(
      fixed,
      R"(<collision><geometry><mesh filename="meshes/missing.obj"/></geometry></collision>)"));
  EXPECT_NE(reason.find("link 'b': collision mesh"), std::string::npos) << reason;
  EXPECT_NE(reason.find((dir_ / "meshes" / "missing.obj").string()), std::string::npos) << reason;
  reason = errorOf(twoLinks(
      fixed,
      R"(<collision><geometry><mesh filename="package://robot/m.stl"/></geometry></collision>)"));
  EXPECT_NE(reason.find("package://"), std::string::npos) << reason;
  write("junk.stl", "this is not a mesh\n");
  reason = errorOf(twoLinks(
      fixed, R"(<collision><geometry><mesh filename="junk.stl"/></geometry></collision>)"));
  EXPECT_NE(reason.find("junk.stl"), std::string::npos) << reason;
  // Collision primitives of zero size (urdfdom reads them without complaint).
  reason = errorOf(
      twoLinks(fixed, R"(<collision><geometry><sphere radius="0"/></geometry></collision>)"));
  EXPECT_NE(reason.find("link 'b': the collision sphere's radius must be finite and > 0"),
            std::string::npos)
      << reason;
  reason = errorOf(
      twoLinks(fixed, R"(<collision><geometry><box size="1 0 1"/></geometry></collision>)"));
  EXPECT_NE(reason.find("link 'b': the collision box's size"), std::string::npos) << reason;
  // A floating base whose origin would be dropped: the scene places the base.
  reason = errorOf(R"(<robot name="r"><link name="world"/><link name="b">)" + inertial +
                   R"(</link><joint name="free" type="floating"><origin xyz="0 0 1"/>
      <parent link="world"/><child link="b"/></joint></robot>)");
  EXPECT_NE(reason.find("joint 'free': a floating base's origin must be the identity"),
            std::string::npos)
      << reason;
  // A moving joint with no mass below it; a bad inertia.
  reason = errorOf(R"(<robot name="r"><link name="a">)" + inertial + R"(</link><link name="b"/>
      <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>)");
  EXPECT_NE(reason.find("link 'b': its joint moves no mass"), std::string::npos) << reason;
  reason = errorOf(R"(<robot name="r"><link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="5"/></inertial></link></robot>)");
  EXPECT_NE(reason.find("link 'a'"), std::string::npos) << reason;
  EXPECT_NE(reason.find("triangle"), std::string::npos) << reason;
}

// The scene's "urdf" key: relative to the scene file, the base pose, "q", "qd" and "drives" by
// joint name, a drive's maxForce the joint's effort unless it gives its own.
TEST_F(Urdf, SceneReadsUrdfArticulations) {
  fs::create_directories(dir_ / "robots");
  fs::copy_file(sourceDir() / "robots" / "arm7.urdf", dir_ / "robots" / "arm7.urdf");
  const fs::path scene = write("scene.json", R"({"articulations": [{"name": "arm",
      "urdf": "robots/arm7.urdf", "position": [1, 0, 2], "orientation": [0.70710678, -0.70710678, 0, 0],
      "q": {"joint4": -1.5}, "qd": {"joint2": 0.25},
      "drives": {"joint1": {"stiffness": 100, "damping": 10},
                 "joint7": {"stiffness": 5, "max_force": 3}}}]})");
  const io::Scene s = io::loadScene(scene);
  ASSERT_EQ(s.articulations.size(), 1u);
  const WorldArticulationSettings& a = s.articulations[0].settings;
  EXPECT_EQ(a.model.nv(), 7);
  EXPECT_EQ(a.base.p, Vec3(1, 0, 2));
  EXPECT_EQ(a.q(3), Real(-1.5));
  EXPECT_EQ(a.qd(1), Real(0.25));
  EXPECT_EQ(a.model.drives()[0].stiffness, Real(100));
  EXPECT_EQ(a.model.drives()[0].maxForce, Real(87));  // joint1's effort
  EXPECT_EQ(a.model.drives()[6].maxForce, Real(3));
  EXPECT_FALSE(a.shapes.empty());
  const std::unique_ptr<World> world = io::instantiate(s);
  EXPECT_EQ(world->articulations().size(), 1u);
}

// Bad "urdf" entries carry the JSON pointer and the URDF file's path.
TEST_F(Urdf, SceneErrorsNameThePointerAndTheUrdf) {
  write("planar.urdf", R"(<robot name="r"><link name="a"/><link name="b"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <joint name="slide" type="planar"><parent link="a"/><child link="b"/></joint></robot>)");
  fs::create_directories(dir_ / "robots");
  fs::copy_file(sourceDir() / "robots" / "arm7.urdf", dir_ / "robots" / "arm7.urdf");
  struct Case {
    std::string entry, pointer, words;
  };
  for (const Case& c : {
           Case{R"({"urdf": "absent.urdf"})", "/articulations/0/urdf",
                (dir_ / "absent.urdf").string() + ": no such file"},
           Case{R"({"urdf": "planar.urdf"})", "/articulations/0/urdf",
                (dir_ / "planar.urdf").string() + ": joint 'slide' is planar"},
           Case{R"({"urdf": "robots/arm7.urdf", "q": {"elbow": 1}})", "/articulations/0/q/elbow",
                "no joint named \"elbow\""},
           Case{R"({"urdf": "robots/arm7.urdf", "drives": {"flange_joint": {"stiffness": 1}}})",
                "/articulations/0/drives/flange_joint", "revolute and prismatic"},
           Case{R"({"urdf": "robots/arm7.urdf", "links": []})", "/articulations/0/links",
                "not both"},
       }) {
    const fs::path scene = write("scene.json", R"({"articulations": [)" + c.entry + "]}");
    try {
      io::loadScene(scene);
      ADD_FAILURE() << c.entry;
    } catch (const io::SceneError& e) {
      EXPECT_EQ(e.pointer(), c.pointer) << e.what();
      EXPECT_NE(e.reason().find(c.words), std::string::npos) << e.what();
    }
  }
}

// scenes/urdf_quadruped.json: the quadruped falls from 0.5 m onto the ground with its drives
// holding a crouch, and comes to rest standing. Its trunk's height at rest, by the crouch's
// kinematics: feet 0.025 m spheres, thigh and calf 0.2 m each at 0.8 rad from the vertical,
// hips in the trunk's centre plane: 0.025 + 2 (0.2 cos 0.8) = 0.304 m. The drives hold the
// legs against a quarter of the weight each (about 35 N) with the knee's lever of about 0.14 m
// (5 N m) at 150 N m/rad: a sag of about 0.03 rad at the knee, with the contacts' slop about
// 0.02 m lower; the trunk's belly (0.05 m below the centre) never touches the ground.
TEST_F(Urdf, QuadrupedSceneLandsAndStands) {
  const io::Scene scene = io::loadScene(sourceDir() / "scenes" / "urdf_quadruped.json");
  const std::unique_ptr<World> world = io::instantiate(scene);
  ASSERT_EQ(world->articulations().size(), 1u);
  const ArticulationId dog = world->articulations()[0];
  const BodyId trunk = world->linkBody(dog, 0);
  const Real dt = world->settings().dt;
  Real lowest = 1e9;
  art::VectorX<Real> joints3s;  // the joints' angles at 3 s
  for (int step = 0; step < int(4 / dt); ++step) {
    world->step(dt);
    const art::Articulation<Real>& a = world->articulation(dog);
    ASSERT_TRUE(a.q().allFinite() && a.qd().allFinite()) << "step " << step;
    lowest = std::min(lowest, world->transform(trunk).p.y());
    if (step == int(3 / dt)) joints3s = a.q().tail(12);
  }
  const Real height = world->transform(trunk).p.y();
  EXPECT_GT(height, Real(0.27)) << "sagged or fell";
  EXPECT_LT(height, Real(0.31)) << "above the crouch's kinematic height";
  EXPECT_GT(lowest, Real(0.05)) << "the belly touched the ground";
  // At rest on its legs: no vertical speed (1 mm/s), the joints still over the last second
  // (1 mrad).
  EXPECT_LT(std::abs(world->linearVelocity(trunk).y()), Real(1e-3));
  EXPECT_LT((world->articulation(dog).q().tail(12) - joints3s).cwiseAbs().maxCoeff(), Real(1e-3));
}

// Regression (issue 18): standing, the quadruped glided along the ground at a constant
// 0.36 m/s (0.56 m/s at 4 substeps), also with its legs locked by limits and no drives, while
// its joint angles did not change: its drives and limits were solved after the contacts, and
// the contacts' relax pass after them, so each substep ended with velocities one side had not
// answered (tests/world/articulations_test.cpp, LockedTable, has the small case). Solved in the
// same iterations, it comes to rest: over the last second its trunk moves less than 1 mm and
// ends slower than 1 mm/s horizontally, a tenth of kStickSpeed (0.01 m/s, where friction
// begins to treat a contact as sliding). Measured: about 1e-6 m and 3e-6 m/s.
TEST_F(Urdf, QuadrupedSceneComesToRestHorizontally) {
  const io::Scene scene = io::loadScene(sourceDir() / "scenes" / "urdf_quadruped.json");
  const std::unique_ptr<World> world = io::instantiate(scene);
  const BodyId trunk = world->linkBody(world->articulations()[0], 0);
  const Real dt = world->settings().dt;
  Vec3 at3s = Vec3::Zero();
  for (int step = 0; step < int(4 / dt); ++step) {
    world->step(dt);
    if (step == int(3 / dt)) at3s = world->transform(trunk).p;
  }
  const Vec3 drift = world->transform(trunk).p - at3s;
  const Vec3 v = world->linearVelocity(trunk);
  EXPECT_LT(std::hypot(drift.x(), drift.z()), Real(1e-3));
  EXPECT_LT(std::hypot(v.x(), v.z()), Real(1e-3));
}
