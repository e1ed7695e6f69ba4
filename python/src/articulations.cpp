// A World's articulations: World.create_articulation(model, ...) and the inertia.Articulation
// handle it returns (the world and the ArticulationId): the state q and qd as NumPy arrays,
// written back in one call, joint forces, drives, and the link bodies' poses and velocities as
// (n, 3) and (n, 4) arrays. A handle keeps its world alive; once its articulation is destroyed
// every use raises InvalidArgument, and while another thread steps the world, RuntimeError.
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "articulation_model.h"
#include "bindings.h"
#include "convert.h"
#include "inertia/core/error.h"
#include "shapes.h"

namespace inertia::python {

namespace art = inertia::articulation;

namespace {

struct PyArticulation {
  py::object world;  // the inertia.World
  ArticulationId id;

  PyWorld& owner() const { return world.cast<PyWorld&>(); }
  /// The world to read, checked: RuntimeError while it steps, InvalidArgument once the
  /// articulation is gone.
  const World& reading() const {
    const World& w = *std::as_const(owner());
    check(w);
    return w;
  }
  /// The world to change (it no longer follows its recipe), checked as reading().
  World& changing() const {
    World& w = *owner();
    check(w);
    return w;
  }
  const art::Articulation<Real>& get() const { return reading().articulation(id); }

 private:
  void check(const World& w) const {
    if (!w.isValid(id))
      throw InvalidArgument("Articulation (index " + std::to_string(id.index) +
                            "): destroyed; its world no longer has it");
  }
};

std::string defaultName(const World& w) {
  return "articulation" + std::to_string(w.articulations().size());
}

// The link bodies, in link order.
std::vector<BodyId> linkBodies(const World& w, ArticulationId id) {
  std::vector<BodyId> ids;
  for (int i = 0; i < w.articulation(id).model().linkCount(); ++i) ids.push_back(w.linkBody(id, i));
  return ids;
}

// The link bodies' state, one row per link in link order.
template <class Get>
RealArray linkRows(const PyArticulation& a, py::ssize_t cols, Get get) {
  const World& w = a.reading();
  return bodyRows(linkBodies(w, a.id), cols, [&](BodyId b, Real* out) { return get(w, b, out); });
}

PyArticulation createArticulation(py::object self, const PyModel& model, std::string name,
                                  py::handle position, py::handle orientation, py::handle q,
                                  py::handle qd, int constraintIterations, Real limitBaumgarte,
                                  bool selfCollision) {
  PyWorld& w = self.cast<PyWorld&>();
  WorldArticulationSettings s;
  s.name = name.empty() ? defaultName(*std::as_const(w)) : std::move(name);
  if (model.model.linkCount() == 0) argumentError("model", "has no links");
  s.model = model.model;
  s.shapes = model.shapes;
  s.base = toPose(position, orientation);
  if (!(s.base.q.coeffs().allFinite() && s.base.q.norm() > Real(1e-6)))
    argumentError("orientation", "must be a finite, non-zero quaternion");
  s.base.q.normalize();
  if (!q.is_none()) s.q = toConfiguration(model.model, q, "q");
  if (!qd.is_none()) s.qd = toVector(qd, "qd", model.model.nv());
  s.solver.constraintIterations = constraintIterations;
  s.solver.limitBaumgarte = limitBaumgarte;
  s.selfCollision = selfCollision;
  return PyArticulation{self, w->createArticulation(s)};
}

void bindHandle(py::module_& m) {
  py::class_<PyArticulation> c(
      m, "Articulation",
      "An articulation of a World (World.create_articulation, World.articulations): its links "
      "are dynamic bodies of the world named NAME/LINK that collide with the rest, stepped in "
      "the world's substeps in the world's gravity. Reads and writes go to the world's "
      "articulation; once destroyed, the handle raises InvalidArgument.");
  c.def_property_readonly(
       "id", [](const PyArticulation& a) { return a.id; }, "Its ArticulationId.")
      .def_property_readonly(
          "world", [](const PyArticulation& a) { return a.world; }, "The World it belongs to.")
      .def(
          "is_valid",
          [](const PyArticulation& a) { return std::as_const(a.owner())->isValid(a.id); },
          "False once destroyed.")
      .def_property_readonly(
          "name",
          [](const PyArticulation& a) { return std::string(a.reading().articulationName(a.id)); })
      .def_property_readonly(
          "model",
          [](const PyArticulation& a) {
            return PyModel{a.get().model(), {}};
          },
          "A copy of its model (without the shapes, which are on the link bodies), with the "
          "world's gravity in base axes and the drives as they are now: for the functions of "
          "(model, q, qd) such as aba, crba and point_jacobian (base frame).")
      .def_property_readonly(
          "nq", [](const PyArticulation& a) { return a.get().model().nq(); }, "Size of q.")
      .def_property_readonly(
          "nv", [](const PyArticulation& a) { return a.get().model().nv(); }, "Size of qd.")
      .def_property_readonly("link_count",
                             [](const PyArticulation& a) { return a.get().model().linkCount(); })
      .def_property_readonly(
          "q",
          [](const PyArticulation& a) {
            const art::VectorX<Real>& q = a.get().q();
            return countedView(a.world, &PyWorld::articulationViews, a.id.index, q.data(),
                               std::size_t(q.size()), 1);
          },
          "Joint coordinates (rad, m, unit quaternions [w, x, y, z]), (nq,): a read-only view "
          "of the world's memory, which the steps update (np.copy keeps a moment); set_state "
          "writes them.")
      .def_property_readonly(
          "qd",
          [](const PyArticulation& a) {
            const art::VectorX<Real>& qd = a.get().qd();
            return countedView(a.world, &PyWorld::articulationViews, a.id.index, qd.data(),
                               std::size_t(qd.size()), 1);
          },
          "Joint velocities (rad/s, m/s), (nv,): a read-only view, as q.")
      .def(
          "set_state",
          [](const PyArticulation& a, py::handle q, py::handle qd) {
            World& w = a.changing();
            art::Articulation<Real>& x = w.articulation(a.id);
            const art::VectorX<Real> qv = toConfiguration(x.model(), q, "q");
            const art::VectorX<Real> qdv =
                qd.is_none() ? art::VectorX<Real>(x.qd()) : toVector(qd, "qd", x.model().nv());
            x.setState(qv, qdv);  // normalises the quaternions
            w.syncArticulation(a.id);
          },
          py::arg("q"), py::arg("qd") = py::none(),
          "Sets q (nq,) and qd (nv,; None keeps the current one) in one call and moves the "
          "link bodies there.")
      .def(
          "set_joint_forces",
          [](const PyArticulation& a, py::handle tau) {
            art::Articulation<Real>& x = a.changing().articulation(a.id);
            x.setJointForces(toVector(tau, "tau", x.model().nv()));
          },
          py::arg("tau"), "Joint forces (N m or N), (nv,), applied at every step until changed.")
      .def(
          "set_drive_target",
          [](const PyArticulation& a, int dof, Real target, Real targetVelocity) {
            art::Articulation<Real>& x = a.changing().articulation(a.id);
            if (dof < 0 || dof >= x.model().nv())
              argumentError("dof", "no degree of freedom " + std::to_string(dof) + " (nv is " +
                                       std::to_string(x.model().nv()) + ")");
            if (!std::isfinite(target)) argumentError("target", "must be finite");
            if (!std::isfinite(targetVelocity)) argumentError("target_velocity", "must be finite");
            x.setDriveTarget(dof, target, targetVelocity);
          },
          py::arg("dof"), py::arg("target"), py::arg("target_velocity") = 0,
          "Moves the drive of degree of freedom dof to target (rad or m) and target_velocity "
          "(rad/s or m/s).")
      .def(
          "set_drive_targets",
          [](const PyArticulation& a, py::handle targets, py::handle velocities) {
            art::Articulation<Real>& x = a.changing().articulation(a.id);
            const int nv = x.model().nv();
            const art::VectorX<Real> t = toVector(targets, "targets", nv);
            const art::VectorX<Real> v = velocities.is_none()
                                             ? art::VectorX<Real>::Zero(nv).eval()
                                             : toVector(velocities, "target_velocities", nv);
            for (int dof = 0; dof < nv; ++dof)
              if (x.model().scalarQIndex()[std::size_t(dof)] >= 0)
                x.setDriveTarget(dof, t(dof), v(dof));
          },
          py::arg("targets"), py::arg("target_velocities") = py::none(),
          "Every revolute and prismatic dof's drive target (rad or m), (nv,), and target "
          "velocity (rad/s or m/s; None: zero), in one call; the entries of spherical and "
          "floating joints' dofs are not used.")
      .def(
          "set_drive",
          [](const PyArticulation& a, int dof, const art::Drive<Real>& d) {
            a.changing().articulation(a.id).setDrive(dof, d);
          },
          py::arg("dof"), py::arg("drive"), "Replaces a revolute or prismatic dof's drive.")
      .def_property_readonly(
          "drives", [](const PyArticulation& a) { return a.get().model().drives(); },
          "Per degree of freedom, copies.")
      .def_property_readonly(
          "constraint_impulses",
          [](const PyArticulation& a) { return fromVector(a.get().constraintImpulses()); },
          "The last substep's joint-space impulses of limits, friction, damping and drives "
          "(N m s or N s), (nv,).")
      .def(
          "link_bodies", [](const PyArticulation& a) { return linkBodies(a.reading(), a.id); },
          "The link bodies, in link order (contacts and ray hits name them).")
      .def(
          "link_positions",
          [](const PyArticulation& a) {
            return linkRows(
                a, 3, [](const World& w, BodyId b, Real* o) { return put(w.transform(b).p, o); });
          },
          "The links' frames' origins in the world (m), (n, 3).")
      .def(
          "link_orientations",
          [](const PyArticulation& a) {
            return linkRows(
                a, 4, [](const World& w, BodyId b, Real* o) { return put(w.transform(b).q, o); });
          },
          "The links' orientations in the world [w, x, y, z], (n, 4).")
      .def(
          "link_linear_velocities",
          [](const PyArticulation& a) {
            return linkRows(a, 3, [](const World& w, BodyId b, Real* o) {
              return put(w.linearVelocity(b), o);
            });
          },
          "Velocities of the links' centres of mass (m/s, world), (n, 3).")
      .def(
          "link_angular_velocities",
          [](const PyArticulation& a) {
            return linkRows(a, 3, [](const World& w, BodyId b, Real* o) {
              return put(w.angularVelocity(b), o);
            });
          },
          "(rad/s, world), (n, 3).")
      .def("__eq__", [](const PyArticulation& a,
                        const PyArticulation& b) { return a.world.is(b.world) && a.id == b.id; })
      .def("__hash__",
           [](const PyArticulation& a) {
             return py::hash(py::make_tuple(a.id.index, a.id.generation));
           })
      .def("__repr__", [](const PyArticulation& a) {
        const World& w = *std::as_const(a.owner());
        if (!w.isValid(a.id)) return std::string("Articulation(destroyed)");
        return "Articulation('" + std::string(w.articulationName(a.id)) + "', " +
               std::to_string(w.articulation(a.id).model().linkCount()) + " links)";
      });
}

PyArticulation handleOf(py::handle world, ArticulationId id) {
  return PyArticulation{py::reinterpret_borrow<py::object>(world), id};
}

ArticulationId toArticulationId(py::handle value, const char* arg) {
  if (py::isinstance<PyArticulation>(value)) return value.cast<const PyArticulation&>().id;
  if (py::isinstance<ArticulationId>(value)) return value.cast<ArticulationId>();
  argumentError(arg, "expected an inertia.Articulation or ArticulationId, got " +
                         std::string(py::str(py::type::of(value))));
}

void bindWorldMethods(py::module_& m) {
  py::class_<PyWorld> world = worldClass(m);
  world
      .def("create_articulation", &createArticulation, py::arg("model"), py::kw_only(),
           py::arg("name") = "", py::arg("position") = py::none(),
           py::arg("orientation") = py::none(), py::arg("q") = py::none(),
           py::arg("qd") = py::none(), py::arg("constraint_iterations") = 20,
           py::arg("limit_baumgarte") = 0.2, py::arg("self_collision") = false,
           "Adds an articulation of an ArticulationModel (copied) and returns its handle. "
           "name (default 'articulationN'): its links' bodies are named NAME/LINK; the base "
           "frame at position (m) and orientation [w, x, y, z] in the world; q (nq,) and qd "
           "(nv,) the initial state (default: the neutral configuration at rest); "
           "constraint_iterations (1..1000): kept with the model, for C++'s Articulation::step "
           "alone; in a world the joint rows are swept with the contacts, once per solver and "
           "relax iteration of the world; "
           "limit_baumgarte: the fraction (0..1) of a limit's violation removed per step; "
           "self_collision: its links collide with each other (each with all but its parent "
           "and children).")
      .def(
          "destroy_articulation",
          [](PyWorld& w, py::handle a) {
            const ArticulationId id = toArticulationId(a, "articulation");
            if (std::as_const(w)->isValid(id))
              PyWorld::refuseViewed(w.articulationViews, id.index, "destroy_articulation",
                                    "its state");
            w->destroyArticulation(id);
          },
          py::arg("articulation"),
          "Removes it and its link bodies; its handles then raise InvalidArgument.")
      .def("is_valid", [](const PyWorld& w, ArticulationId id) { return w->isValid(id); })
      .def(
          "articulations",
          [](py::object self) {
            std::vector<PyArticulation> out;
            for (ArticulationId id : std::as_const(self.cast<PyWorld&>())->articulations())
              out.push_back(handleOf(self, id));
            return out;
          },
          "The live articulations in slot order (a scene's in the order of its file).")
      .def(
          "find_articulation",
          [](py::object self, const std::string& name) {
            const PyWorld& w = self.cast<PyWorld&>();
            for (ArticulationId id : w->articulations())
              if (w->articulationName(id) == name) return handleOf(self, id);
            throw py::key_error("no articulation named '" + name + "'");
          },
          py::arg("name"), "The first articulation with this name (KeyError when none has it).")
      .def(
          "articulation",
          [](py::object self, ArticulationId id) {
            if (!std::as_const(self.cast<PyWorld&>())->isValid(id))
              argumentError("id", "not an articulation of this world");
            return handleOf(self, id);
          },
          py::arg("id"), "The handle of an ArticulationId.");
}

}  // namespace

void bindArticulations(py::module_& m) {
  bindHandle(m);
  bindWorldMethods(m);
}

}  // namespace inertia::python
