// Mesh files as vertex lists (src/io/mesh_file.cpp): one tetrahedron written as OBJ (the OBJ
// loader), ASCII STL and COLLADA (Assimp) gives the same four corners; COLLADA's node
// transforms move the vertices; missing and unreadable files are named with what is wrong.
#include "io/mesh_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../scratch_dir.h"

using namespace inertia;
namespace fs = std::filesystem;
using io::detail::loadMeshVertices;

// Outside the anonymous namespace: the tests derive from it, and in a unity batch, which
// includes this file, GCC rejects a base of internal linkage (-Wsubobject-linkage).
class MeshFile : public test::ScratchDirTest {
 protected:
  // The message loadMeshVertices gives for `path`, empty when it loads.
  static std::string errorOf(const fs::path& path) {
    try {
      loadMeshVertices(path);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
};

namespace {

// The corners of the unit tetrahedron, sorted, and a mesh's distinct vertices, sorted.
const std::vector<Vec3> kCorners = {Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0)};

std::vector<Vec3> distinctSorted(std::vector<Vec3> v) {
  auto less = [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

const char* kTetrahedronStl =
    "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\n"
    "endloop\nendfacet\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
    "vertex 0 0 1\nendloop\nendfacet\nfacet normal -1 0 0\nouter loop\nvertex 0 0 0\n"
    "vertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 1 1 1\nouter loop\n"
    "vertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";

// The tetrahedron as COLLADA, its node moved by `matrix` (row-major, as COLLADA writes it).
std::string tetrahedronDae(const std::string& matrix) {
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tet" name="tet"><mesh>
      <source id="tet-pos">
        <float_array id="tet-pos-array" count="12">0 0 0 1 0 0 0 1 0 0 0 1</float_array>
        <technique_common><accessor source="#tet-pos-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="tet-vtx"><input semantic="POSITION" source="#tet-pos"/></vertices>
      <triangles count="4"><input semantic="VERTEX" source="#tet-vtx" offset="0"/>
        <p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="part" name="part"><matrix>)" +
         matrix + R"(</matrix><instance_geometry url="#tet"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

}  // namespace

// The OBJ loader and Assimp read the same solid to the same corners (exact: the files hold
// small integers).
TEST_F(MeshFile, ObjStlAndColladaGiveTheSameVertices) {
  const fs::path obj =
      write("tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const fs::path stl = write("tet.stl", kTetrahedronStl);
  const fs::path dae = write("tet.dae", tetrahedronDae("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"));
  EXPECT_EQ(distinctSorted(loadMeshVertices(obj)), kCorners);
  EXPECT_EQ(distinctSorted(loadMeshVertices(stl)), kCorners);
  EXPECT_EQ(distinctSorted(loadMeshVertices(dae)), kCorners);
}

// A node's transform moves its mesh: a translation by (1, 2, 3) and a quarter turn about z
// (x -> y, y -> -x), exact in the file's small integers.
TEST_F(MeshFile, NodeTransformsMoveTheVertices) {
  const fs::path dae = write("moved.dae", tetrahedronDae("0 -1 0 1 1 0 0 2 0 0 1 3 0 0 0 1"));
  std::vector<Vec3> expected;
  for (const Vec3& c : kCorners) expected.push_back(Vec3(-c.y() + 1, c.x() + 2, c.z() + 3));
  EXPECT_EQ(distinctSorted(loadMeshVertices(dae)), distinctSorted(expected));
}

TEST_F(MeshFile, BadFilesAreNamedWithTheProblem) {
  for (const char* name : {"absent.obj", "absent.stl"}) {
    const std::string reason = errorOf(dir_ / name);
    EXPECT_NE(reason.find((dir_ / name).string()), std::string::npos) << reason;
  }
  EXPECT_NE(errorOf(dir_ / "absent.stl").find("no such file"), std::string::npos);
  const fs::path junk = write("junk.stl", "this is not a mesh\n");
  const std::string reason = errorOf(junk);
  EXPECT_FALSE(reason.empty());
  EXPECT_NE(reason.find(junk.string()), std::string::npos) << reason;
}
