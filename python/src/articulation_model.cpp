// Articulation models and the algorithms over them: inertia.ArticulationModel (links added
// parents first, as the scene files' "articulations" give them), inertia.Drive, inertia.LinkShape,
// and the library's Featherstone algorithms as functions of (model, q, qd): aba, rnea, crba,
// forward_dynamics_crba, point_jacobian, link_pose, point_position, the energies, the centre of
// mass and the momentum. Nothing is computed here: every function calls the library's.
#include "articulation_model.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "convert.h"
#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"
#include "shapes.h"

namespace inertia::python {

namespace art = inertia::articulation;

namespace {

constexpr std::pair<const char*, art::JointType> kJointTypes[] = {
    {"revolute", art::JointType::Revolute},
    {"prismatic", art::JointType::Prismatic},
    {"spherical", art::JointType::Spherical},
    {"fixed", art::JointType::Fixed},
    {"floating", art::JointType::Floating}};

art::JointType toJointType(const std::string& name) {
  for (const auto& [n, t] : kJointTypes)
    if (name == n) return t;
  argumentError("joint", "unknown joint type '" + name +
                             "' (revolute, prismatic, spherical, fixed, floating)");
}

const char* jointTypeName(art::JointType type) {
  for (const auto& [n, t] : kJointTypes)
    if (t == type) return n;
  return "?";
}

/// A collision shape of a link as Python gives it: the shape object (kept for reading back),
/// its material and pose.
struct PyLinkShape {
  py::object shape;
  Material material;
  Transform pose;
};

art::Drive<Real> makeDrive(Real stiffness, Real damping, Real target, Real targetVelocity,
                           Real maxForce) {
  return {stiffness, damping, target, targetVelocity, maxForce};
}

Real toNumber(py::handle value, const char* arg) {
  const double x = PyFloat_AsDouble(value.ptr());
  if (x == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    argumentError(arg, "expected a number, got " + std::string(py::str(py::type::of(value))));
  }
  return Real(x);
}

// The link's mass properties: given (mass with inertia, the principal moments or a 3x3 tensor
// about the centre of mass), or from its shapes' volumes and densities (mass None).
art::LinkInertia<Real> linkInertia(py::handle mass, py::handle com, py::handle inertia,
                                   const std::vector<PyLinkShape>& shapes) {
  if (mass.is_none()) {
    if (!inertia.is_none()) argumentError("inertia", "give it with mass, or neither");
    if (!com.is_none()) argumentError("com", "give it with mass, or neither");
    if (shapes.empty())
      argumentError("mass", "a link needs mass and inertia, or shapes to take them from");
    std::vector<art::LinkShape> parts;
    for (const PyLinkShape& s : shapes)
      parts.push_back({toShape(s.shape, "shapes"), s.pose, s.material.density});
    return art::inertiaFromShapes<Real>(parts);
  }
  art::LinkInertia<Real> in;
  in.mass = toNumber(mass, "mass");
  if (!com.is_none()) in.centerOfMass = toVec3(com, "com");
  if (inertia.is_none()) argumentError("inertia", "required with mass (kg m^2)");
  if (RealArray a = RealArray::ensure(inertia); a && a.ndim() == 1) {
    in.inertia = toVec3(inertia, "inertia").asDiagonal();
  } else {
    RealArray t = toMatrix(inertia, "inertia", 3, 3);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) in.inertia(i, j) = t.at(i, j);
  }
  return in;
}

int addLink(PyModel& m, const std::string& name, py::handle parent, const std::string& joint,
            py::handle axis, py::handle originPosition, py::handle originOrientation,
            py::handle limits, Real damping, Real friction, Real armature, Real velocityLimit,
            py::handle drive, py::handle mass, py::handle com, py::handle inertia,
            py::handle shapes) {
  art::LinkSettings<Real> s;
  s.name = name;
  if (!name.empty() && m.model.findLink(name) >= 0)
    argumentError("name", "the model already has a link named '" + name + "'");
  s.parent = parent.is_none() ? -1 : toLink(m.model, parent, "parent");
  s.joint.type = toJointType(joint);
  s.joint.axis = toVec3(axis, "axis");
  s.joint.originPosition = toVec3(originPosition, "origin_position");
  s.joint.originOrientation = toQuat(originOrientation, "origin_orientation");
  if (!limits.is_none()) {
    Real bounds[2];
    toReals(limits, "limits", bounds, 2);
    s.joint.lower = bounds[0];
    s.joint.upper = bounds[1];
  }
  s.joint.damping = damping;
  s.joint.friction = friction;
  s.joint.armature = armature;
  s.joint.velocityLimit = velocityLimit;
  if (!drive.is_none()) {
    if (!py::isinstance<art::Drive<Real>>(drive))
      argumentError("drive", "expected an inertia.Drive or None, got " +
                                 std::string(py::str(py::type::of(drive))));
    s.joint.drive = drive.cast<art::Drive<Real>>();
  }
  std::vector<PyLinkShape> linkShapes;
  if (!py::isinstance<py::iterable>(shapes) || py::isinstance<py::str>(shapes))
    argumentError("shapes", "expected a list of inertia.LinkShape");
  for (py::handle sh : shapes) {
    if (!py::isinstance<PyLinkShape>(sh))
      argumentError("shapes", "expected inertia.LinkShape items, got " +
                                  std::string(py::str(py::type::of(sh))));
    linkShapes.push_back(sh.cast<PyLinkShape>());
  }
  s.inertia = linkInertia(mass, com, inertia, linkShapes);
  const int index = m.model.addLink(s);  // InvalidArgument naming the link and the field
  for (const PyLinkShape& sh : linkShapes)
    m.shapes.push_back({index, toShape(sh.shape, "shapes"), sh.pose, sh.material});
  return index;
}

void bindDrive(py::module_& m) {
  using D = art::Drive<Real>;
  py::class_<D>(m, "Drive",
                "A PD drive of a revolute or prismatic joint: the generalised force "
                "clamp(stiffness (target - q) + damping (target_velocity - qd), -max_force, "
                "max_force), solved implicitly (stable whatever the gains).")
      .def(py::init(&makeDrive), py::kw_only(), py::arg("stiffness") = 0, py::arg("damping") = 0,
           py::arg("target") = 0, py::arg("target_velocity") = 0,
           py::arg("max_force") = std::numeric_limits<Real>::infinity(),
           "stiffness (N m/rad or N/m), damping (N m s/rad or N s/m), target (rad or m), "
           "target_velocity (rad/s or m/s), max_force (N m or N; inf: unbounded).")
      .def_readwrite("stiffness", &D::stiffness, "(N m/rad or N/m), >= 0")
      .def_readwrite("damping", &D::damping, "(N m s/rad or N s/m), >= 0")
      .def_readwrite("target", &D::targetPosition, "(rad or m)")
      .def_readwrite("target_velocity", &D::targetVelocity, "(rad/s or m/s)")
      .def_readwrite("max_force", &D::maxForce, "(N m or N), > 0")
      .def("__repr__", [](const D& d) {
        return py::str(
                   "Drive(stiffness={}, damping={}, target={}, target_velocity={}, "
                   "max_force={})")
            .format(d.stiffness, d.damping, d.targetPosition, d.targetVelocity, d.maxForce);
      });
}

void bindLinkShape(py::module_& m) {
  py::class_<PyLinkShape>(m, "LinkShape",
                          "A collision shape of an articulation's link, of a material, at a "
                          "pose in the link's frame. Its density gives the link's mass when the "
                          "link is added without one.")
      .def(py::init([](py::handle shape, const Material& material, py::handle position,
                       py::handle orientation) {
             toShape(shape, "shape");  // ValueError now, not when the link is added
             return PyLinkShape{py::reinterpret_borrow<py::object>(shape), material,
                                toPose(position, orientation)};
           }),
           py::arg("shape"), py::arg("material") = Material{}, py::kw_only(),
           py::arg("position") = py::none(), py::arg("orientation") = py::none(),
           "shape: an inertia.Sphere, Box, ...; position (m) and orientation [w, x, y, z] in "
           "the link's frame.")
      .def_readonly("shape", &PyLinkShape::shape)
      .def_readonly("material", &PyLinkShape::material)
      .def_property_readonly(
          "position", [](const PyLinkShape& s) { return fromVec3(s.pose.p); }, "(m)")
      .def_property_readonly(
          "orientation", [](const PyLinkShape& s) { return fromQuat(s.pose.q); }, "[w, x, y, z]");
}

const art::Model<Real>& modelOf(const PyModel& m) {
  if (m.model.linkCount() == 0) argumentError("model", "has no links");
  return m.model;
}

py::dict linkInfo(const art::Model<Real>& model, int i) {
  const art::Link<Real>& l = model.link(i);
  py::dict d;
  d["name"] = l.name;
  d["parent"] = l.parent;
  d["joint"] = jointTypeName(l.joint);
  d["q_slice"] = py::slice(l.qIndex, l.qIndex + l.nq, 1);
  d["v_slice"] = py::slice(l.vIndex, l.vIndex + l.nv, 1);
  d["mass"] = l.mass;
  d["com"] = fromVec3(l.centerOfMass);
  return d;
}

void bindModel(py::module_& m) {
  py::class_<PyModel>(m, "ArticulationModel",
                      "A tree of links in reduced coordinates (Featherstone): each link hangs "
                      "from its parent, or from the base, by one joint. Add links parents "
                      "first. q (size nq) holds angles (rad), displacements (m) and unit "
                      "quaternions [w, x, y, z] (spherical joints; a floating base's position "
                      "then quaternion); qd (size nv) the joint rates (rad/s, m/s; angular "
                      "velocities in the link's axes; a floating base's [w; v] in its own axes).")
      .def(py::init<>())
      .def("add_link", &addLink, py::arg("name") = "", py::kw_only(),
           py::arg("parent") = py::none(), py::arg("joint") = "revolute",
           py::arg("axis") = py::make_tuple(0, 0, 1),
           py::arg("origin_position") = py::make_tuple(0, 0, 0),
           py::arg("origin_orientation") = py::make_tuple(1, 0, 0, 0),
           py::arg("limits") = py::none(), py::arg("damping") = 0, py::arg("friction") = 0,
           py::arg("armature") = 0,
           py::arg("velocity_limit") = std::numeric_limits<Real>::infinity(),
           py::arg("drive") = py::none(), py::arg("mass") = py::none(), py::arg("com") = py::none(),
           py::arg("inertia") = py::none(), py::arg("shapes") = py::list(),
           "Adds a link and returns its index. parent: None (the base), an index or a link's "
           "name; joint: 'revolute', 'prismatic', 'spherical', 'fixed' or 'floating' (a root "
           "only); axis of a revolute or prismatic joint in the joint frame; the joint frame "
           "at origin_position (m) and origin_orientation [w, x, y, z] in the parent's frame; "
           "limits (lower, upper) (rad or m); per degree of freedom damping (N m s/rad or "
           "N s/m), Coulomb friction (N m or N), armature (kg m^2 or kg) and velocity_limit "
           "(rad/s or m/s); drive: an inertia.Drive; mass (kg), com (m, link frame) and "
           "inertia about the centre of mass (kg m^2: principal moments or 3x3), or None to "
           "take all three from the shapes (inertia.LinkShape, whose densities count).")
      .def_property_readonly("link_count", [](const PyModel& m) { return m.model.linkCount(); })
      .def_property_readonly(
          "nq", [](const PyModel& m) { return m.model.nq(); }, "Size of q.")
      .def_property_readonly(
          "nv", [](const PyModel& m) { return m.model.nv(); }, "Size of qd: degrees of freedom.")
      .def_property(
          "gravity", [](const PyModel& m) { return fromVec3(m.model.gravity); },
          [](PyModel& m, py::handle g) {
            const Vec3 v = toVec3(g, "gravity");
            if (!v.allFinite()) argumentError("gravity", "must be finite");
            m.model.gravity = v;
          },
          "In the base frame (m/s^2), for the functions of (model, q, ...).")
      .def(
          "find_link",
          [](const PyModel& m, const std::string& name) {
            const int i = m.model.findLink(name);
            if (i < 0) throw py::key_error("no link named '" + name + "'");
            return i;
          },
          py::arg("name"), "The index of the link named name (KeyError when none is).")
      .def(
          "link",
          [](const PyModel& m, py::handle link) {
            return linkInfo(m.model, toLink(m.model, link, "link"));
          },
          py::arg("link"),
          "A link (index or name) as a dict: name, parent (-1: the base), joint, q_slice and "
          "v_slice (its coordinates in q and qd), mass (kg), com (m, link frame).")
      .def(
          "link_names",
          [](const PyModel& m) {
            std::vector<std::string> names;
            for (const art::Link<Real>& l : m.model.links()) names.push_back(l.name);
            return names;
          },
          "In index order.")
      .def_property_readonly(
          "shape_count", [](const PyModel& m) { return m.shapes.size(); },
          "Collision shapes of the links, given to the link bodies of a World.")
      .def(
          "neutral_configuration",
          [](const PyModel& m) { return fromVector(m.model.neutralConfiguration()); },
          "q with every joint at zero and every quaternion the identity.")
      .def_property_readonly(
          "lower", [](const PyModel& m) { return fromVector(m.model.lower()); },
          "Per degree of freedom (rad or m; -inf where none).")
      .def_property_readonly(
          "upper", [](const PyModel& m) { return fromVector(m.model.upper()); },
          "Per degree of freedom (rad or m; inf where none).")
      .def_property_readonly(
          "damping", [](const PyModel& m) { return fromVector(m.model.damping()); },
          "Per degree of freedom (N m s/rad or N s/m).")
      .def_property_readonly(
          "friction", [](const PyModel& m) { return fromVector(m.model.friction()); },
          "Per degree of freedom (N m or N).")
      .def_property_readonly(
          "armature", [](const PyModel& m) { return fromVector(m.model.armature()); },
          "Per degree of freedom (kg m^2 or kg).")
      .def_property_readonly(
          "velocity_limit", [](const PyModel& m) { return fromVector(m.model.velocityLimit()); },
          "Per degree of freedom (rad/s or m/s; inf where none).")
      .def_property_readonly(
          "drives", [](const PyModel& m) { return m.model.drives(); },
          "Per degree of freedom, copies (set_drive changes one).")
      .def(
          "set_drive",
          [](PyModel& m, int dof, const art::Drive<Real>& d) { m.model.setDrive(dof, d); },
          py::arg("dof"), py::arg("drive"), "Revolute and prismatic joints' dofs only.")
      .def_static(
          "random_tree",
          [](int links, bool floatingBase, bool armature, std::uint32_t seed) {
            if (links < 1) argumentError("links", "must be >= 1");
            return PyModel{art::randomTree<Real>({links, floatingBase, armature, seed}), {}};
          },
          py::kw_only(), py::arg("links") = 10, py::arg("floating_base") = false,
          py::arg("armature") = true, py::arg("seed") = 1,
          "The library's seeded random tree (its tests' and benchmarks'): joint types cycling "
          "through revolute, prismatic, spherical and fixed (a floating root with "
          "floating_base), masses 0.5 to 2 kg, inertias of random boxes.")
      .def_static(
          "pendulum_chain",
          [](int links, Real length, Real mass) {
            if (links < 1) argumentError("links", "must be >= 1");
            return PyModel{art::pendulumChain<Real>(links, length, mass), {}};
          },
          py::kw_only(), py::arg("links"), py::arg("length"), py::arg("mass"),
          "A chain of revolute joints about z hanging along -y, each link a point mass (kg) "
          "length (m) below its joint.")
      .def_static(
          "seven_dof_arm",
          [] {
            return PyModel{art::sevenDofArm<Real>(), {}};
          },
          "A 7-DOF arm shaped as the Franka Panda (its kinematics and link masses), with limits.")
      .def(
          "random_state",
          [](const PyModel& m, std::uint32_t seed) {
            art::VectorX<Real> q, qd;
            art::randomState<Real>(modelOf(m), seed, q, qd);
            return py::make_tuple(fromVector(q), fromVector(qd));
          },
          py::arg("seed") = 1,
          "(q, qd): angles and displacements in [-1, 1], uniform random quaternions, rates in "
          "[-1, 1], drawn from seed.")
      .def("__repr__", [](const PyModel& m) {
        return "ArticulationModel(" + std::to_string(m.model.linkCount()) + " links, nq " +
               std::to_string(m.model.nq()) + ", nv " + std::to_string(m.model.nv()) + ")";
      });
}

py::array fromMatrix(const art::MatrixX<Real>& a) {
  RealArray out({py::ssize_t(a.rows()), py::ssize_t(a.cols())});
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) out.mutable_at(i, j) = a(i, j);
  return out;
}

void bindAlgorithms(py::module_& m) {
  using art::VectorX;
  m.def(
      "aba",
      [](const PyModel& pm, py::handle q, py::handle qd, py::handle tau) {
        const art::Model<Real>& model = modelOf(pm);
        return fromVector(art::aba<Real>(model, toConfiguration(model, q, "q"),
                                         toVector(qd, "qd", model.nv()),
                                         toVector(tau, "tau", model.nv())));
      },
      py::arg("model"), py::arg("q"), py::arg("qd"), py::arg("tau"),
      "Forward dynamics by Featherstone's articulated-body algorithm: the joint accelerations "
      "qdd (rad/s^2 or m/s^2, size nv) under gravity and the joint forces tau (N m or N). "
      "Joint damping, friction, limits and drives are not in it (the step adds them).");
  m.def(
      "forward_dynamics_crba",
      [](const PyModel& pm, py::handle q, py::handle qd, py::handle tau) {
        const art::Model<Real>& model = modelOf(pm);
        return fromVector(art::forwardDynamicsCrba<Real>(model, toConfiguration(model, q, "q"),
                                                         toVector(qd, "qd", model.nv()),
                                                         toVector(tau, "tau", model.nv())));
      },
      py::arg("model"), py::arg("q"), py::arg("qd"), py::arg("tau"),
      "Forward dynamics as aba, by H qdd = tau - C with H from crba and C from rnea (Cholesky).");
  m.def(
      "rnea",
      [](const PyModel& pm, py::handle q, py::handle qd, py::handle qdd) {
        const art::Model<Real>& model = modelOf(pm);
        return fromVector(art::rnea<Real>(model, toConfiguration(model, q, "q"),
                                          toVector(qd, "qd", model.nv()),
                                          toVector(qdd, "qdd", model.nv())));
      },
      py::arg("model"), py::arg("q"), py::arg("qd"), py::arg("qdd"),
      "Inverse dynamics by recursive Newton-Euler: the joint forces tau (N m or N) that give "
      "the accelerations qdd under gravity. rnea(model, q, qd, 0) is the bias C(q, qd).");
  m.def(
      "crba",
      [](const PyModel& pm, py::handle q) {
        const art::Model<Real>& model = modelOf(pm);
        return fromMatrix(art::crba<Real>(model, toConfiguration(model, q, "q")));
      },
      py::arg("model"), py::arg("q"),
      "The joint-space mass matrix H(q) (nv, nv), symmetric positive definite, by the "
      "composite-rigid-body algorithm; armature on its diagonal (kg m^2 or kg).");
  m.def(
      "point_jacobian",
      [](const PyModel& pm, py::handle q, py::handle link, py::handle point) {
        const art::Model<Real>& model = modelOf(pm);
        const VectorX<Real> qv = toConfiguration(model, q, "q");
        const int l = toLink(model, link, "link");
        return fromMatrix(art::pointJacobian<Real>(model, qv, l, toVec3(point, "point")));
      },
      py::arg("model"), py::arg("q"), py::arg("link"), py::arg("point") = py::make_tuple(0, 0, 0),
      "The Jacobian (6, nv) of a point (m, in the link's frame) fixed on a link (index or "
      "name): [w; v] = J qd, w the link's angular velocity (rad/s), v the point's velocity "
      "(m/s), both in base axes.");
  m.def(
      "link_pose",
      [](const PyModel& pm, py::handle q, py::handle link) {
        const art::Model<Real>& model = modelOf(pm);
        const VectorX<Real> qv = toConfiguration(model, q, "q");
        const art::PluckerTransform<Real> X =
            art::linkPose<Real>(model, qv, toLink(model, link, "link"));
        // X maps base coordinates into the link's: the link's rotation in the base is E^T.
        return py::make_tuple(fromVec3(X.r), fromQuat(Quat(Mat3(X.E.transpose())).normalized()));
      },
      py::arg("model"), py::arg("q"), py::arg("link"),
      "(position (m), orientation [w, x, y, z]) of a link's frame in the base frame.");
  m.def(
      "point_position",
      [](const PyModel& pm, py::handle q, py::handle link, py::handle point) {
        const art::Model<Real>& model = modelOf(pm);
        const VectorX<Real> qv = toConfiguration(model, q, "q");
        const int l = toLink(model, link, "link");
        return fromVec3(art::pointPosition<Real>(model, qv, l, toVec3(point, "point")));
      },
      py::arg("model"), py::arg("q"), py::arg("link"), py::arg("point") = py::make_tuple(0, 0, 0),
      "Where a point (m, in the link's frame) is in the base frame (m).");
  m.def(
      "integrate_configuration",
      [](const PyModel& pm, py::handle q, py::handle qd, Real h) {
        const art::Model<Real>& model = modelOf(pm);
        VectorX<Real> qv = toConfiguration(model, q, "q");
        if (!std::isfinite(h)) argumentError("h", "must be finite (s)");
        art::integrateConfiguration<Real>(model, qv, toVector(qd, "qd", model.nv()), h);
        return fromVector(qv);
      },
      py::arg("model"), py::arg("q"), py::arg("qd"), py::arg("h"),
      "q moved by the velocity qd for h seconds (quaternions by the exact rotation).");
  m.def(
      "kinetic_energy",
      [](const PyModel& pm, py::handle q, py::handle qd) {
        const art::Model<Real>& model = modelOf(pm);
        return art::kineticEnergy<Real>(model, toConfiguration(model, q, "q"),
                                        toVector(qd, "qd", model.nv()));
      },
      py::arg("model"), py::arg("q"), py::arg("qd"),
      "Of the links and the armature (J): 1/2 qd . H qd.");
  m.def(
      "potential_energy",
      [](const PyModel& pm, py::handle q) {
        const art::Model<Real>& model = modelOf(pm);
        return art::potentialEnergy<Real>(model, toConfiguration(model, q, "q"));
      },
      py::arg("model"), py::arg("q"),
      "In the model's gravity (J), zero at the base origin: -sum m_i g . c_i.");
  m.def(
      "center_of_mass",
      [](const PyModel& pm, py::handle q) {
        const art::Model<Real>& model = modelOf(pm);
        return fromVec3(art::centerOfMass<Real>(model, toConfiguration(model, q, "q")));
      },
      py::arg("model"), py::arg("q"), "Of the links (m, base frame).");
  m.def(
      "momentum",
      [](const PyModel& pm, py::handle q, py::handle qd) {
        const art::Model<Real>& model = modelOf(pm);
        const art::Vector6<Real> h = art::momentum<Real>(model, toConfiguration(model, q, "q"),
                                                         toVector(qd, "qd", model.nv()));
        return fromVector(VectorX<Real>(h));
      },
      py::arg("model"), py::arg("q"), py::arg("qd"),
      "Spatial momentum about the base origin in base axes: [angular (kg m^2/s); linear "
      "(kg m/s)], size 6.");
}

}  // namespace

art::VectorX<Real> toVector(py::handle value, const char* arg, int n) {
  art::VectorX<Real> v(n);
  toReals(value, arg, v.data(), std::size_t(n));
  if (!v.allFinite()) argumentError(arg, "must be finite");
  return v;
}

art::VectorX<Real> toConfiguration(const art::Model<Real>& model, py::handle value,
                                   const char* arg) {
  art::VectorX<Real> q = toVector(value, arg, model.nq());
  for (const art::Link<Real>& l : model.links()) {
    const int at = l.joint == art::JointType::Spherical  ? l.qIndex
                   : l.joint == art::JointType::Floating ? l.qIndex + 3
                                                         : -1;
    if (at >= 0 && !(q.segment<4>(at).norm() > Real(1e-6)))
      argumentError(arg, "the quaternion of link '" + l.name + "' (q[" + std::to_string(at) + ":" +
                             std::to_string(at + 4) + "]) is zero");
  }
  return q;
}

int toLink(const art::Model<Real>& model, py::handle value, const char* arg) {
  if (py::isinstance<py::str>(value)) {
    const std::string name = value.cast<std::string>();
    const int i = model.findLink(name);
    if (i < 0) argumentError(arg, "no link named '" + name + "'");
    return i;
  }
  if (!py::isinstance<py::int_>(value))
    argumentError(
        arg, "expected a link index or name, got " + std::string(py::str(py::type::of(value))));
  const long long i = value.cast<long long>();
  if (i < 0 || i >= model.linkCount())
    argumentError(arg, "no link " + std::to_string(i) + " (the model has " +
                           std::to_string(model.linkCount()) + ")");
  return int(i);
}

py::array fromVector(const art::VectorX<Real>& v) {
  RealArray a(v.size());
  std::copy_n(v.data(), v.size(), a.mutable_data());
  return a;
}

void bindArticulationModel(py::module_& m) {
  bindDrive(m);
  bindLinkShape(m);
  bindModel(m);
  bindAlgorithms(m);
}

}  // namespace inertia::python
