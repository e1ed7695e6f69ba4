// Deformables of a World: mass-spring models from the library's generators (rope, cloth, soft
// box, soft sphere), their creation, fields and obstacles, and the vertices as NumPy arrays
// that alias the deformable's memory (positions and velocities are contiguous (n, 3) blocks).
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "bindings.h"
#include "convert.h"
#include "inertia/deformable/generators.h"
#include "shapes.h"

namespace inertia::python {

namespace {

SpringStiffness stiffness(Real stretch, Real shear, Real bend) { return {stretch, shear, bend}; }

std::array<int, 3> toInts3(const std::vector<int>& v, const char* arg) {
  if (v.size() != 3) argumentError(arg, "expected 3 integers");
  return {v[0], v[1], v[2]};
}

// The model's pinned vertices from a sequence of indices (checked by the library on creation).
void pin(MassSpringModel& model, const std::vector<std::int64_t>& pinned) {
  for (std::int64_t i : pinned) {
    if (i < 0 || std::size_t(i) >= model.vertexCount())
      argumentError("pinned", "vertex " + std::to_string(i) + " out of range (the model has " +
                                  std::to_string(model.vertexCount()) + " vertices)");
    model.pinned.push_back(std::uint32_t(i));
  }
}

void bindModel(py::module_& m) {
  py::class_<MassSpringModel>(m, "MassSpringModel",
                              "A deformable's initial state and structure (vertices, masses, "
                              "springs, triangles, pinned vertices), as the generators rope, "
                              "cloth, soft_box, soft_sphere, hair and soft_mesh build it.")
      .def_property_readonly("vertex_count", &MassSpringModel::vertexCount)
      .def_property_readonly(
          "positions",
          [](const MassSpringModel& model) {
            RealArray a({py::ssize_t(model.vertexCount()), py::ssize_t(3)});
            for (std::size_t i = 0; i < model.vertexCount(); ++i)
              for (int k = 0; k < 3; ++k) a.mutable_at(py::ssize_t(i), k) = model.positions[i][k];
            return a;
          },
          "Rest positions (m), (n, 3), a copy.")
      .def_property_readonly(
          "masses", [](const MassSpringModel& model) { return RealArray(py::cast(model.masses)); },
          "(kg), (n,), a copy.")
      .def_property_readonly("spring_count",
                             [](const MassSpringModel& model) { return model.springs.size(); })
      .def_property_readonly("triangle_count",
                             [](const MassSpringModel& model) { return model.triangles.size(); })
      .def_property(
          "pinned", [](const MassSpringModel& model) { return model.pinned; },
          [](MassSpringModel& model, const std::vector<std::int64_t>& pinned) {
            model.pinned.clear();
            pin(model, pinned);
          },
          "Indices of the vertices held where they are.");

  m.def(
      "rope",
      [](py::handle start, py::handle end, int segments, Real mass, Real stretch, Real bend,
         Real damping, const std::vector<std::int64_t>& pinned) {
        MassSpringModel model =
            rope(RopeSettings{toVec3(start, "start"), toVec3(end, "end"), segments, mass,
                              stiffness(stretch, 0, bend), damping});
        pin(model, pinned);
        return model;
      },
      py::kw_only(), py::arg("start") = py::make_tuple(0, 0, 0),
      py::arg("end") = py::make_tuple(1, 0, 0), py::arg("segments") = 10, py::arg("mass") = 1,
      py::arg("stretch") = 5000, py::arg("bend") = 5, py::arg("damping") = 0,
      py::arg("pinned") = std::vector<std::int64_t>{},
      "A rope or hair strand from start to end (m): segments + 1 vertices, mass (kg, total) "
      "spread evenly, stretch and bend stiffness per spring (N/m), damping per spring (N s/m); "
      "pinned: vertex indices held in place.");
  m.def(
      "cloth",
      [](py::handle position, py::handle orientation, std::array<Real, 2> size,
         std::array<int, 2> resolution, Real mass, Real stretch, Real shear, Real bend,
         Real damping, const std::vector<std::int64_t>& pinned) {
        MassSpringModel model =
            cloth(ClothSettings{toPose(position, orientation), size, resolution, mass,
                                stiffness(stretch, shear, bend), damping});
        pin(model, pinned);
        return model;
      },
      py::kw_only(), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
      py::arg("size") = std::array<Real, 2>{1, 1},
      py::arg("resolution") = std::array<int, 2>{10, 10}, py::arg("mass") = 1,
      py::arg("stretch") = 5000, py::arg("shear") = 500, py::arg("bend") = 5,
      py::arg("damping") = 0, py::arg("pinned") = std::vector<std::int64_t>{},
      "A cloth rectangle of size (m, along its local x and z) centred at position (m), normal "
      "+y turned by orientation [w, x, y, z]; resolution: cells along x and z (vertex "
      "i + j (nx + 1) at column i, row j). Stiffness per spring (N/m), damping (N s/m), mass "
      "(kg, total).");
  m.def(
      "soft_box",
      [](py::handle position, py::handle orientation, py::handle halfExtents,
         const std::vector<int>& resolution, Real mass, Real stretch, Real shear, Real bend,
         Real damping, const std::vector<std::int64_t>& pinned) {
        MassSpringModel model = softBox(SoftBoxSettings{
            toPose(position, orientation), toVec3(halfExtents, "half_extents"),
            toInts3(resolution, "resolution"), mass, stiffness(stretch, shear, bend), damping});
        pin(model, pinned);
        return model;
      },
      py::kw_only(), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
      py::arg("half_extents") = py::make_tuple(0.5, 0.5, 0.5),
      py::arg("resolution") = std::vector<int>{4, 4, 4}, py::arg("mass") = 1,
      py::arg("stretch") = 5000, py::arg("shear") = 500, py::arg("bend") = 5,
      py::arg("damping") = 0, py::arg("pinned") = std::vector<std::int64_t>{},
      "A soft box of half_extents (m): a lattice of resolution cells per axis. Stiffness per "
      "spring (N/m), damping (N s/m), mass (kg, total).");
  m.def(
      "soft_sphere",
      [](py::handle position, py::handle orientation, Real radius, int subdivisions, Real mass,
         Real stretch, Real bend, Real damping, const std::vector<std::int64_t>& pinned) {
        MassSpringModel model =
            softSphere(SoftSphereSettings{toPose(position, orientation), radius, subdivisions, mass,
                                          stiffness(stretch, 0, bend), damping});
        pin(model, pinned);
        return model;
      },
      py::kw_only(), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
      py::arg("radius") = 0.5, py::arg("subdivisions") = 2, py::arg("mass") = 1,
      py::arg("stretch") = 5000, py::arg("bend") = 5, py::arg("damping") = 0,
      py::arg("pinned") = std::vector<std::int64_t>{},
      "A soft sphere of radius (m): an icosphere (10 * 4^s + 2 surface vertices, s = "
      "subdivisions, 0..5) and its centre, the last vertex. Stiffness per spring (N/m), damping "
      "(N s/m), mass (kg, total).");
  m.def(
      "hair",
      [](py::handle position, py::handle orientation, Real radius, Real capAngle, int strands,
         int segments, Real length, Real mass, Real stretch, Real bend, Real damping) {
        return hair(HairSettings{toPose(position, orientation), radius, capAngle, strands,
                                 segments, length, mass, stiffness(stretch, 0, bend), damping});
      },
      py::kw_only(), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
      py::arg("radius") = 0.1, py::arg("cap_angle") = 1.2, py::arg("strands") = 100,
      py::arg("segments") = 16, py::arg("length") = 0.2, py::arg("mass") = 0.05,
      py::arg("stretch") = 5000, py::arg("bend") = 5, py::arg("damping") = 0,
      "Hair: strands straight strands rooted on a sphere of radius (m) about position, within "
      "cap_angle (rad) of its +y axis, each length (m) along the normal in segments; strand s is "
      "vertices s (segments + 1) .. s (segments + 1) + segments, its root pinned. Stiffness per "
      "spring (N/m), damping (N s/m), mass (kg, total).");
  m.def(
      "soft_mesh",
      [](const TriangleMesh& mesh, py::handle position, py::handle orientation, int resolution,
         int ties, Real mass, Real stretch, Real shear, Real bend, Real damping,
         const std::vector<std::int64_t>& pinned) {
        MassSpringModel model =
            softMesh(SoftMeshSettings{toPose(position, orientation), &mesh, resolution, ties, mass,
                                      stiffness(stretch, shear, bend), damping});
        pin(model, pinned);
        return model;
      },
      py::arg("mesh"), py::kw_only(), py::arg("position") = py::none(),
      py::arg("orientation") = py::none(), py::arg("resolution") = 6, py::arg("ties") = 4,
      py::arg("mass") = 1, py::arg("stretch") = 5000, py::arg("shear") = 500,
      py::arg("bend") = 5, py::arg("damping") = 0, py::arg("pinned") = std::vector<std::int64_t>{},
      "A soft body from a closed TriangleMesh (faces counter-clockwise from outside): its "
      "vertices first, with springs on the edges and across them, then an interior lattice of "
      "resolution cells along the longest side that holds the volume, each surface vertex tied "
      "to its ties nearest lattice vertices. Stiffness per spring (N/m), damping (N s/m), mass "
      "(kg, total).");
}

// Writes (n, 3) rows into a deformable one vertex at a time (the library checks each value).
template <class Set>
void writeVertices(Deformable& d, py::handle value, const char* arg, Set set) {
  RealArray a = toMatrix(value, arg, py::ssize_t(d.vertexCount()), 3);
  const Real* in = a.data();
  for (std::size_t i = 0; i < 3 * d.vertexCount(); ++i)
    if (!std::isfinite(in[i])) argumentError(arg, "values must be finite");
  for (std::size_t i = 0; i < d.vertexCount(); ++i, in += 3) (d.*set)(i, Vec3(in[0], in[1], in[2]));
}

std::size_t vertexIndex(const Deformable& d, std::int64_t vertex) {
  if (vertex < 0 || std::size_t(vertex) >= d.vertexCount())
    throw py::index_error("vertex " + std::to_string(vertex) + " out of range (" +
                          std::to_string(d.vertexCount()) + " vertices)");
  return std::size_t(vertex);
}

void bindCreation(py::class_<PyWorld>& world) {
  world
      .def(
          "create_deformable",
          [](PyWorld& w, const MassSpringModel& model, const std::string& name,
             const std::string& integrator, Real thickness, Real friction, Real tearStrain,
             double solverTolerance, int solverMaxIterations, const std::string& linearSolver,
             bool collideWithBodies) {
            DeformableSettings s;
            s.name = name;
            if (integrator == "implicit_euler") {
              s.integrator = ode::Method::BackwardEuler;
            } else {
              const std::optional<ode::Method> method = ode::methodFromName(integrator);
              if (!method) argumentError("integrator", "unknown integrator '" + integrator + "'");
              s.integrator = *method;
            }
            s.thickness = thickness;
            s.friction = friction;
            s.tearStrain = tearStrain;
            s.solverTolerance = solverTolerance;
            s.solverMaxIterations = solverMaxIterations;
            if (linearSolver == "automatic")
              s.linearSolver = DeformableLinearSolver::Automatic;
            else if (linearSolver == "conjugate_gradient")
              s.linearSolver = DeformableLinearSolver::ConjugateGradient;
            else if (linearSolver == "direct")
              s.linearSolver = DeformableLinearSolver::Direct;
            else
              argumentError("linear_solver", "'" + linearSolver +
                                                 "' is not automatic, conjugate_gradient or direct");
            s.collideWithBodies = collideWithBodies;
            return w->createDeformable(s, model);
          },
          py::arg("model"), py::kw_only(), py::arg("name") = "",
          py::arg("integrator") = "implicit_euler", py::arg("thickness") = 0.01,
          py::arg("friction") = 0.3, py::arg("tear_strain") = 0, py::arg("solver_tolerance") = 1e-6,
          py::arg("solver_max_iterations") = 1000, py::arg("linear_solver") = "automatic",
          py::arg("collide_with_bodies") = true,
          "Adds a deformable built from model (inertia.rope, cloth, soft_box, soft_sphere, hair, "
          "soft_mesh). "
          "integrator: 'implicit_euler' (Baraff and Witkin) or an explicit method's name; "
          "thickness kept from obstacles (m); friction against them (Coulomb); tear_strain: a "
          "spring breaks past (l - L) / L (0: never); the implicit solve's relative tolerance "
          "and iteration cap; linear_solver: how each Newton system is solved, 'direct' (sparse "
          "LDL^T), 'conjugate_gradient' (modified PCG) or 'automatic' (direct for strands); "
          "collide_with_bodies: the bodies' shapes are obstacles (one way). "
          "Gravity acts only through fields: add_deformable_field(d, inertia.GravityField(g)).")
      .def(
          "destroy_deformable",
          [](PyWorld& w, DeformableId id) {
            if (std::as_const(w)->isValid(id))  // a read: the recipe stays
              PyWorld::refuseViewed(w.deformableViews, id.index, "destroy_deformable",
                                    "its vertices");
            w->destroyDeformable(id);
          },
          py::arg("deformable"))
      .def(
          "deformables", [](const PyWorld& w) { return w->deformables(); },
          "The live deformables in slot order (the order the world steps them).")
      .def(
          "deformable_name",
          [](const PyWorld& w, DeformableId id) { return w->deformable(id).name(); },
          py::arg("deformable"))
      .def(
          "add_deformable_field",
          [](PyWorld& w, DeformableId id, py::handle field, py::handle region) {
            return w->deformable(id).addField(toForceField(field, region));
          },
          py::arg("deformable"), py::arg("field"), py::arg("region") = py::none(),
          "A force field (inertia.GravityField, ...) acting on every vertex, optionally only "
          "inside the box region = (lower, upper) (m).")
      .def(
          "add_deformable_obstacle",
          [](PyWorld& w, DeformableId id, py::handle shape, py::handle position,
             py::handle orientation) {
            return w->deformable(id).addObstacle(
                Obstacle{Collider(toShape(shape, "shape")), toPose(position, orientation)});
          },
          py::arg("deformable"), py::arg("shape"), py::kw_only(), py::arg("position") = py::none(),
          py::arg("orientation") = py::none(),
          "A static shape at position (m) and orientation the vertices collide with.");
}

void bindVertices(py::class_<PyWorld>& world) {
  world
      .def(
          "deformable_vertex_count",
          [](const PyWorld& w, DeformableId id) { return w->deformable(id).vertexCount(); },
          py::arg("deformable"))
      .def(
          "deformable_positions",
          [](py::object self, DeformableId id) {
            const Deformable& d = self.cast<const PyWorld&>()->deformable(id);
            return countedView(self, &PyWorld::deformableViews, id.index, d.positions().data(),
                               d.vertexCount(), 3);
          },
          py::arg("deformable"),
          "Vertex positions (m), (n, 3): a read-only view of the deformable's memory, not a copy "
          "(it follows the steps; set_deformable_positions writes).")
      .def(
          "deformable_velocities",
          [](py::object self, DeformableId id) {
            const Deformable& d = self.cast<const PyWorld&>()->deformable(id);
            return countedView(self, &PyWorld::deformableViews, id.index, d.velocities().data(),
                               d.vertexCount(), 3);
          },
          py::arg("deformable"), "Vertex velocities (m/s), (n, 3): a read-only view.")
      .def(
          "deformable_masses",
          [](py::object self, DeformableId id) {
            const Deformable& d = self.cast<const PyWorld&>()->deformable(id);
            return countedView(self, &PyWorld::deformableViews, id.index, d.masses().data(),
                               d.vertexCount(), 1);
          },
          py::arg("deformable"), "Vertex masses (kg), (n,): a read-only view.")
      .def(
          "set_deformable_positions",
          [](PyWorld& w, DeformableId id, py::handle a) {
            writeVertices(w->deformable(id), a, "positions", &Deformable::setPosition);
          },
          py::arg("deformable"), py::arg("positions"), "(m), (n, 3), every vertex.")
      .def(
          "set_deformable_velocities",
          [](PyWorld& w, DeformableId id, py::handle a) {
            writeVertices(w->deformable(id), a, "velocities", &Deformable::setVelocity);
          },
          py::arg("deformable"), py::arg("velocities"),
          "(m/s), (n, 3), every vertex; pinned vertices keep velocity zero.")
      .def(
          "set_vertex_pinned",
          [](PyWorld& w, DeformableId id, std::int64_t vertex, bool pinned) {
            Deformable& d = w->deformable(id);
            d.setPinned(vertexIndex(d, vertex), pinned);
          },
          py::arg("deformable"), py::arg("vertex"), py::arg("pinned") = true,
          "Holds a vertex where it is now (velocity zero), or frees it.")
      .def(
          "is_vertex_pinned",
          [](const PyWorld& w, DeformableId id, std::int64_t vertex) {
            const Deformable& d = w->deformable(id);
            return d.isPinned(vertexIndex(d, vertex));
          },
          py::arg("deformable"), py::arg("vertex"))
      .def(
          "deformable_springs",
          [](const PyWorld& w, DeformableId id) {
            const auto springs = w->deformable(id).springs();
            py::array_t<std::uint32_t> a({py::ssize_t(springs.size()), py::ssize_t(2)});
            for (std::size_t i = 0; i < springs.size(); ++i)
              a.mutable_at(py::ssize_t(i), 0) = springs[i].a,
                                           a.mutable_at(py::ssize_t(i), 1) = springs[i].b;
            return a;
          },
          py::arg("deformable"), "Each spring's two vertices, (m, 2), a copy.")
      .def(
          "deformable_broken",
          [](const PyWorld& w, DeformableId id) {
            const Deformable& d = w->deformable(id);
            py::array_t<bool> a(py::ssize_t(d.springs().size()));
            for (std::size_t i = 0; i < d.springs().size(); ++i)
              a.mutable_at(py::ssize_t(i)) = d.isBroken(i);
            return a;
          },
          py::arg("deformable"), "Per spring (deformable_springs' order): torn, (m,).")
      .def(
          "deformable_triangles",
          [](const PyWorld& w, DeformableId id) {
            const auto tris = w->deformable(id).triangles();
            py::array_t<std::uint32_t> a({py::ssize_t(tris.size()), py::ssize_t(3)});
            for (std::size_t i = 0; i < tris.size(); ++i)
              for (int k = 0; k < 3; ++k) a.mutable_at(py::ssize_t(i), k) = tris[i][std::size_t(k)];
            return a;
          },
          py::arg("deformable"), "Surface triangles (vertex indices), (t, 3), a copy.")
      .def(
          "deformable_energy",
          [](const PyWorld& w, DeformableId id) {
            const Deformable& d = w->deformable(id);
            py::dict e;
            e["kinetic"] = d.kineticEnergy();
            e["spring"] = d.springEnergy();
            return e;
          },
          py::arg("deformable"), "Kinetic and spring potential energy (J).");
}

}  // namespace

void bindDeformables(py::module_& m) {
  bindModel(m);
  py::class_<PyWorld> world = worldClass(m);
  bindCreation(world);
  bindVertices(world);
}

}  // namespace inertia::python
