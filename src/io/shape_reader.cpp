#include "shape_reader.h"

#include <vector>

#include "inertia/core/error.h"
#include "inertia/geometry/height_field.h"
#include "inertia/geometry/hull.h"
#include "inertia/geometry/mesh.h"
#include "inertia/io/obj.h"

namespace inertia::io::detail {

std::vector<Vec3> readPoints(const Node& n) {
  std::vector<Vec3> points(n.requireArray());
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = n.at(i).vec3();
  return points;
}

std::vector<Triangle> readTriangles(const Node& n, std::size_t vertexCount) {
  std::vector<Triangle> triangles(n.requireArray());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    Node t = n.at(i);
    if (t.requireArray() != 3) t.fail("expected 3 vertex indices");
    for (std::size_t k = 0; k < 3; ++k)
      triangles[i][k] = std::uint32_t(t.at(k).integer(0, (long long)vertexCount - 1));
  }
  return triangles;
}

Transform readPose(const Node& n) {
  Transform pose;
  if (n.has("position")) pose.p = n.at("position").vec3();
  if (n.has("orientation")) pose.q = n.at("orientation").quaternion();
  return pose;
}

Shape readShape(const Node& n, Transform& pose, std::initializer_list<std::string_view> extra) {
  const std::string type = n.at("type").string();
  auto keys = [&](std::initializer_list<std::string_view> own) {
    std::vector<std::string_view> all{"type", "position", "orientation"};
    all.insert(all.end(), own.begin(), own.end());
    all.insert(all.end(), extra.begin(), extra.end());
    return all;
  };
  auto check = [&](std::initializer_list<std::string_view> own) { n.requireObject(keys(own)); };
  pose = readPose(n);
  try {
    if (type == "plane") {
      check({"normal", "offset"});
      Plane p;
      if (n.has("normal")) p.normal = n.at("normal").vec3();
      if (n.has("offset")) p.offset = Real(n.at("offset").number());
      if (p.normal.norm() < Real(1e-6)) n.at("normal").fail("plane normal must be non-zero");
      return Shape(p);
    }
    if (type == "sphere") {
      check({"radius"});
      return Shape(Sphere{Real(n.at("radius").number(0, 1e6, true))});
    }
    if (type == "capsule") {
      check({"radius", "half_height"});
      return Shape(Capsule{Real(n.at("radius").number(0, 1e6, true)),
                           Real(n.at("half_height").number(0, 1e6, true))});
    }
    if (type == "cylinder") {
      check({"radius", "half_height"});
      return Shape(Cylinder{Real(n.at("radius").number(0, 1e6, true)),
                            Real(n.at("half_height").number(0, 1e6, true))});
    }
    if (type == "box") {
      check({"half_extents"});
      const Vec3 e = n.at("half_extents").vec3();
      if ((e.array() <= 0).any()) n.at("half_extents").fail("half extents must be > 0");
      return Shape(Box{e});
    }
    if (type == "hull") {
      check({"points"});
      const std::vector<Vec3> points = readPoints(n.at("points"));
      return Shape(ConvexHull(points));
    }
    if (type == "heightfield") {
      check({"heights", "spacing"});
      Node rows = n.at("heights");
      std::vector<std::vector<Real>> heights(rows.requireArray());
      for (std::size_t r = 0; r < heights.size(); ++r) {
        Node row = rows.at(r);
        heights[r].resize(row.requireArray());
        for (std::size_t c = 0; c < heights[r].size(); ++c) heights[r][c] = Real(row.at(c).number());
      }
      return Shape(HeightField(heights, Real(n.at("spacing").number(0, 1e6, true))));
    }
    if (type == "compound") {
      check({"shapes"});
      Node list = n.at("shapes");
      std::vector<CompoundChild> children;
      for (std::size_t i = 0; i < list.requireArray(); ++i) {
        Transform childPose;
        Shape child = readShape(list.at(i), childPose);
        children.push_back({std::move(child), childPose});
      }
      return Shape(Compound(std::move(children)));
    }
    if (type == "mesh") {
      check({"vertices", "triangles", "obj"});
      if (n.has("obj")) {
        if (n.has("vertices") || n.has("triangles"))
          n.fail("a mesh takes \"obj\" or \"vertices\" and \"triangles\", not both");
        const Node obj = n.at("obj");
        try {
          return Shape(loadObj(obj.path("OBJ")));
        } catch (const ObjError& e) {
          obj.fail(std::string("cannot load OBJ: ") + e.what());
        }
      }
      std::vector<Vec3> vertices = readPoints(n.at("vertices"));
      std::vector<Triangle> triangles = readTriangles(n.at("triangles"), vertices.size());
      return Shape(TriangleMesh(std::move(vertices), std::move(triangles)));
    }
  } catch (const InvalidArgument& e) {
    n.fail(std::string("invalid ") + type + ": " + e.what());
  }
  n.at("type").fail("unknown shape type \"" + type +
                    "\"; expected one of plane, sphere, capsule, cylinder, box, hull, mesh, heightfield, compound");
}

}  // namespace inertia::io::detail
