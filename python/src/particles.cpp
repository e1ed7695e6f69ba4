// Particle systems of a World: creation, emitters, fields, obstacles, and the live particles as
// NumPy arrays that alias the pool's memory (structure of arrays: positions are one contiguous
// (n, 3) block), so reading them copies nothing and writing into them moves the particles.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "bindings.h"
#include "convert.h"
#include "inertia/particles/particle_system.h"
#include "shapes.h"

namespace inertia::python {

namespace {

Range toRange(py::handle value, const char* arg) {
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) {
    const Real x = value.cast<Real>();
    return {x, x};
  }
  Real r[2];
  toReals(value, arg, r, 2);
  return {r[0], r[1]};
}

EmitterShape toEmitterShape(const std::string& name) {
  static const std::pair<const char*, EmitterShape> kNames[] = {
      {"point", EmitterShape::Point},
      {"sphere", EmitterShape::Sphere},
      {"sphere_surface", EmitterShape::SphereSurface},
      {"box", EmitterShape::Box},
      {"cone", EmitterShape::Cone},
      {"disc", EmitterShape::Disc},
      {"mesh", EmitterShape::MeshSurface}};
  for (const auto& [n, shape] : kNames)
    if (name == n) return shape;
  argumentError("shape", "unknown emitter shape '" + name +
                             "' (point, sphere, sphere_surface, box, cone, disc, mesh)");
}

void rangeProperty(py::class_<EmitterSettings>& c, const char* name, Range EmitterSettings::*member,
                   const char* doc) {
  c.def_property(
      name,
      [member](const EmitterSettings& s) {
        return py::make_tuple((s.*member).min, (s.*member).max);
      },
      [member, name](EmitterSettings& s, py::handle v) { s.*member = toRange(v, name); }, doc);
}

void writeRows(std::span<Real> dst, py::handle value, const char* arg, std::size_t n) {
  RealArray a = toMatrix(value, arg, py::ssize_t(n), 3);
  // The pool trusts its values (the library checks them where they enter: emitters); here
  // they enter from Python.
  if (!std::all_of(a.data(), a.data() + 3 * n, [](Real x) { return std::isfinite(x); }))
    argumentError(arg, "values must be finite");
  std::copy_n(a.data(), 3 * n, dst.data());
}

}  // namespace

namespace {

// A view's keeper: holds the World's Python object alive and counts the system's views.
struct ViewKeeper {
  py::object world;
  ViewCounts PyWorld::*counts;
  std::uint32_t slot;
};

}  // namespace

py::array countedView(py::object self, ViewCounts PyWorld::*counts, std::uint32_t slot,
                      const Real* data, std::size_t n, py::ssize_t cols) {
  PyWorld& w = self.cast<PyWorld&>();
  ++(w.*counts)[slot];
  py::capsule keeper(new ViewKeeper{self, counts, slot}, [](void* p) {
    auto* k = static_cast<ViewKeeper*>(p);
    ViewCounts& views = k->world.cast<PyWorld&>().*(k->counts);
    if (--views[k->slot] == 0) views.erase(k->slot);
    delete k;
  });
  RealArray a =
      cols == 1
          ? RealArray({py::ssize_t(n)}, {py::ssize_t(sizeof(Real))}, data, keeper)
          : RealArray({py::ssize_t(n), cols},
                      {py::ssize_t(cols * py::ssize_t(sizeof(Real))), py::ssize_t(sizeof(Real))},
                      data, keeper);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

ForceField toForceField(py::handle field, py::handle region) {
  ForceField f;
  if (py::isinstance<GravityField>(field))
    f.field = field.cast<GravityField>();
  else if (py::isinstance<LinearDragField>(field))
    f.field = field.cast<LinearDragField>();
  else if (py::isinstance<QuadraticDragField>(field))
    f.field = field.cast<QuadraticDragField>();
  else if (py::isinstance<WindField>(field))
    f.field = field.cast<WindField>();
  else if (py::isinstance<VortexField>(field))
    f.field = field.cast<VortexField>();
  else if (py::isinstance<AttractorField>(field))
    f.field = field.cast<AttractorField>();
  else if (py::isinstance<TurbulenceField>(field))
    f.field = field.cast<TurbulenceField>();
  else
    argumentError("field", "expected one of the inertia.*Field classes");
  if (!region.is_none()) {
    if (py::len(region) != 2) argumentError("region", "expected (lower, upper)");
    f.region = Aabb{toVec3(region[py::int_(0)], "region"), toVec3(region[py::int_(1)], "region")};
  }
  return f;
}

void bindParticles(py::module_& m) {
  py::class_<EmitterSettings> emitter(
      m, "Emitter",
      "Where new particles appear, which way, how fast and for how long. Made "
      "with keywords; ranges are a number or (min, max).");
  emitter.def(py::init([](const py::kwargs& kwargs) {
    EmitterSettings s;
    setAttributes(py::cast(&s, py::return_value_policy::reference), kwargs, "Emitter");
    return s;
  }));
  emitter.def_property(
      "shape",
      [](const EmitterSettings& s) {
        static const char* kNames[] = {"point", "sphere", "sphere_surface", "box", "cone",
                                       "disc",  "mesh"};
        return std::string(kNames[int(s.shape)]);
      },
      [](EmitterSettings& s, const std::string& name) { s.shape = toEmitterShape(name); },
      "'point', 'sphere', 'sphere_surface', 'box', 'cone', 'disc' or 'mesh'.");
  emitter.def_property(
      "position", [](const EmitterSettings& s) { return fromVec3(s.pose.p); },
      [](EmitterSettings& s, py::handle v) { s.pose.p = toVec3(v, "position"); },
      "The emitter's origin (m; relative to attach_to's body when attached).");
  emitter.def_property(
      "orientation", [](const EmitterSettings& s) { return fromQuat(s.pose.q); },
      [](EmitterSettings& s, py::handle v) { s.pose.q = toQuat(v, "orientation"); },
      "[w, x, y, z]");
  emitter.def_readwrite("radius", &EmitterSettings::radius, "Sphere and disc radius (m).");
  vec3Property(emitter, "half_extents", &EmitterSettings::halfExtents, "Box (m).");
  emitter.def_readwrite("angle", &EmitterSettings::angle, "Cone half-angle (rad).");
  emitter.def_property(
      "mesh", [](const EmitterSettings&) { return py::none(); },
      [](EmitterSettings& s, std::shared_ptr<TriangleMesh> mesh) { s.mesh = mesh; },
      "A TriangleMesh for 'mesh' emitters (write-only).");
  emitter.def_readwrite("rate", &EmitterSettings::rate, "Particles per second.");
  emitter.def_readwrite("burst", &EmitterSettings::burst, "Particles emitted at the first step.");
  vec3Property(emitter, "direction", &EmitterSettings::direction, "Base direction (local).");
  emitter.def_readwrite("spread", &EmitterSettings::spread, "Random tilt half-angle (rad).");
  rangeProperty(emitter, "speed", &EmitterSettings::speed, "(m/s)");
  rangeProperty(emitter, "lifetime", &EmitterSettings::lifetime, "(s; inf: immortal)");
  rangeProperty(emitter, "mass", &EmitterSettings::mass, "(kg)");
  rangeProperty(emitter, "size", &EmitterSettings::size, "Particle radius (m).");
  vec3Property(emitter, "color_min", &EmitterSettings::colorMin, "rgb 0..1");
  vec3Property(emitter, "color_max", &EmitterSettings::colorMax, "rgb 0..1");
  emitter.def_readwrite("seed", &EmitterSettings::seed, "Same seed, same particles.");
  emitter.def_property(
      "attach_to",
      [](const EmitterSettings& s) -> py::object {
        return s.attachTo.isNull() ? py::none() : py::cast(s.attachTo);
      },
      [](EmitterSettings& s, std::optional<BodyId> body) { s.attachTo = body.value_or(BodyId{}); },
      "A body the emitter rides on, or None.");

  // Force fields: each a small value class; World.add_field takes any of them.
  py::class_<GravityField>(m, "GravityField", "Uniform acceleration g (m/s^2).")
      .def(py::init([](py::handle g) { return GravityField{toVec3(g, "g")}; }),
           py::arg("g") = py::make_tuple(0, -9.81, 0));
  py::class_<LinearDragField>(m, "LinearDragField", "F = -k v (k in kg/s).")
      .def(py::init([](Real k) { return LinearDragField{k}; }), py::arg("k") = 0.1);
  py::class_<QuadraticDragField>(m, "QuadraticDragField", "F = -k |v| v (k in kg/m).")
      .def(py::init([](Real k) { return QuadraticDragField{k}; }), py::arg("k") = 0.01);
  py::class_<WindField>(m, "WindField", "F = -k (v - velocity) (velocity m/s, k kg/s).")
      .def(py::init([](py::handle v, Real k) {
             return WindField{toVec3(v, "velocity"), k};
           }),
           py::arg("velocity") = py::make_tuple(1, 0, 0), py::arg("k") = 0.1);
  py::class_<VortexField>(m, "VortexField",
                          "A Rankine vortex about axis through center (m), angular_speed (rad/s) "
                          "inside core_radius (m), tightness (1/s).")
      .def(py::init([](py::handle center, py::handle axis, Real angularSpeed, Real coreRadius,
                       Real tightness) {
             return VortexField{toVec3(center, "center"), toVec3(axis, "axis"), angularSpeed,
                                coreRadius, tightness};
           }),
           py::kw_only(), py::arg("center") = py::make_tuple(0, 0, 0),
           py::arg("axis") = py::make_tuple(0, 1, 0), py::arg("angular_speed") = 1,
           py::arg("core_radius") = 1, py::arg("tightness") = 5);
  py::class_<AttractorField>(m, "AttractorField",
                             "A point attractor (strength > 0) or repeller; falloff "
                             "'inverse_square', 'linear' or 'constant'.")
      .def(py::init([](py::handle position, Real strength, const std::string& falloff, Real cutoff,
                       Real minDistance) {
             AttractorField f{toVec3(position, "position"), strength};
             if (falloff == "inverse_square")
               f.falloff = Falloff::InverseSquare;
             else if (falloff == "linear")
               f.falloff = Falloff::Linear;
             else if (falloff == "constant")
               f.falloff = Falloff::Constant;
             else
               argumentError("falloff", "expected 'inverse_square', 'linear' or 'constant'");
             f.cutoff = cutoff;
             f.minDistance = minDistance;
             return f;
           }),
           py::kw_only(), py::arg("position") = py::make_tuple(0, 0, 0), py::arg("strength") = 1,
           py::arg("falloff") = "inverse_square",
           py::arg("cutoff") = std::numeric_limits<Real>::infinity(),
           py::arg("min_distance") = 0.05);
  py::class_<TurbulenceField>(m, "TurbulenceField",
                              "Curl-noise turbulence: amplitude (m/s^2), scale (m), speed (rad/s).")
      .def(py::init([](Real amplitude, Real scale, Real speed, int modes, std::uint64_t seed) {
             return TurbulenceField{amplitude, scale, speed, modes, seed};
           }),
           py::kw_only(), py::arg("amplitude") = 1, py::arg("scale") = 1, py::arg("speed") = 0,
           py::arg("modes") = 8, py::arg("seed") = 1);

  py::class_<PyWorld> world = worldClass(m);
  world
      .def(
          "create_particle_system",
          [](PyWorld& w, const std::string& name, std::size_t capacity,
             const std::string& integrator, Real restitution, Real friction,
             Real restitutionThreshold, bool particleCollisions, bool collideWithBodies) {
            ParticleSystemSettings s;
            s.name = name;
            s.capacity = capacity;
            const std::optional<ode::Method> method = ode::methodFromName(integrator);
            if (!method) argumentError("integrator", "unknown integrator '" + integrator + "'");
            s.integrator = *method;
            s.restitution = restitution;
            s.friction = friction;
            s.restitutionThreshold = restitutionThreshold;
            s.particleCollisions = particleCollisions;
            s.collideWithBodies = collideWithBodies;
            return w->createParticleSystem(s);
          },
          py::kw_only(), py::arg("name") = "", py::arg("capacity") = 10000,
          py::arg("integrator") = "symplectic_euler", py::arg("restitution") = 0.5,
          py::arg("friction") = 0.1, py::arg("restitution_threshold") = 0.05,
          py::arg("particle_collisions") = false, py::arg("collide_with_bodies") = false,
          "Adds a particle system of `capacity` particles; restitution and friction against "
          "obstacles; restitution_threshold (m/s).")
      .def(
          "destroy_particle_system",
          [](PyWorld& w, ParticleSystemId id) {
            if (std::as_const(w)->isValid(id))  // a read: the recipe stays
              PyWorld::refuseViewed(w.particleViews, id.index, "destroy_particle_system",
                                    "its particles");
            w->destroyParticleSystem(id);
          },
          py::arg("system"))
      .def("particle_systems", [](const PyWorld& w) { return w->particleSystems(); })
      .def(
          "particle_system_name",
          [](const PyWorld& w, ParticleSystemId id) { return w->particleSystem(id).name(); },
          py::arg("system"))
      .def(
          "add_emitter",
          [](PyWorld& w, ParticleSystemId id, const EmitterSettings& e) {
            return w->particleSystem(id).addEmitter(e);
          },
          py::arg("system"), py::arg("emitter"))
      .def(
          "add_field",
          [](PyWorld& w, ParticleSystemId id, py::handle field, py::handle region) {
            return w->particleSystem(id).addField(toForceField(field, region));
          },
          py::arg("system"), py::arg("field"), py::arg("region") = py::none(),
          "Adds a force field, optionally limited to the box region = (lower, upper) (m).")
      .def(
          "add_obstacle",
          [](PyWorld& w, ParticleSystemId id, py::handle shape, py::handle position,
             py::handle orientation) {
            return w->particleSystem(id).addObstacle(
                Obstacle{Collider(toShape(shape, "shape")), toPose(position, orientation)});
          },
          py::arg("system"), py::arg("shape"), py::kw_only(), py::arg("position") = py::none(),
          py::arg("orientation") = py::none(), "A static shape the particles collide with.")
      .def(
          "particle_count",
          [](const PyWorld& w, ParticleSystemId id) { return w->particleSystem(id).pool().size(); },
          py::arg("system"), "Live particles.")
      .def(
          "particle_stats",
          [](const PyWorld& w, ParticleSystemId id) {
            const ParticleStats s = w->particleSystem(id).stats();
            py::dict d;
            d["alive"] = s.alive;
            d["emitted"] = s.emitted;
            d["died"] = s.died;
            d["dropped"] = s.dropped;
            return d;
          },
          py::arg("system"), "Counters since creation: alive, emitted, died, dropped.")
      .def(
          "particle_positions",
          [](py::object self, ParticleSystemId id) {
            const ParticlePool& pool = self.cast<const PyWorld&>()->particleSystem(id).pool();
            return countedView(self, &PyWorld::particleViews, id.index, pool.positions().data(),
                               pool.size(), 3);
          },
          py::arg("system"),
          "The live particles' positions (m), (n, 3): a read-only view of the pool's memory, "
          "not a copy (set_particle_positions writes). Valid for the particles live now: take "
          "a new one after a step (particles are born and die).")
      .def(
          "particle_velocities",
          [](py::object self, ParticleSystemId id) {
            const ParticlePool& pool = self.cast<const PyWorld&>()->particleSystem(id).pool();
            return countedView(self, &PyWorld::particleViews, id.index, pool.velocities().data(),
                               pool.size(), 3);
          },
          py::arg("system"),
          "The live particles' velocities (m/s), (n, 3): a read-only view, as positions.")
      .def(
          "particle_ages",
          [](py::object self, ParticleSystemId id) {
            const ParticlePool& pool = self.cast<const PyWorld&>()->particleSystem(id).pool();
            return countedView(self, &PyWorld::particleViews, id.index, pool.ages().data(),
                               pool.size(), 1);
          },
          py::arg("system"), "Ages (s), (n,): a read-only view.")
      .def(
          "particle_ids",
          [](const PyWorld& w, ParticleSystemId id) {
            const auto ids = w->particleSystem(id).pool().ids();
            return py::array_t<std::uint64_t>(py::ssize_t(ids.size()), ids.data());
          },
          py::arg("system"), "Unique ids, increasing along the pool (a copy).")
      .def(
          "set_particle_positions",
          [](PyWorld& w, ParticleSystemId id, py::handle a) {
            ParticlePool& pool = w->particleSystem(id).pool();
            writeRows(pool.positions(), a, "positions", pool.size());
          },
          py::arg("system"), py::arg("positions"), "(m), (n, 3) for the n live particles.")
      .def(
          "set_particle_velocities",
          [](PyWorld& w, ParticleSystemId id, py::handle a) {
            ParticlePool& pool = w->particleSystem(id).pool();
            writeRows(pool.velocities(), a, "velocities", pool.size());
          },
          py::arg("system"), py::arg("velocities"), "(m/s), (n, 3) for the n live particles.");
}

}  // namespace inertia::python
