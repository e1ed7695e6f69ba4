// Joints: settings classes made with keywords (inertia.HingeJoint(body_b=door, limits=(-1, 0),
// motor=inertia.JointMotor(speed=1, max_force=20))) and World.create_joint and friends.
// Anchors and axes are in each body's frame; a null body_a (None) is the world.
#include <pybind11/stl.h>

#include <array>
#include <optional>
#include <string>

#include "bindings.h"
#include "convert.h"
#include "inertia/dynamics/joint.h"
#include "shapes.h"

namespace inertia::python {

namespace {

BodyId toBodyOrWorld(py::handle value, const char* arg) {
  if (value.is_none()) return BodyId{};
  if (!py::isinstance<BodyId>(value))
    argumentError(arg, "expected a BodyId or None (the world), got " +
                           std::string(py::str(py::type::of(value))));
  return value.cast<BodyId>();
}

JointLimits toLimits(py::handle value, const char* arg) {
  if (py::isinstance<JointLimits>(value)) return value.cast<JointLimits>();
  Real bounds[2];
  toReals(value, arg, bounds, 2);
  return {bounds[0], bounds[1]};
}

template <class T>
T toInstance(py::handle value, const char* arg, const char* typeName) {
  if (!py::isinstance<T>(value))
    argumentError(arg, std::string("expected an inertia.") + typeName + ", got " +
                           std::string(py::str(py::type::of(value))));
  return value.cast<T>();
}

// A property of an optional member: None clears it.
template <class S, class T, class Convert>
void optionalProperty(py::class_<S>& c, const char* name, std::optional<T> S::*member,
                      Convert convert, const char* doc) {
  c.def_property(
      name,
      [member](const S& s) -> py::object {
        return (s.*member) ? py::cast(*(s.*member)) : py::none();
      },
      [member, name, convert](S& s, py::handle v) {
        if (v.is_none())
          s.*member = std::nullopt;
        else
          s.*member = convert(v, name);
      },
      doc);
}

template <class S>
void limitsProperty(py::class_<S>& c, const char* name, std::optional<JointLimits> S::*member,
                    const char* doc) {
  optionalProperty(c, name, member, toLimits, doc);
}

template <class S>
void motorProperty(py::class_<S>& c) {
  optionalProperty(
      c, "motor", &S::motor,
      [](py::handle v, const char* arg) { return toInstance<JointMotor>(v, arg, "JointMotor"); },
      "A JointMotor on the free coordinate, or None.");
}

template <class S>
void springProperty(py::class_<S>& c, const char* doc) {
  optionalProperty(
      c, "spring", &S::spring,
      [](py::handle v, const char* arg) { return toInstance<JointSpring>(v, arg, "JointSpring"); },
      doc);
}

// What every joint type has: its bodies, break thresholds, collide_connected and name; and
// construction from keywords only.
template <class S>
py::class_<S> jointClass(py::module_& m, const char* name, const char* doc) {
  py::class_<S> c(m, name, doc);
  c.def(py::init([name](const py::kwargs& kwargs) {
          S s;
          setAttributes(py::cast(&s, py::return_value_policy::reference), kwargs, name);
          return s;
        }),
        "Keywords name the attributes; the others keep their defaults.");
  c.def_property(
      "body_a",
      [](const S& s) -> py::object { return s.bodyA.isNull() ? py::none() : py::cast(s.bodyA); },
      [](S& s, py::handle v) { s.bodyA = toBodyOrWorld(v, "body_a"); },
      "The first body, or None for the world (then anchor_a and axis_a are world coordinates).");
  c.def_property(
      "body_b",
      [](const S& s) -> py::object { return s.bodyB.isNull() ? py::none() : py::cast(s.bodyB); },
      [](S& s, py::handle v) { s.bodyB = toBodyOrWorld(v, "body_b"); }, "The second body.");
  c.def_readwrite("break_force", &S::breakForce, "Breaks above this constraint force (N).");
  c.def_readwrite("break_torque", &S::breakTorque, "Breaks above this constraint torque (N m).");
  c.def_readwrite("collide_connected", &S::collideConnected,
                  "The two bodies collide with each other.");
  c.def_readwrite("name", &S::name);
  return c;
}

template <class S>
void anchors(py::class_<S>& c) {
  vec3Property(c, "anchor_a", &S::anchorA, "Anchor in A's frame (m; world when A is None).");
  vec3Property(c, "anchor_b", &S::anchorB, "Anchor in B's frame (m).");
}

template <class S>
void createJointMethod(py::class_<PyWorld>& world) {
  world.def(
      "create_joint", [](PyWorld& w, const S& s) { return w->createJoint(s); },
      py::arg("settings"));
}

py::tuple frameTuple(const Transform& t) { return py::make_tuple(fromVec3(t.p), fromQuat(t.q)); }

Transform toFrame(py::handle v, const char* arg) {
  if (!py::isinstance<py::tuple>(v) && !py::isinstance<py::list>(v))
    argumentError(arg, "expected (position, orientation)");
  if (py::len(v) != 2) argumentError(arg, "expected (position, orientation)");
  Transform t;
  t.p = toVec3(v[py::int_(0)], arg);
  t.q = toQuat(v[py::int_(1)], arg);
  return t;
}

}  // namespace

void bindJoints(py::module_& m) {
  py::class_<JointLimits>(m, "JointLimits",
                          "Bounds of a joint's free coordinate: an angle (rad) or a position (m).")
      .def(py::init([](Real lower, Real upper) {
             return JointLimits{lower, upper};
           }),
           py::arg("lower"), py::arg("upper"))
      .def_readwrite("lower", &JointLimits::lower)
      .def_readwrite("upper", &JointLimits::upper);

  py::class_<JointMotor>(
      m, "JointMotor",
      "Drives the free coordinate's speed (rad/s or m/s) with at most max_force "
      "(N m or N); with a target (rad or m) it is a servo of servo_frequency (Hz).")
      .def(py::init([](Real speed, Real maxForce, std::optional<Real> target, Real servoFrequency) {
             return JointMotor{speed, maxForce, target, servoFrequency};
           }),
           py::kw_only(), py::arg("speed") = 0, py::arg("max_force") = 0,
           py::arg("target") = py::none(), py::arg("servo_frequency") = 2)
      .def_readwrite("speed", &JointMotor::speed)
      .def_readwrite("max_force", &JointMotor::maxForce)
      .def_readwrite("target", &JointMotor::target)
      .def_readwrite("servo_frequency", &JointMotor::servoFrequency);

  py::class_<JointSpring>(m, "JointSpring",
                          "A soft constraint of frequency (Hz) and damping ratio (1: critical), "
                          "towards rest (rad or m).")
      .def(py::init([](Real frequency, Real dampingRatio, Real rest) {
             return JointSpring{frequency, dampingRatio, rest};
           }),
           py::kw_only(), py::arg("frequency") = 1, py::arg("damping_ratio") = 0,
           py::arg("rest") = 0)
      .def_readwrite("frequency", &JointSpring::frequency)
      .def_readwrite("damping_ratio", &JointSpring::dampingRatio)
      .def_readwrite("rest", &JointSpring::rest);

  py::class_<JointAxis> axis(m, "JointAxis",
                             "One degree of freedom of a six-DOF joint: locked, or free within "
                             "optional limits, with an optional motor, spring and friction.");
  axis.def(py::init([](const py::kwargs& kwargs) {
        JointAxis a;
        setAttributes(py::cast(&a, py::return_value_policy::reference), kwargs, "JointAxis");
        return a;
      }))
      .def_readwrite("locked", &JointAxis::locked)
      .def_readwrite("friction", &JointAxis::friction, "Force (N) or torque (N m), >= 0.");
  limitsProperty(axis, "limits", &JointAxis::limits, "(lower, upper) (m or rad), or None.");
  motorProperty(axis);
  springProperty(axis, "A JointSpring towards its rest, or None.");

  auto ball = jointClass<BallJointSettings>(
      m, "BallJoint",
      "Ball and socket: the anchors coincide; rotation free within an optional "
      "cone and twist limits about the axis.");
  anchors(ball);
  vec3Property(ball, "axis_a", &BallJointSettings::axisA, "Cone and twist axis in A's frame.");
  vec3Property(ball, "axis_b", &BallJointSettings::axisB, "The same axis in B's frame.");
  ball.def_readwrite("cone_limit", &BallJointSettings::coneLimit,
                     "Largest swing (rad, in (0, pi)), or None.");
  limitsProperty(ball, "twist_limits", &BallJointSettings::twistLimits, "(rad), or None.");
  ball.def_readwrite("friction", &BallJointSettings::friction, "(N m)");

  auto hinge = jointClass<HingeJointSettings>(
      m, "HingeJoint", "Hinge: the anchors coincide and the axes stay aligned.");
  anchors(hinge);
  vec3Property(hinge, "axis_a", &HingeJointSettings::axisA, "Hinge axis in A's frame.");
  vec3Property(hinge, "axis_b", &HingeJointSettings::axisB, "The same axis in B's frame.");
  limitsProperty(hinge, "limits", &HingeJointSettings::limits,
                 "(lower, upper) angle of B about the axis (rad), or None.");
  motorProperty(hinge);
  springProperty(hinge, "A JointSpring towards its rest angle, or None.");
  hinge.def_readwrite("friction", &HingeJointSettings::friction, "(N m)");

  auto slider = jointClass<SliderJointSettings>(
      m, "SliderJoint", "Slider: no relative rotation; B's anchor moves along A's axis.");
  anchors(slider);
  vec3Property(slider, "axis_a", &SliderJointSettings::axisA, "Sliding axis in A's frame.");
  limitsProperty(slider, "limits", &SliderJointSettings::limits, "(lower, upper) (m), or None.");
  motorProperty(slider);
  springProperty(slider, "A JointSpring towards its rest position (m), or None.");
  slider.def_readwrite("friction", &SliderJointSettings::friction, "(N)");

  auto universal = jointClass<UniversalJointSettings>(
      m, "UniversalJoint",
      "Universal (Cardan): A turns about axis_a, B about axis_b, the two "
      "perpendicular.");
  anchors(universal);
  vec3Property(universal, "axis_a", &UniversalJointSettings::axisA, "In A's frame.");
  vec3Property(universal, "axis_b", &UniversalJointSettings::axisB, "In B's frame.");
  limitsProperty(universal, "limits_a", &UniversalJointSettings::limitsA, "(rad), or None.");
  limitsProperty(universal, "limits_b", &UniversalJointSettings::limitsB, "(rad), or None.");

  auto weld = jointClass<WeldJointSettings>(
      m, "WeldJoint", "Weld: position and rotation fixed as created (soft with a spring).");
  anchors(weld);
  springProperty(weld, "A JointSpring (its rest unused), or None.");

  auto distance = jointClass<DistanceJointSettings>(
      m, "DistanceJoint",
      "The anchors' distance within [min_length, max_length] (a rope when "
      "min_length is 0).");
  anchors(distance);
  distance.def_readwrite("length", &DistanceJointSettings::length,
                         "Rest length (m); negative: the distance at creation.");
  distance.def_readwrite("min_length", &DistanceJointSettings::minLength,
                         "(m); negative: equal to length.");
  distance.def_readwrite("max_length", &DistanceJointSettings::maxLength,
                         "(m); negative: equal to length.");
  springProperty(distance, "A JointSpring pulling towards length, or None.");

  auto sixDof = jointClass<SixDofJointSettings>(
      m, "SixDofJoint",
      "Six degrees of freedom (x, y, z, rx, ry, rz of B's frame in A's), each "
      "a JointAxis; all locked by default.");
  sixDof.def_property(
      "frame_a", [](const SixDofJointSettings& s) { return frameTuple(s.frameA); },
      [](SixDofJointSettings& s, py::handle v) { s.frameA = toFrame(v, "frame_a"); },
      "(position (m), orientation [w, x, y, z]) in A's frame.");
  sixDof.def_property(
      "frame_b", [](const SixDofJointSettings& s) { return frameTuple(s.frameB); },
      [](SixDofJointSettings& s, py::handle v) { s.frameB = toFrame(v, "frame_b"); },
      "(position (m), orientation [w, x, y, z]) in B's frame.");
  sixDof.def_property(
      "axes",
      [](const SixDofJointSettings& s) {
        return std::vector<JointAxis>(s.axes.begin(), s.axes.end());
      },
      [](SixDofJointSettings& s, const py::sequence& axes) {
        if (py::len(axes) != 6) argumentError("axes", "expected 6 JointAxis (x, y, z, rx, ry, rz)");
        for (std::size_t i = 0; i < 6; ++i)
          s.axes[i] = toInstance<JointAxis>(axes[i], "axes", "JointAxis");
      },
      "Six JointAxis: x, y, z (m), rx, ry, rz (rad).");

  py::class_<JointEvent>(m, "JointEvent", "A joint that broke in the last step.")
      .def_readonly("joint", &JointEvent::joint)
      .def_property_readonly(
          "force", [](const JointEvent& e) { return fromVec3(e.force); },
          "Constraint force when it broke (N, on B).")
      .def_property_readonly(
          "torque", [](const JointEvent& e) { return fromVec3(e.torque); }, "(N m)");

  py::class_<PyWorld> world = worldClass(m);
  createJointMethod<BallJointSettings>(world);
  createJointMethod<HingeJointSettings>(world);
  createJointMethod<SliderJointSettings>(world);
  createJointMethod<UniversalJointSettings>(world);
  createJointMethod<WeldJointSettings>(world);
  createJointMethod<DistanceJointSettings>(world);
  createJointMethod<SixDofJointSettings>(world);
  world
      .def(
          "destroy_joint", [](PyWorld& w, JointId id) { w->destroyJoint(id); }, py::arg("joint"))
      .def(
          "joints", [](const PyWorld& w) { return w->rigidBodies().joints(); },
          "The live joints in slot order.")
      .def_property_readonly("joint_count",
                             [](const PyWorld& w) { return w->rigidBodies().jointCount(); })
      .def(
          "joint_type",
          [](const PyWorld& w, JointId id) {
            return std::string(jointTypeName(w->rigidBodies().jointType(id)));
          },
          py::arg("joint"),
          "'ball', 'hinge', 'slider', 'universal', 'weld', 'distance' or 'six_dof'.")
      .def(
          "joint_name",
          [](const PyWorld& w, JointId id) { return std::string(w->rigidBodies().jointName(id)); },
          py::arg("joint"))
      .def(
          "joint_bodies",
          [](const PyWorld& w, JointId id) {
            const BodyId a = w->rigidBodies().jointBodyA(id);
            return py::make_tuple(a.isNull() ? py::none() : py::cast(a),
                                  w->rigidBodies().jointBodyB(id));
          },
          py::arg("joint"), "(body_a or None for the world, body_b).")
      .def(
          "set_joint_enabled",
          [](PyWorld& w, JointId id, bool on) { w->rigidBodies().setJointEnabled(id, on); },
          py::arg("joint"), py::arg("enabled"), "Enabling a broken joint repairs it.")
      .def(
          "is_joint_enabled",
          [](const PyWorld& w, JointId id) { return w->rigidBodies().isJointEnabled(id); },
          py::arg("joint"))
      .def(
          "is_joint_broken",
          [](const PyWorld& w, JointId id) { return w->rigidBodies().isJointBroken(id); },
          py::arg("joint"))
      .def(
          "set_joint_motor",
          [](PyWorld& w, JointId id, py::handle motor) {
            w->rigidBodies().setJointMotor(
                id, motor.is_none()
                        ? std::nullopt
                        : std::optional(toInstance<JointMotor>(motor, "motor", "JointMotor")));
          },
          py::arg("joint"), py::arg("motor"), "A hinge's or slider's motor; None removes it.")
      .def(
          "set_joint_limits",
          [](PyWorld& w, JointId id, py::handle limits) {
            w->rigidBodies().setJointLimits(
                id, limits.is_none() ? std::nullopt : std::optional(toLimits(limits, "limits")));
          },
          py::arg("joint"), py::arg("limits"), "(lower, upper) (rad or m); None removes them.")
      .def(
          "set_joint_spring",
          [](PyWorld& w, JointId id, py::handle spring) {
            w->rigidBodies().setJointSpring(
                id, spring.is_none()
                        ? std::nullopt
                        : std::optional(toInstance<JointSpring>(spring, "spring", "JointSpring")));
          },
          py::arg("joint"), py::arg("spring"), "None removes it.")
      .def(
          "set_joint_axis",
          [](PyWorld& w, JointId id, int axis, const JointAxis& settings) {
            w->rigidBodies().setJointAxis(id, axis, settings);
          },
          py::arg("joint"), py::arg("axis"), py::arg("settings"),
          "A six-DOF joint's degree of freedom axis (0..5: x, y, z, rx, ry, rz).")
      .def(
          "joint_force",
          [](const PyWorld& w, JointId id) { return fromVec3(w->rigidBodies().jointForce(id)); },
          py::arg("joint"), "Last step's constraint force on B at its anchor (N, world).")
      .def(
          "joint_torque",
          [](const PyWorld& w, JointId id) { return fromVec3(w->rigidBodies().jointTorque(id)); },
          py::arg("joint"), "Last step's constraint torque on B (N m, world).")
      .def(
          "joint_coordinate",
          [](const PyWorld& w, JointId id) { return w->rigidBodies().jointCoordinate(id); },
          py::arg("joint"),
          "A hinge's angle (rad), a slider's position (m), a distance joint's length (m), a "
          "ball joint's twist (rad); 0 for the others.")
      .def(
          "joint_axis_coordinate",
          [](const PyWorld& w, JointId id, int axis) {
            return w->rigidBodies().jointAxisCoordinate(id, axis);
          },
          py::arg("joint"), py::arg("axis"), "B's frame in A's: x, y, z (m), rx, ry, rz (rad).")
      .def(
          "joint_error",
          [](const PyWorld& w, JointId id) {
            const JointError e = w->rigidBodies().jointError(id);
            return py::make_tuple(e.position, e.angle);
          },
          py::arg("joint"), "(position error (m), angle error (rad)).")
      .def(
          "joint_anchors",
          [](const PyWorld& w, JointId id) {
            return py::make_tuple(fromVec3(w->rigidBodies().jointAnchorA(id)),
                                  fromVec3(w->rigidBodies().jointAnchorB(id)));
          },
          py::arg("joint"), "The anchors in world coordinates (m).")
      .def(
          "joint_events", [](const PyWorld& w) { return w->rigidBodies().jointEvents(); },
          "The joints that broke in the last step.");
}

}  // namespace inertia::python
