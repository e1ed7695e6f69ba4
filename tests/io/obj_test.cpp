// OBJ import: a unit cube written with quads in two groups (12 triangles, closed, volume 1),
// the errors (missing file, parse error with its line, index out of range, no faces, degenerate
// face), and scene files whose mesh shapes name an OBJ relative to the scene file.
#include "inertia/io/obj.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "inertia/geometry/mass.h"
#include "inertia/geometry/shapes.h"
#include "inertia/io/scene.h"

using namespace inertia;
namespace fs = std::filesystem;

namespace {

// The unit cube [0, 1]^3: quads counter-clockwise seen from outside, split over two groups,
// with normals, texture coordinates, a material reference and an unreferenced vertex (9) that
// the loader drops.
constexpr const char* kCube = R"(# unit cube
mtllib missing.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
v 5 5 5
vn 0 0 -1
vt 0 0
o lower
usemtl none
f 1//1 4//1 3//1 2//1
f 1 2 6 5
f 1 5 8 4
o upper
f 5 6 7 8
f 2 3 7 6
f 4 8 7 3
)";

// A fresh directory per test and process (the asan and double builds may run at once).
fs::path scratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / ("inertia_obj_" + std::string(info->name()) +
                                                    "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

io::ObjError objErrorOf(const fs::path& file) {
  try {
    io::loadObj(file);
  } catch (const io::ObjError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for " << file;
  return io::ObjError("", 0, "");
}

}  // namespace

// 6 quads -> 12 triangles over the 8 referenced vertices; closed and outward, so the mass
// properties apply: volume 1 and centre (1/2, 1/2, 1/2) (Mirtich's integrals are exact for a
// polyhedron; the tolerance is float rounding of sums of O(1) terms).
TEST(Obj, CubeWithQuadsLoadsAsClosedMesh) {
  const fs::path dir = scratch();
  const TriangleMesh mesh = io::loadObj(write(dir / "cube.obj", kCube));
  EXPECT_EQ(mesh.triangles().size(), 12u);
  EXPECT_EQ(mesh.vertices().size(), 8u);
  EXPECT_TRUE(mesh.isClosed());
  EXPECT_EQ(mesh.bounds().lower, Vec3::Zero());
  EXPECT_EQ(mesh.bounds().upper, Vec3::Ones());
  const MassProperties m = massProperties(mesh, Real(1000));
  const Real tol = 64 * std::numeric_limits<Real>::epsilon();
  EXPECT_NEAR(m.volume, 1, tol);
  EXPECT_NEAR(m.mass, 1000, 1000 * tol);
  EXPECT_NEAR((m.centerOfMass - Vec3::Constant(Real(0.5))).norm(), 0, tol);
  fs::remove_all(dir);
}

TEST(Obj, ErrorsNameTheFileAndLine) {
  const fs::path dir = scratch();
  // Missing file.
  io::ObjError missing = objErrorOf(dir / "nope.obj");
  EXPECT_EQ(missing.file(), (dir / "nope.obj").string());
  EXPECT_NE(std::string(missing.what()).find("no such file"), std::string::npos);
  // A zero face index is a parse error on line 5.
  io::ObjError zero = objErrorOf(write(dir / "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 0 1 2\n"));
  EXPECT_EQ(zero.line(), 5) << zero.what();
  EXPECT_NE(std::string(zero.what()).find((dir / "zero.obj").string() + ":5: "), std::string::npos)
      << zero.what();
  // An index past the vertices (tinyobjloader only warns): named with the vertex count.
  io::ObjError range = objErrorOf(write(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
  EXPECT_NE(range.reason().find("uses vertex 9, but the file has 3 vertices"), std::string::npos)
      << range.what();
  // No faces.
  io::ObjError empty = objErrorOf(write(dir / "empty.obj", "v 0 0 0\nv 1 0 0\n"));
  EXPECT_NE(empty.reason().find("no faces"), std::string::npos) << empty.what();
  // A face repeating a vertex: TriangleMesh's rejection, with the file named.
  io::ObjError degenerate =
      objErrorOf(write(dir / "degenerate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n"));
  EXPECT_NE(degenerate.reason().find("invalid mesh"), std::string::npos) << degenerate.what();
  EXPECT_EQ(degenerate.file(), (dir / "degenerate.obj").string());
  fs::remove_all(dir);
}

// {"type": "mesh", "obj": "meshes/cube.obj"} resolves against the scene file's directory;
// a bad OBJ fails with the "obj" value's JSON pointer and the OBJ error in the reason.
TEST(Obj, SceneMeshShapeFromObj) {
  const fs::path dir = scratch();
  write(dir / "meshes" / "cube.obj", kCube);
  write(dir / "meshes" / "bad.obj", "v 0 0 0\nf 0 1 2\n");
  const std::string body = R"({"bodies": [{"name": "rock", "type": "static", "shapes": [
      {"type": "mesh", "obj": "OBJ"}]}]})";
  auto scene = [&](const std::string& obj) {
    std::string text = body;
    text.replace(text.find("OBJ"), 3, obj);
    return write(dir / "scene.json", text);
  };
  const io::Scene s = io::loadScene(scene("meshes/cube.obj"));
  ASSERT_EQ(s.bodies.size(), 1u);
  ASSERT_EQ(s.bodies[0].shapes.size(), 1u);
  const Shape& shape = s.bodies[0].shapes[0].shape;
  ASSERT_EQ(shape.type(), ShapeType::Mesh);
  EXPECT_EQ(shape.get<TriangleMesh>().triangles().size(), 12u);
  EXPECT_TRUE(shape.get<TriangleMesh>().isClosed());

  for (const char* bad : {"meshes/bad.obj", "meshes/none.obj"}) {
    try {
      io::loadScene(scene(bad));
      ADD_FAILURE() << "no error for " << bad;
    } catch (const io::SceneError& e) {
      EXPECT_EQ(e.pointer(), "/bodies/0/shapes/0/obj") << e.what();
      EXPECT_NE(e.reason().find("cannot load OBJ"), std::string::npos) << e.what();
      EXPECT_NE(e.reason().find((dir / bad).string()), std::string::npos) << e.what();
    }
  }
  // "obj" together with inline vertices is ambiguous.
  try {
    io::parseScene(R"({"bodies": [{"type": "static", "shapes": [
        {"type": "mesh", "obj": "a.obj", "vertices": [], "triangles": []}]}]})",
                   dir / "inline.json");
    ADD_FAILURE() << "no error for obj + vertices";
  } catch (const io::SceneError& e) {
    EXPECT_EQ(e.pointer(), "/bodies/0/shapes/0") << e.what();
  }
  fs::remove_all(dir);
}
