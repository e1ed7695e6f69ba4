#include "particles_section.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "inertia/core/error.h"
#include "inertia/geometry/mesh.h"
#include "shape_reader.h"

namespace inertia::io::detail {

namespace {

// A range is [min, max] or a single number. `allowInfinity` admits "inf" as a string for
// immortal particles (JSON has no infinity).
Range readRange(const Node& n, double lo, double hi, bool openLo, bool allowInfinity = false) {
  auto one = [&](const Node& x) -> Real {
    if (allowInfinity && x.json().is_string()) {
      if (x.string() == "inf") return std::numeric_limits<Real>::infinity();
      x.fail("expected a number or \"inf\", got \"" + x.string() + "\"");
    }
    return Real(x.number(lo, hi, openLo));
  };
  if (n.json().is_array()) {
    if (n.requireArray() != 2) n.fail("expected a number or a range [min, max]");
    Range r{one(n.at(std::size_t(0))), one(n.at(std::size_t(1)))};
    if (r.min > r.max) n.fail("range minimum exceeds its maximum");
    return r;
  }
  return Range::constant(one(n));
}

EmitterSettings readEmitter(const Node& n, Real defaultSize, const std::vector<BodyDesc>& bodies) {
  EmitterSettings e;
  e.size = Range::constant(defaultSize);
  const std::string type = n.at("type").string();
  n.requireObject({"type", "position", "orientation", "rate", "burst", "direction", "spread",
                   "speed", "lifetime", "mass", "size", "color", "seed", "radius",
                   "half_extents", "angle", "vertices", "triangles", "attach_to"});
  if (type == "point") e.shape = EmitterShape::Point;
  else if (type == "sphere") e.shape = EmitterShape::Sphere;
  else if (type == "sphere_surface") e.shape = EmitterShape::SphereSurface;
  else if (type == "box") e.shape = EmitterShape::Box;
  else if (type == "cone") e.shape = EmitterShape::Cone;
  else if (type == "disc") e.shape = EmitterShape::Disc;
  else if (type == "mesh") e.shape = EmitterShape::MeshSurface;
  else
    n.at("type").fail("unknown emitter type \"" + type +
                      "\"; expected one of point, sphere, sphere_surface, box, cone, disc, mesh");
  e.pose = readPose(n);
  if (n.has("rate")) e.rate = Real(n.at("rate").number(0, 1e9));
  if (n.has("burst")) e.burst = n.at("burst").integer(0, 1ll << 31);
  if (n.has("direction")) {
    e.direction = n.at("direction").vec3();
    if (e.direction.norm() < Real(1e-6)) n.at("direction").fail("direction must be non-zero");
  }
  if (n.has("spread")) e.spread = Real(n.at("spread").number(0, std::numbers::pi));
  if (n.has("speed")) e.speed = readRange(n.at("speed"), 0, 1e6, false);
  if (n.has("lifetime")) e.lifetime = readRange(n.at("lifetime"), 0, 1e9, true, true);
  if (n.has("mass")) e.mass = readRange(n.at("mass"), 0, 1e9, true);
  if (n.has("size")) e.size = readRange(n.at("size"), 0, 1e3, false);
  if (n.has("color")) {
    Node c = n.at("color");
    if (c.requireArray() == 2 && c.at(std::size_t(0)).json().is_array()) {
      e.colorMin = c.at(std::size_t(0)).vec3();
      e.colorMax = c.at(std::size_t(1)).vec3();
    } else {
      e.colorMin = e.colorMax = c.vec3();
    }
  }
  if (n.has("seed")) e.seed = std::uint64_t(n.at("seed").integer(0, std::numeric_limits<long long>::max()));
  if (n.has("radius")) e.radius = Real(n.at("radius").number(0, 1e6));
  if (n.has("half_extents")) e.halfExtents = n.at("half_extents").vec3();
  if (n.has("angle")) e.angle = Real(n.at("angle").number(0, std::numbers::pi));
  if (e.shape == EmitterShape::MeshSurface) {
    // A mesh emitter's surface is given like a mesh shape's.
    std::vector<Vec3> vertices = readPoints(n.at("vertices"));
    std::vector<Triangle> triangles = readTriangles(n.at("triangles"), vertices.size());
    checked(n, [&] { e.mesh = std::make_shared<TriangleMesh>(std::move(vertices), std::move(triangles)); });
  } else if (n.has("vertices") || n.has("triangles")) {
    n.fail("\"vertices\" and \"triangles\" belong to mesh emitters only");
  }
  if (n.has("attach_to")) {
    // A body of the scene by name (unique: parseScene checks); the emitter's position and
    // orientation are then relative to the body's origin. io::instantiate() turns the name
    // into the body's id.
    Node a = n.at("attach_to");
    const std::string name = a.string();
    if (std::none_of(bodies.begin(), bodies.end(),
                     [&](const BodyDesc& b) { return b.settings.name == name; }))
      a.fail("no body is named \"" + name + "\"");
    e.attachToName = name;
  }
  checked(n, [&] { validate(e); });
  return e;
}

}  // namespace

ForceField readField(const Node& n) {
  const std::string type = n.at("type").string();
  ForceField f;
  auto keys = [&](std::initializer_list<std::string_view> own) {
    std::vector<std::string_view> all{"type", "region"};
    all.insert(all.end(), own.begin(), own.end());
    n.requireObject(all);
  };
  if (type == "gravity") {
    keys({"g"});
    GravityField g;
    if (n.has("g")) g.g = n.at("g").vec3();
    f.field = g;
  } else if (type == "drag") {
    keys({"k"});
    f.field = LinearDragField{Real(n.at("k").number(0, 1e9))};
  } else if (type == "quadratic_drag") {
    keys({"k"});
    f.field = QuadraticDragField{Real(n.at("k").number(0, 1e9))};
  } else if (type == "wind") {
    keys({"velocity", "k"});
    f.field = WindField{n.at("velocity").vec3(), Real(n.at("k").number(0, 1e9))};
  } else if (type == "vortex") {
    keys({"center", "axis", "angular_speed", "core_radius", "tightness"});
    VortexField v;
    if (n.has("center")) v.center = n.at("center").vec3();
    if (n.has("axis")) v.axis = n.at("axis").vec3();
    v.angularSpeed = Real(n.at("angular_speed").number(-1e6, 1e6));
    if (n.has("core_radius")) v.coreRadius = Real(n.at("core_radius").number(0, 1e6, true));
    if (n.has("tightness")) v.tightness = Real(n.at("tightness").number(0, 1e6));
    f.field = v;
  } else if (type == "attractor") {
    keys({"position", "strength", "falloff", "cutoff", "min_distance"});
    AttractorField a;
    if (n.has("position")) a.position = n.at("position").vec3();
    a.strength = Real(n.at("strength").number(-1e9, 1e9));
    if (n.has("falloff")) {
      Node fo = n.at("falloff");
      const std::string s = fo.string();
      if (s == "inverse_square") a.falloff = Falloff::InverseSquare;
      else if (s == "linear") a.falloff = Falloff::Linear;
      else if (s == "constant") a.falloff = Falloff::Constant;
      else fo.fail("unknown falloff \"" + s + "\"; expected inverse_square, linear or constant");
    }
    if (n.has("cutoff")) a.cutoff = Real(n.at("cutoff").number(0, 1e9, true));
    if (n.has("min_distance")) a.minDistance = Real(n.at("min_distance").number(0, 1e6, true));
    f.field = a;
  } else if (type == "turbulence") {
    keys({"amplitude", "scale", "speed", "modes", "seed"});
    TurbulenceField t;
    t.amplitude = Real(n.at("amplitude").number(-1e6, 1e6));
    if (n.has("scale")) t.scale = Real(n.at("scale").number(0, 1e6, true));
    if (n.has("speed")) t.speed = Real(n.at("speed").number(-1e6, 1e6));
    if (n.has("modes")) t.modes = int(n.at("modes").integer(1, 64));
    if (n.has("seed")) t.seed = std::uint64_t(n.at("seed").integer(0, std::numeric_limits<long long>::max()));
    f.field = t;
  } else {
    n.at("type").fail("unknown field type \"" + type +
                      "\"; expected one of gravity, drag, quadratic_drag, wind, vortex, attractor, turbulence");
  }
  if (n.has("region")) {
    Node r = n.at("region");
    r.requireObject({"min", "max"});
    Aabb box{r.at("min").vec3(), r.at("max").vec3()};
    if (!box.isValid()) r.fail("region min must not exceed max on any axis");
    f.region = box;
  }
  checked(n, [&] { validate(f); });
  return f;
}

ParticleSystemDesc readParticleSystem(const Node& n, std::size_t index, const std::vector<BodyDesc>& bodies) {
  n.requireObject({"name", "capacity", "integrator", "emitters", "fields", "obstacles",
                   "restitution", "friction", "radius", "restitution_threshold",
                   "particle_collisions", "collide_with_bodies"});
  ParticleSystemDesc d;
  ParticleSystemSettings& s = d.settings;
  s.name = n.has("name") ? n.at("name").string() : std::to_string(index);
  if (n.has("capacity")) s.capacity = std::size_t(n.at("capacity").integer(1, 1ll << 31));
  if (n.has("integrator")) {
    Node i = n.at("integrator");
    auto method = ode::methodFromName(i.string());
    if (!method) {
      std::string names;
      for (std::string_view m : ode::kMethodNames) names += (names.empty() ? "" : ", ") + std::string(m);
      i.fail("unknown integrator \"" + i.string() + "\"; expected one of " + names);
    }
    s.integrator = *method;
  }
  if (n.has("restitution")) s.restitution = Real(n.at("restitution").number(0, 1));
  if (n.has("friction")) s.friction = Real(n.at("friction").number(0, 1e3));
  if (n.has("restitution_threshold"))
    s.restitutionThreshold = Real(n.at("restitution_threshold").number(0, 1e3));
  if (n.has("particle_collisions")) s.particleCollisions = n.at("particle_collisions").boolean();
  if (n.has("collide_with_bodies")) s.collideWithBodies = n.at("collide_with_bodies").boolean();
  const Real size = n.has("radius") ? Real(n.at("radius").number(0, 1e3)) : Real(0.01);
  if (n.has("emitters")) {
    Node list = n.at("emitters");
    for (std::size_t i = 0; i < list.requireArray(); ++i) d.emitters.push_back(readEmitter(list.at(i), size, bodies));
  }
  if (n.has("fields")) {
    Node list = n.at("fields");
    for (std::size_t i = 0; i < list.requireArray(); ++i) d.fields.push_back(readField(list.at(i)));
  }
  if (n.has("obstacles")) {
    Node list = n.at("obstacles");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      Transform pose;
      Shape shape = readShape(list.at(i), pose);
      d.obstacles.push_back({Collider(std::move(shape)), pose});
    }
  }
  return d;
}

}  // namespace inertia::io::detail
