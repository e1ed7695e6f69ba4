// Shapes and materials: inertia.Sphere(0.5), inertia.Material(density=1000), ...
// Each is checked when it is made (ValueError naming the bad value); the primitives and
// materials pickle.
#include "inertia/geometry/shapes.h"

#include <pybind11/stl.h>

#include <memory>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "inertia/dynamics/body.h"
#include "shapes.h"

namespace inertia::python {

namespace {

std::vector<Vec3> toPoints(py::handle value, const char* arg) {
  RealArray a = toRows(value, arg, 3);
  std::vector<Vec3> points(std::size_t(a.shape(0)));
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = Vec3(a.at(py::ssize_t(i), 0), a.at(py::ssize_t(i), 1), a.at(py::ssize_t(i), 2));
  return points;
}

}  // namespace

Shape toShape(py::handle value, const char* arg) {
  if (py::isinstance<Sphere>(value)) return value.cast<Sphere>();
  if (py::isinstance<Box>(value)) return value.cast<Box>();
  if (py::isinstance<Capsule>(value)) return value.cast<Capsule>();
  if (py::isinstance<Cylinder>(value)) return value.cast<Cylinder>();
  if (py::isinstance<Plane>(value)) return value.cast<Plane>();
  if (py::isinstance<ConvexHull>(value))
    return Shape(std::shared_ptr<const ConvexHull>(value.cast<std::shared_ptr<ConvexHull>>()));
  if (py::isinstance<TriangleMesh>(value))
    return Shape(std::shared_ptr<const TriangleMesh>(value.cast<std::shared_ptr<TriangleMesh>>()));
  if (py::isinstance<HeightField>(value))
    return Shape(std::shared_ptr<const HeightField>(value.cast<std::shared_ptr<HeightField>>()));
  if (py::isinstance<Compound>(value))
    return Shape(std::shared_ptr<const Compound>(value.cast<std::shared_ptr<Compound>>()));
  argumentError(arg,
                "expected a shape (Sphere, Box, Capsule, Cylinder, Plane, ConvexHull, "
                "TriangleMesh, HeightField or Compound), got " +
                    std::string(py::str(py::type::of(value))));
}

Transform toPose(py::handle position, py::handle orientation) {
  Transform t;
  if (!position.is_none()) t.p = toVec3(position, "position");
  if (!orientation.is_none()) t.q = toQuat(orientation, "orientation");
  return t;
}

void bindShapes(py::module_& m) {
  py::class_<Material> material(m, "Material",
                                "The surface and bulk properties of a shape. Two touching "
                                "materials combine friction by the geometric mean and "
                                "restitution by the maximum.");
  material
      .def(py::init([](Real density, Real friction, Real dynamicFriction, Real restitution,
                       Real rollingFriction, Real spinningFriction) {
             Material mat{density,     friction,        dynamicFriction,
                          restitution, rollingFriction, spinningFriction};
             validate(mat);
             return mat;
           }),
           py::kw_only(), py::arg("density") = 1000, py::arg("friction") = 0.6,
           py::arg("dynamic_friction") = -1, py::arg("restitution") = 0,
           py::arg("rolling_friction") = 0, py::arg("spinning_friction") = 0)
      .def_readonly("density", &Material::density, "Mass per volume (kg/m^3).")
      .def_readonly("friction", &Material::friction, "Static Coulomb friction coefficient.")
      .def_readonly("dynamic_friction", &Material::dynamicFriction,
                    "Sliding Coulomb friction coefficient; negative: same as friction.")
      .def_readonly("restitution", &Material::restitution,
                    "Coefficient of restitution, 0 (plastic) .. 1 (elastic).")
      .def_readonly("rolling_friction", &Material::rollingFriction,
                    "Rolling resistance lever arm (m).")
      .def_readonly("spinning_friction", &Material::spinningFriction,
                    "Spinning friction lever arm (m).")
      .def("__repr__",
           [](const Material& a) {
             return py::str("Material(density={}, friction={}, restitution={})")
                 .format(a.density, a.friction, a.restitution);
           })
      .def(py::pickle(
          [](const Material& a) {
            return py::make_tuple(a.density, a.friction, a.dynamicFriction, a.restitution,
                                  a.rollingFriction, a.spinningFriction);
          },
          [](const py::tuple& t) {
            return Material{t[0].cast<Real>(), t[1].cast<Real>(), t[2].cast<Real>(),
                            t[3].cast<Real>(), t[4].cast<Real>(), t[5].cast<Real>()};
          }));

  py::class_<Sphere>(m, "Sphere", "A ball centred at the body's origin (or the shape's pose).")
      .def(py::init([](Real radius) {
             Sphere s{radius};
             validate(s);
             return s;
           }),
           py::arg("radius") = 0.5)
      .def_readonly("radius", &Sphere::radius, "Radius (m).")
      .def("__repr__", [](const Sphere& s) { return py::str("Sphere({})").format(s.radius); })
      .def(py::pickle([](const Sphere& s) { return py::make_tuple(s.radius); },
                      [](const py::tuple& t) { return Sphere{t[0].cast<Real>()}; }));

  py::class_<Capsule>(m, "Capsule",
                      "A cylinder capped by two hemispheres, its axis along the local y axis.")
      .def(py::init([](Real radius, Real halfHeight) {
             Capsule c{radius, halfHeight};
             validate(c);
             return c;
           }),
           py::arg("radius") = 0.5, py::arg("half_height") = 0.5)
      .def_readonly("radius", &Capsule::radius, "Radius (m).")
      .def_readonly("half_height", &Capsule::halfHeight, "Half the core segment's length (m).")
      .def(py::pickle([](const Capsule& c) { return py::make_tuple(c.radius, c.halfHeight); },
                      [](const py::tuple& t) {
                        return Capsule{t[0].cast<Real>(), t[1].cast<Real>()};
                      }));

  py::class_<Cylinder>(m, "Cylinder", "A solid cylinder, its axis along the local y axis.")
      .def(py::init([](Real radius, Real halfHeight) {
             Cylinder c{radius, halfHeight};
             validate(c);
             return c;
           }),
           py::arg("radius") = 0.5, py::arg("half_height") = 0.5)
      .def_readonly("radius", &Cylinder::radius, "Radius (m).")
      .def_readonly("half_height", &Cylinder::halfHeight, "Half the height (m).")
      .def(py::pickle([](const Cylinder& c) { return py::make_tuple(c.radius, c.halfHeight); },
                      [](const py::tuple& t) {
                        return Cylinder{t[0].cast<Real>(), t[1].cast<Real>()};
                      }));

  py::class_<Box>(m, "Box", "A box centred at the local origin.")
      .def(py::init([](py::handle halfExtents) {
             Box b{toVec3(halfExtents, "half_extents")};
             validate(b);
             return b;
           }),
           py::arg("half_extents"))
      .def_property_readonly(
          "half_extents", [](const Box& b) { return fromVec3(b.halfExtents); },
          "Half the side lengths (m).")
      .def(py::pickle([](const Box& b) { return py::make_tuple(fromVec3(b.halfExtents)); },
                      [](const py::tuple& t) { return Box{toVec3(t[0], "half_extents")}; }));

  py::class_<Plane>(m, "Plane",
                    "The half-space {x : normal . x <= offset}, solid below (static bodies only).")
      .def(py::init([](py::handle normal, Real offset) {
             Plane p{toVec3(normal, "normal"), offset};
             validate(p);
             return p;
           }),
           py::arg("normal") = py::make_tuple(0, 1, 0), py::arg("offset") = 0)
      .def_property_readonly(
          "normal", [](const Plane& p) { return fromVec3(p.normal); }, "Outward normal.")
      .def_readonly("offset", &Plane::offset, "Distance of the plane from the origin (m).")
      .def(py::pickle([](const Plane& p) { return py::make_tuple(fromVec3(p.normal), p.offset); },
                      [](const py::tuple& t) {
                        return Plane{toVec3(t[0], "normal"), t[1].cast<Real>()};
                      }));

  py::class_<ConvexHull, std::shared_ptr<ConvexHull>>(m, "ConvexHull",
                                                      "The convex hull of points (Qhull).")
      .def(py::init([](py::handle points) {
             std::vector<Vec3> p = toPoints(points, "points");
             return std::make_shared<ConvexHull>(std::span<const Vec3>(p));
           }),
           py::arg("points"), "points: (n, 3) array (m), at least 4 not coplanar.")
      .def_property_readonly(
          "vertices",
          [](const ConvexHull& h) {
            RealArray a({py::ssize_t(h.vertices().size()), py::ssize_t(3)});
            for (std::size_t i = 0; i < h.vertices().size(); ++i)
              for (int k = 0; k < 3; ++k) a.mutable_at(py::ssize_t(i), k) = h.vertices()[i][k];
            return a;
          },
          "The hull's vertices (m), (n, 3).");

  py::class_<TriangleMesh, std::shared_ptr<TriangleMesh>>(
      m, "TriangleMesh", "A triangle mesh (closed when on a dynamic body).")
      .def(py::init([](py::handle vertices, const std::vector<std::array<std::int64_t, 3>>& tris) {
             std::vector<Triangle> triangles;
             for (const auto& t : tris) {
               for (std::int64_t i : t)
                 if (i < 0 || i > std::int64_t(UINT32_MAX))
                   argumentError("triangles", "index " + std::to_string(i) + " out of range");
               triangles.push_back({std::uint32_t(t[0]), std::uint32_t(t[1]), std::uint32_t(t[2])});
             }
             return std::make_shared<TriangleMesh>(toPoints(vertices, "vertices"),
                                                   std::move(triangles));
           }),
           py::arg("vertices"), py::arg("triangles"),
           "vertices: (n, 3) array (m); triangles: (k, 3) vertex indices, counter-clockwise "
           "seen from outside.")
      .def_property_readonly("is_closed", &TriangleMesh::isClosed);

  py::class_<HeightField, std::shared_ptr<HeightField>>(
      m, "HeightField",
      "Terrain: sample (i, j) of heights lies at (j * spacing, heights[i][j], i * spacing).")
      .def(py::init([](py::handle heights, Real spacing) {
             RealArray a = toRows(heights, "heights", -1);
             std::vector<std::vector<Real>> rows(std::size_t(a.shape(0)));
             for (py::ssize_t i = 0; i < a.shape(0); ++i)
               for (py::ssize_t j = 0; j < a.shape(1); ++j)
                 rows[std::size_t(i)].push_back(a.at(i, j));
             return std::make_shared<HeightField>(rows, spacing);
           }),
           py::arg("heights"), py::arg("spacing"), "heights: (rows, cols) (m); spacing (m).");

  py::class_<Compound, std::shared_ptr<Compound>>(m, "Compound",
                                                  "Several shapes rigidly joined, each posed.")
      .def(py::init([](const py::list& children) {
             std::vector<CompoundChild> list;
             for (py::handle c : children) {
               if (!py::isinstance<py::tuple>(c) || py::len(c) < 1 || py::len(c) > 3)
                 argumentError("children", "each child is (shape, position, orientation)");
               py::tuple t = py::reinterpret_borrow<py::tuple>(c);
               const py::object position = t.size() > 1 ? py::object(t[1]) : py::none();
               const py::object orientation = t.size() > 2 ? py::object(t[2]) : py::none();
               list.push_back({toShape(t[0], "children"), toPose(position, orientation)});
             }
             return std::make_shared<Compound>(std::move(list));
           }),
           py::arg("children"),
           "children: [(shape, position, orientation)], position (m) and orientation "
           "[w, x, y, z] optional.");
}

}  // namespace inertia::python
