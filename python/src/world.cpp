// inertia.World: settings, bodies and their shapes, state as NumPy arrays, stepping, contacts,
// ray casts, snapshots, and scene files (load_scene, parse_scene).
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "inertia/core/error.h"
#include "inertia/io/scene.h"
#include "shapes.h"

namespace inertia::python {

namespace {

BodyType toBodyType(py::handle value) {
  if (py::isinstance<BodyType>(value)) return value.cast<BodyType>();
  if (py::isinstance<py::str>(value)) {
    BodyType t;
    if (bodyTypeFromName(value.cast<std::string>(), t)) return t;
  }
  argumentError("type", "expected 'static', 'kinematic', 'dynamic' or an inertia.BodyType, got " +
                            std::string(py::repr(value)));
}

WorldSettings makeSettings(py::handle gravity, Real dt, int substeps, const std::string& solver,
                           int iterations, int relaxIterations, Real jointHertz,
                           Real jointDampingRatio, const std::string& integrator, int threads,
                           bool sleeping) {
  WorldSettings s;
  s.gravity = toVec3(gravity, "gravity");
  s.dt = dt;
  s.substeps = substeps;
  if (!solverFromName(solver, s.solver.type))
    argumentError("solver", "unknown solver '" + solver + "' (" + std::string(solverNames()) + ")");
  s.solver.iterations = iterations;
  s.solver.relaxIterations = relaxIterations;
  s.solver.jointHertz = jointHertz;
  s.solver.jointDampingRatio = jointDampingRatio;
  const std::optional<ode::Method> method = ode::methodFromName(integrator);
  if (!method) argumentError("integrator", "unknown integrator '" + integrator + "'");
  s.integrator = *method;
  s.threads = threads;
  s.sleeping = sleeping;
  validate(s);
  return s;
}

// The live bodies in slot order: the order of every state array.
std::vector<BodyId> bodyList(const World& w) { return w.rigidBodies().bodies(); }

template <class Get>
RealArray gather(const World& w, py::ssize_t cols, Get get) {
  return bodyRows(bodyList(w), cols, get);
}

// Writes one row per body, in slot order, after checking the shape.
template <class Set>
void scatter(World& w, py::handle value, const char* arg, py::ssize_t cols, Set set) {
  const std::vector<BodyId> ids = bodyList(w);
  RealArray a = toMatrix(value, arg, py::ssize_t(ids.size()), cols);
  const Real* in = a.data();
  for (BodyId id : ids) set(id, in + 0), in += cols;
}

// A World from scene text and its recipe (which the world keeps until changed from Python).
PyWorld fromScene(std::string text, std::string name, std::optional<Real> dt,
                  std::optional<int> threads) {
  Recipe recipe{std::make_shared<const std::string>(std::move(text)),
                std::move(name),
                dt,
                threads,
                std::nullopt,
                {}};
  PyWorld w;
  w.world = recipe.make();
  w.recipe = std::move(recipe);
  return w;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Pickling: a World pickles as its recipe (version 1: scene, name, dt, threads, gravity,
// calls); one built or changed through the API cannot be pickled.
// A snapshot, and the world it came from and that world's recipe at the time.
struct PyState {
  World::State state;
  std::uint64_t world = 0;  // PyWorld::serial
  std::optional<Recipe> recipe;
};

void restoreState(PyWorld& w, const PyState& s) {
  World& world = w.get();
  w.refuseAnyViewed("restore_state");
  world.restoreState(s.state);
  // The snapshot holds every body, joint, contact, particle system, deformable, articulation and
  // the clock, but not the settings (which belong to the world): the recipe at the snapshot
  // describes the world again only for its own snapshot.
  w.recipe = s.world == w.serial ? s.recipe : std::nullopt;
}

py::tuple pickleWorld(const PyWorld& w) {
  w.get();  // RuntimeError while another thread steps it
  if (!w.recipe)
    throw py::type_error(
        "cannot pickle this inertia.World: it was built or changed through the API, and only "
        "a world made from a scene (load_scene, parse_scene, Batch) and stepped since can be "
        "rebuilt elsewhere (save_state and restore_state work within one process)");
  const Recipe& r = *w.recipe;
  py::list calls;
  for (const Recipe::Call& c : r.calls) calls.append(py::make_tuple(c.value, c.maxSteps, c.repeat));
  py::object gravity = r.gravity ? py::object(fromVec3(*r.gravity)) : py::object(py::none());
  return py::make_tuple(1, py::bytes(*r.scene), r.name, r.dt, r.threads, gravity, calls);
}

PyWorld unpickleWorld(const py::tuple& t) {
  if (t.size() != 7 || t[0].cast<int>() != 1)
    throw py::value_error("unpickling inertia.World: not a state this version wrote");
  Recipe r;
  r.scene = std::make_shared<const std::string>(t[1].cast<std::string>());
  r.name = t[2].cast<std::string>();
  r.dt = t[3].cast<std::optional<Real>>();
  r.threads = t[4].cast<std::optional<int>>();
  if (!t[5].is_none()) r.gravity = toVec3(t[5], "gravity");
  for (py::handle c : t[6].cast<py::list>()) {
    const auto call = c.cast<std::tuple<Real, int, std::int64_t>>();
    r.calls.push_back({std::get<0>(call), std::get<1>(call), std::get<2>(call)});
  }
  PyWorld w;
  w.world = r.make();
  w.recipe = std::move(r);
  return w;
}

RealArray pointsOf(const ContactInfo& c, bool onA) {
  const int n = c.manifold.pointCount;
  RealArray a({py::ssize_t(n), py::ssize_t(3)});
  Real* out = a.mutable_data();
  for (int i = 0; i < n; ++i)
    out = put(
        onA ? c.manifold.points[std::size_t(i)].pointA : c.manifold.points[std::size_t(i)].pointB,
        out);
  return a;
}

}  // namespace

void Recipe::record(Real value, int maxSteps, std::int64_t times) {
  if (!calls.empty() && calls.back().maxSteps == maxSteps &&
      std::memcmp(&calls.back().value, &value, sizeof(Real)) == 0)
    calls.back().repeat += times;
  else
    calls.push_back({value, maxSteps, times});
}

std::unique_ptr<World> Recipe::make() const {
  io::Scene s = io::parseScene(*scene, name);
  if (dt) s.world.dt = *dt;
  if (threads) s.world.threads = *threads;
  if (gravity) s.world.gravity = *gravity;
  std::unique_ptr<World> world = io::instantiate(s);
  py::gil_scoped_release release;
  for (const Call& c : calls)
    for (std::int64_t i = 0; i < c.repeat; ++i)
      if (c.maxSteps == 0)
        world->step(c.value);
      else
        world->advance(c.value, c.maxSteps);
  return world;
}

py::class_<PyWorld> worldClass(py::module_& m) {
  return py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
}

void bindWorld(py::module_& m) {
  py::enum_<BodyType>(m, "BodyType", "How a body moves.")
      .value("STATIC", BodyType::Static, "Never moves.")
      .value("KINEMATIC", BodyType::Kinematic, "Moved by the velocity it is given; not pushed.")
      .value("DYNAMIC", BodyType::Dynamic, "Moved by forces, gravity and contacts.");

  py::class_<PyState>(m, "WorldState",
                      "A snapshot of a world's rigid bodies, joints, contacts, particle "
                      "systems, deformables, articulations and clock (save_state); "
                      "restore_state continues "
                      "from it bit-identically.")
      .def_property_readonly(
          "time", [](const PyState& s) { return s.state.time; }, "Simulated time (s).")
      .def_property_readonly("step_count", [](const PyState& s) { return s.state.steps; });

  py::class_<ContactInfo>(m, "Contact", "A contact manifold between two shapes after a step.")
      .def_readonly("body_a", &ContactInfo::bodyA)
      .def_readonly("body_b", &ContactInfo::bodyB)
      .def_readonly("shape_a", &ContactInfo::shapeA)
      .def_readonly("shape_b", &ContactInfo::shapeB)
      .def_property_readonly(
          "normal", [](const ContactInfo& c) { return fromVec3(c.manifold.normal); },
          "Unit normal from A to B (world).")
      .def_property_readonly(
          "points_a", [](const ContactInfo& c) { return pointsOf(c, true); },
          "The points on A's surface (m, world), (k, 3), k <= 4.")
      .def_property_readonly(
          "points_b", [](const ContactInfo& c) { return pointsOf(c, false); },
          "The points on B's surface (m, world), (k, 3).")
      .def_property_readonly(
          "separations",
          [](const ContactInfo& c) {
            RealArray a(c.manifold.pointCount);
            for (int i = 0; i < c.manifold.pointCount; ++i)
              a.mutable_at(i) = c.manifold.points[std::size_t(i)].separation;
            return a;
          },
          "Per point (m): negative when overlapping, positive for a speculative point.")
      .def_property_readonly(
          "normal_impulses",
          [](const ContactInfo& c) {
            RealArray a(c.manifold.pointCount);
            for (int i = 0; i < c.manifold.pointCount; ++i)
              a.mutable_at(i) = c.normalImpulses[std::size_t(i)];
            return a;
          },
          "Per point, the last substep's normal impulse (N s).");

  py::class_<ContactEvent>(m, "ContactEvent", "A contact that began or ended in the last step.")
      .def_readonly("body_a", &ContactEvent::bodyA)
      .def_readonly("body_b", &ContactEvent::bodyB)
      .def_readonly("shape_a", &ContactEvent::shapeA)
      .def_readonly("shape_b", &ContactEvent::shapeB)
      .def_property_readonly(
          "point", [](const ContactEvent& e) { return fromVec3(e.point); },
          "A contact point (m, world).")
      .def_property_readonly(
          "normal", [](const ContactEvent& e) { return fromVec3(e.normal); },
          "Unit normal from A to B.")
      .def_readonly("approach_speed", &ContactEvent::approachSpeed,
                    "Normal approach speed at the start (m/s).");

  py::class_<WorldRayHit>(m, "RayHit", "Where a ray first hits a shape of the world.")
      .def_readonly("body", &WorldRayHit::body)
      .def_readonly("shape", &WorldRayHit::shape)
      .def_property_readonly(
          "distance", [](const WorldRayHit& h) { return h.hit.fraction; },
          "Distance from the ray's origin (m).")
      .def_property_readonly(
          "point", [](const WorldRayHit& h) { return fromVec3(h.hit.point); },
          "Hit point (m, world).")
      .def_property_readonly(
          "normal", [](const WorldRayHit& h) { return fromVec3(h.hit.normal); },
          "Unit surface normal at the hit.");

  py::class_<PyWorld> world(m, "World",
                            "A simulation world: rigid bodies, joints, particle systems and "
                            "deformables stepped with a fixed time step. Deterministic at any "
                            "thread count. It steps without the GIL; while it does, its methods "
                            "called from other threads raise RuntimeError. A world made from a "
                            "scene pickles (as the scene and the steps taken, replayed on "
                            "unpickling) until it is changed from Python.");
  world.def(
      py::init([](py::handle gravity, Real dt, int substeps, const std::string& solver,
                  int iterations, int relaxIterations, Real jointHertz, Real jointDampingRatio,
                  const std::string& integrator, int threads, bool sleeping) {
        PyWorld w;
        w.world = std::make_unique<World>(
            makeSettings(gravity, dt, substeps, solver, iterations, relaxIterations, jointHertz,
                         jointDampingRatio, integrator, threads, sleeping));
        return w;
      }),
      py::kw_only(), py::arg("gravity") = py::make_tuple(0, -9.81, 0), py::arg("dt") = 1.0 / 60,
      py::arg("substeps") = 4, py::arg("solver") = "soft_step", py::arg("iterations") = 4,
      py::arg("relax_iterations") = 1, py::arg("joint_hertz") = 120,
      py::arg("joint_damping_ratio") = 2, py::arg("integrator") = "symplectic_euler",
      py::arg("threads") = 0, py::arg("sleeping") = true,
      "gravity (m/s^2); dt: the fixed step of step() and advance() (s); substeps per step "
      "(1..64); solver: 'soft_step', 'pgs', 'lcp_dantzig' or 'lcp_lemke'; iterations "
      "per substep; relax_iterations: soft_step's passes without bias per substep; joint_hertz "
      "and joint_damping_ratio: soft_step's stiffness (Hz, at most half the substep rate) and "
      "damping of joints' locked rows and limits; integrator of free motion ('symplectic_euler', "
      "'rk4', ...); threads (0: every core; results do not depend on it); sleeping: bodies at "
      "rest sleep.");

  // Settings and clock.
  world
      .def_property_readonly(
          "gravity", [](const PyWorld& w) { return fromVec3(w->settings().gravity); },
          "Gravitational acceleration (m/s^2).")
      .def_property_readonly(
          "dt", [](const PyWorld& w) { return w->settings().dt; }, "The fixed time step (s).")
      .def_property_readonly("substeps", [](const PyWorld& w) { return w->settings().substeps; })
      .def_property_readonly("threads", [](const PyWorld& w) { return w->settings().threads; })
      .def_property_readonly(
          "time", [](const PyWorld& w) { return w->time(); }, "Simulated time (s).")
      .def_property_readonly("step_count", [](const PyWorld& w) { return w->stepCount(); })
      .def_property_readonly(
          "interpolation_alpha", [](const PyWorld& w) { return w->interpolationAlpha(); },
          "After advance(): where (0..1) real time lies between the last two "
          "physics states.")
      .def(
          "step",
          [](PyWorld& w, std::optional<Real> dt) {
            World& world = w.get();
            const Real h = dt.value_or(world.settings().dt);
            {
              SteppingScope stepping(w);
              py::gil_scoped_release release;  // the library checks h (InvalidArgument)
              world.step(h);
            }
            if (w.recipe) w.recipe->record(h, 0);
          },
          py::arg("dt") = py::none(),
          "Advances by exactly dt seconds (default: the world's dt), in substeps.")
      .def(
          "advance",
          [](PyWorld& w, Real frameTime, int maxSteps) {
            World& world = w.get();
            int taken = 0;
            {
              SteppingScope stepping(w);
              py::gil_scoped_release release;  // the library checks its arguments
              taken = world.advance(frameTime, maxSteps);
            }
            if (w.recipe) w.recipe->record(frameTime, maxSteps);
            return taken;
          },
          py::arg("frame_time"), py::arg("max_steps") = 8,
          "Advances a frame of frame_time seconds in fixed steps of dt with an accumulator; at "
          "most max_steps steps. Returns the number of steps taken.");

  // Bodies.
  world
      .def(
          "create_body",
          [](PyWorld& w, py::handle type, py::handle position, py::handle orientation,
             py::handle velocity, py::handle angularVelocity, Real linearDamping,
             Real angularDamping, Real gravityScale, Real mass, py::handle inertia, bool allowSleep,
             bool bullet, const std::string& name) {
            BodySettings s;
            s.type = toBodyType(type);
            s.position = toVec3(position, "position");
            s.orientation = toQuat(orientation, "orientation");
            s.linearVelocity = toVec3(velocity, "velocity");
            s.angularVelocity = toVec3(angularVelocity, "angular_velocity");
            s.linearDamping = linearDamping;
            s.angularDamping = angularDamping;
            s.gravityScale = gravityScale;
            s.mass = mass;
            s.inertia = toVec3(inertia, "inertia");
            s.allowSleep = allowSleep;
            s.bullet = bullet;
            s.name = name;
            return w->createBody(s);
          },
          py::kw_only(), py::arg("type") = "dynamic", py::arg("position") = py::make_tuple(0, 0, 0),
          py::arg("orientation") = py::make_tuple(1, 0, 0, 0),
          py::arg("velocity") = py::make_tuple(0, 0, 0),
          py::arg("angular_velocity") = py::make_tuple(0, 0, 0), py::arg("linear_damping") = 0,
          py::arg("angular_damping") = 0, py::arg("gravity_scale") = 1, py::arg("mass") = 0,
          py::arg("inertia") = py::make_tuple(0, 0, 0), py::arg("allow_sleep") = true,
          py::arg("bullet") = false, py::arg("name") = "",
          "Adds a body without shapes. type: 'static', 'kinematic' or 'dynamic'; position of "
          "its origin (m); orientation [w, x, y, z]; velocity of the centre of mass (m/s); "
          "angular_velocity (rad/s); dampings (1/s); mass (kg; 0: from the shapes' densities); "
          "inertia: principal moments (kg m^2; zero: from the shapes).")
      .def(
          "destroy_body", [](PyWorld& w, BodyId id) { w->destroyBody(id); }, py::arg("body"))
      .def(
          "add_shape",
          [](PyWorld& w, BodyId body, py::handle shape, const Material& material,
             py::handle position, py::handle orientation) {
            return w->addShape(body, toShape(shape, "shape"), material,
                               toPose(position, orientation));
          },
          py::arg("body"), py::arg("shape"), py::arg("material") = Material{}, py::kw_only(),
          py::arg("position") = py::none(), py::arg("orientation") = py::none(),
          "Attaches a shape made of material at position (m) and orientation [w, x, y, z] "
          "relative to the body's origin; updates the body's mass.")
      .def(
          "remove_shape", [](PyWorld& w, ShapeId s) { w->rigidBodies().removeShape(s); },
          py::arg("shape"))
      .def(
          "set_filter",
          [](PyWorld& w, ShapeId s, std::uint32_t category, std::uint32_t mask,
             std::int32_t group) {
            w->rigidBodies().setFilter(s, {category, mask, group});
          },
          py::arg("shape"), py::kw_only(), py::arg("category") = 1, py::arg("mask") = 0xFFFFFFFFu,
          py::arg("group") = 0,
          "Which shapes this one collides with, from the next step (wakes its body): two "
          "shapes of the same non-zero group always collide when it is positive and never when "
          "it is negative; otherwise each one's category bits must meet the other's mask "
          "(32-bit unsigned).")
      .def(
          "filter",
          [](const PyWorld& w, ShapeId s) {
            const CollisionFilter f = w->rigidBodies().filter(s);
            return py::make_tuple(f.category, f.mask, f.group);
          },
          py::arg("shape"), "The shape's collision filter as (category, mask, group).")
      .def("is_valid", [](const PyWorld& w, BodyId id) { return w->isValid(id); })
      .def("is_valid", [](const PyWorld& w, JointId id) { return w->isValid(id); })
      .def("is_valid", [](const PyWorld& w, ParticleSystemId id) { return w->isValid(id); })
      .def("is_valid", [](const PyWorld& w, DeformableId id) { return w->isValid(id); })
      .def(
          "bodies", [](const PyWorld& w) { return bodyList(*w); },
          "The live bodies in slot order: the order of the state arrays.")
      .def_property_readonly("body_count", [](const PyWorld& w) { return w->bodyCount(); })
      .def(
          "shapes", [](const PyWorld& w, BodyId id) { return w->rigidBodies().shapes(id); },
          py::arg("body"), "A body's shapes, in the order they were added.")
      .def(
          "shape_body", [](const PyWorld& w, ShapeId s) { return w->rigidBodies().body(s); },
          py::arg("shape"))
      .def(
          "find_body",
          [](const PyWorld& w, const std::string& name) {
            for (BodyId id : bodyList(*w))
              if (w->rigidBodies().name(id) == name) return id;
            throw py::key_error("no body named '" + name + "'");
          },
          py::arg("name"), "The first body with this name (KeyError when none has it).")
      .def(
          "body_name",
          [](const PyWorld& w, BodyId id) { return std::string(w->rigidBodies().name(id)); },
          py::arg("body"))
      .def(
          "body_type", [](const PyWorld& w, BodyId id) { return w->rigidBodies().type(id); },
          py::arg("body"))
      .def(
          "is_awake", [](const PyWorld& w, BodyId id) { return w->rigidBodies().isAwake(id); },
          py::arg("body"))
      .def(
          "position", [](const PyWorld& w, BodyId id) { return fromVec3(w->transform(id).p); },
          py::arg("body"), "Position of the body's origin (m).")
      .def(
          "orientation", [](const PyWorld& w, BodyId id) { return fromQuat(w->transform(id).q); },
          py::arg("body"), "Orientation, a unit quaternion [w, x, y, z].")
      .def(
          "linear_velocity",
          [](const PyWorld& w, BodyId id) { return fromVec3(w->linearVelocity(id)); },
          py::arg("body"), "Velocity of the centre of mass (m/s).")
      .def(
          "angular_velocity",
          [](const PyWorld& w, BodyId id) { return fromVec3(w->angularVelocity(id)); },
          py::arg("body"), "Angular velocity (rad/s).")
      .def(
          "center_of_mass",
          [](const PyWorld& w, BodyId id) { return fromVec3(w->rigidBodies().centerOfMass(id)); },
          py::arg("body"), "(m, world)")
      .def(
          "mass", [](const PyWorld& w, BodyId id) { return w->rigidBodies().mass(id); },
          py::arg("body"), "(kg); 0 for static and kinematic bodies.")
      .def(
          "inertia",
          [](const PyWorld& w, BodyId id) { return fromMat3(w->rigidBodies().inertiaWorld(id)); },
          py::arg("body"), "Inertia tensor about the centre of mass in world axes (kg m^2).")
      .def(
          "set_position",
          [](PyWorld& w, BodyId id, py::handle p) {
            Transform t = w->transform(id);
            t.p = toVec3(p, "position");
            w->rigidBodies().setTransform(id, t);
          },
          py::arg("body"), py::arg("position"), "Teleports the body's origin (m); wakes it.")
      .def(
          "set_orientation",
          [](PyWorld& w, BodyId id, py::handle q) {
            Transform t = w->transform(id);
            t.q = toQuat(q, "orientation");
            w->rigidBodies().setTransform(id, t);
          },
          py::arg("body"), py::arg("orientation"), "[w, x, y, z], normalised; wakes the body.")
      .def(
          "set_linear_velocity",
          [](PyWorld& w, BodyId id, py::handle v) {
            w->rigidBodies().setLinearVelocity(id, toVec3(v, "velocity"));
          },
          py::arg("body"), py::arg("velocity"), "(m/s); wakes the body.")
      .def(
          "set_angular_velocity",
          [](PyWorld& w, BodyId id, py::handle v) {
            w->rigidBodies().setAngularVelocity(id, toVec3(v, "angular_velocity"));
          },
          py::arg("body"), py::arg("angular_velocity"), "(rad/s); wakes the body.")
      .def(
          "move_kinematic",
          [](PyWorld& w, BodyId id, py::handle position, py::handle orientation, Real dt) {
            w->rigidBodies().moveKinematic(id, toPose(position, orientation), dt);
          },
          py::arg("body"), py::arg("position"), py::arg("orientation"), py::arg("dt"),
          "Kinematic bodies: sets the velocities that reach the pose in dt seconds.")
      .def(
          "apply_force",
          [](PyWorld& w, BodyId id, py::handle force, py::handle point) {
            const Vec3 f = toVec3(force, "force");
            if (point.is_none())
              w->rigidBodies().applyForceAtCenter(id, f);
            else
              w->rigidBodies().applyForce(id, f, toVec3(point, "point"));
          },
          py::arg("body"), py::arg("force"), py::arg("point") = py::none(),
          "A force (N) at a world point (m; default the centre of mass), over the next step.")
      .def(
          "apply_torque",
          [](PyWorld& w, BodyId id, py::handle t) {
            w->rigidBodies().applyTorque(id, toVec3(t, "torque"));
          },
          py::arg("body"), py::arg("torque"), "(N m), over the next step.")
      .def(
          "apply_impulse",
          [](PyWorld& w, BodyId id, py::handle impulse, py::handle point) {
            const Vec3 j = toVec3(impulse, "impulse");
            const Vec3 p =
                point.is_none() ? w->rigidBodies().centerOfMass(id) : toVec3(point, "point");
            w->rigidBodies().applyImpulse(id, j, p);
          },
          py::arg("body"), py::arg("impulse"), py::arg("point") = py::none(),
          "An impulse (N s) at a world point (m; default the centre of mass), at once.")
      .def(
          "apply_angular_impulse",
          [](PyWorld& w, BodyId id, py::handle l) {
            w->rigidBodies().applyAngularImpulse(id, toVec3(l, "impulse"));
          },
          py::arg("body"), py::arg("impulse"), "(N m s), at once.")
      .def(
          "wake", [](PyWorld& w, BodyId id) { w->rigidBodies().wake(id); }, py::arg("body"));

  // State of every body as arrays, in bodies() order: copies (the bodies are records, not
  // arrays, in the library), read and written in one call each.
  world
      .def(
          "positions",
          [](const PyWorld& w) {
            return gather(*w, 3, [&](BodyId id, Real* o) { return put(w->transform(id).p, o); });
          },
          "Positions of the bodies' origins (m), (n, 3).")
      .def(
          "orientations",
          [](const PyWorld& w) {
            return gather(*w, 4, [&](BodyId id, Real* o) { return put(w->transform(id).q, o); });
          },
          "Orientations [w, x, y, z], (n, 4).")
      .def(
          "linear_velocities",
          [](const PyWorld& w) {
            return gather(*w, 3, [&](BodyId id, Real* o) { return put(w->linearVelocity(id), o); });
          },
          "Velocities of the centres of mass (m/s), (n, 3).")
      .def(
          "angular_velocities",
          [](const PyWorld& w) {
            return gather(*w, 3,
                          [&](BodyId id, Real* o) { return put(w->angularVelocity(id), o); });
          },
          "Angular velocities (rad/s), (n, 3).")
      .def(
          "set_positions",
          [](PyWorld& w, py::handle a) {
            scatter(*w, a, "positions", 3, [&](BodyId id, const Real* p) {
              Transform t = w->transform(id);
              t.p = Vec3(p[0], p[1], p[2]);
              w->rigidBodies().setTransform(id, t);
            });
          },
          py::arg("positions"), "Teleports every body's origin (m), (n, 3); wakes them.")
      .def(
          "set_orientations",
          [](PyWorld& w, py::handle a) {
            scatter(*w, a, "orientations", 4, [&](BodyId id, const Real* q) {
              Transform t = w->transform(id);
              t.q = Quat(q[0], q[1], q[2], q[3]);
              w->rigidBodies().setTransform(id, t);
            });
          },
          py::arg("orientations"), "[w, x, y, z] per body, (n, 4), normalised; wakes them.")
      .def(
          "set_linear_velocities",
          [](PyWorld& w, py::handle a) {
            scatter(*w, a, "velocities", 3, [&](BodyId id, const Real* v) {
              w->rigidBodies().setLinearVelocity(id, Vec3(v[0], v[1], v[2]));
            });
          },
          py::arg("velocities"), "(m/s), (n, 3); static bodies ignore theirs.")
      .def(
          "set_angular_velocities",
          [](PyWorld& w, py::handle a) {
            scatter(*w, a, "angular_velocities", 3, [&](BodyId id, const Real* v) {
              w->rigidBodies().setAngularVelocity(id, Vec3(v[0], v[1], v[2]));
            });
          },
          py::arg("angular_velocities"), "(rad/s), (n, 3); static bodies ignore theirs.")
      .def(
          "kinetic_energy", [](const PyWorld& w) { return w->rigidBodies().kineticEnergy(); },
          "Of the dynamic bodies (J).")
      .def(
          "linear_momentum",
          [](const PyWorld& w) { return fromVec3(w->rigidBodies().linearMomentum()); }, "(kg m/s)")
      .def(
          "angular_momentum",
          [](const PyWorld& w, py::handle about) {
            return fromVec3(w->rigidBodies().angularMomentum(toVec3(about, "about")));
          },
          py::arg("about") = py::make_tuple(0, 0, 0), "About a world point (kg m^2/s).");

  // Contacts, events and queries.
  world
      .def_property_readonly(
          "contact_count", [](const PyWorld& w) { return w->contactCount(); },
          "Touching manifolds after the last step.")
      .def(
          "contacts", [](const PyWorld& w) { return w->rigidBodies().contacts(); },
          "Every manifold of the last step (touching or speculative).")
      .def(
          "contact_begin_events", [](const PyWorld& w) { return w->rigidBodies().beginEvents(); },
          "Contacts that began in the last step.")
      .def(
          "contact_end_events", [](const PyWorld& w) { return w->rigidBodies().endEvents(); },
          "Contacts that ended in the last step.")
      .def(
          "cast_ray",
          [](const PyWorld& w, py::handle origin, py::handle direction,
             Real maxDistance) -> std::optional<WorldRayHit> {
            const Vec3 o = toVec3(origin, "origin");
            const Vec3 d = toVec3(direction, "direction");
            if (!o.allFinite()) argumentError("origin", "must be finite");
            if (!(d.allFinite() && d.norm() > 0))
              argumentError("direction", "must be finite and non-zero");
            if (!(maxDistance >= 0)) argumentError("max_distance", "must be >= 0 (m)");
            // A unit direction makes the hit's fraction its distance.
            return w->castRay(Ray{o, d.normalized(), maxDistance});
          },
          py::arg("origin"), py::arg("direction"), py::arg("max_distance") = 1e4,
          "The first shape hit by the ray from origin (m) along direction within max_distance "
          "(m), or None.")
      .def(
          "save_state",
          [](const PyWorld& w) {
            return PyState{w->saveState(), w.serial, w.recipe};
          },
          "A snapshot of the bodies, joints, contacts, particle systems, deformables, "
          "articulations and clock.")
      .def("restore_state", &restoreState, py::arg("state"),
           "Continues from a snapshot bit-identically. A world restored to its own snapshot "
           "pickles as it did when the snapshot was taken.")
      .def(py::pickle(&pickleWorld, &unpickleWorld));

  m.def(
      "load_scene",
      [](const std::string& path, std::optional<Real> dt, std::optional<int> threads) {
        io::loadScene(path);  // SceneError with the file and pointer, before the recipe's read
        return fromScene(readFile(path), path, dt, threads);
      },
      py::arg("path"), py::kw_only(), py::arg("dt") = py::none(), py::arg("threads") = py::none(),
      "A World from a scene file (JSON, DESIGN.md section 4); dt (s) and threads override the "
      "file's, as `inertia run --dt --threads` do. Raises SceneError (a ValueError) with the file, "
      "the JSON pointer and the reason.");
  m.def(
      "parse_scene",
      [](py::handle scene, const std::string& name, std::optional<Real> dt,
         std::optional<int> threads) {
        std::string text;
        if (py::isinstance<py::str>(scene))
          text = scene.cast<std::string>();
        else
          text = py::module_::import("json").attr("dumps")(scene).cast<std::string>();
        return fromScene(std::move(text), name, dt, threads);
      },
      py::arg("scene"), py::arg("name") = "<scene>", py::kw_only(), py::arg("dt") = py::none(),
      py::arg("threads") = py::none(),
      "A World from scene text or a dict of the same structure; `name` stands for the file in "
      "messages (relative paths resolve against its folder).");
}

}  // namespace inertia::python
