#include "bodies_section.h"

#include <array>
#include <string>

#include "inertia/core/error.h"
#include "inertia/geometry/mass.h"
#include "shape_reader.h"

namespace inertia::io::detail {

namespace {

constexpr std::string_view kMaterialKeys[] = {"density",          "friction",
                                              "dynamic_friction", "restitution",
                                              "rolling_friction", "spinning_friction"};

Material readMaterialObject(const Node& n, Material m) {
  n.requireObject(kMaterialKeys);
  if (n.has("density")) m.density = Real(n.at("density").number(0, 1e9, /*openLo=*/true));
  if (n.has("friction")) m.friction = Real(n.at("friction").number(0, 1e3));
  if (n.has("dynamic_friction")) m.dynamicFriction = Real(n.at("dynamic_friction").number(0, 1e3));
  if (n.has("restitution")) m.restitution = Real(n.at("restitution").number(0, 1));
  if (n.has("rolling_friction")) m.rollingFriction = Real(n.at("rolling_friction").number(0, 1e3));
  if (n.has("spinning_friction"))
    m.spinningFriction = Real(n.at("spinning_friction").number(0, 1e3));
  return m;
}

}  // namespace

// "material": a name from "materials" or an inline object; absent gives `fallback`.
Material readMaterialRef(const Node& owner, const MaterialTable& table, const Material& fallback) {
  if (!owner.has("material")) return fallback;
  Node n = owner.at("material");
  if (n.json().is_string()) {
    const std::string name = n.string();
    auto it = table.find(name);
    if (it == table.end()) {
      std::string known;
      for (const auto& [k, v] : table) known += (known.empty() ? "" : ", ") + k;
      n.fail("unknown material \"" + name + "\"" +
             (known.empty() ? std::string("; the scene defines no materials")
                            : "; defined: " + known));
    }
    return it->second;
  }
  return readMaterialObject(n, fallback);
}

namespace {

std::optional<Vec3> readColor(const Node& owner) {
  if (!owner.has("color")) return std::nullopt;
  Node c = owner.at("color");
  const Vec3 rgb = c.vec3();
  if ((rgb.array() < 0).any() || (rgb.array() > 1).any())
    c.fail("color components must be in [0, 1]");
  return rgb;
}

// "filter": {"category": bits, "mask": bits, "group": integer}, each optional (body.h).
CollisionFilter readFilter(const Node& owner) {
  CollisionFilter f;
  if (!owner.has("filter")) return f;
  Node n = owner.at("filter");
  n.requireObject({"category", "mask", "group"});
  constexpr long long kBits = 0xFFFFFFFFll, kGroup = 0x7FFFFFFFll;
  if (n.has("category")) f.category = std::uint32_t(n.at("category").integer(0, kBits));
  if (n.has("mask")) f.mask = std::uint32_t(n.at("mask").integer(0, kBits));
  if (n.has("group")) f.group = std::int32_t(n.at("group").integer(-kGroup, kGroup));
  return f;
}

// A shape with its material; checks what a body of `type` may carry.
ShapeDesc readBodyShape(const Node& n, BodyType type, const MaterialTable& table,
                        const Material& bodyMaterial) {
  ShapeDesc d;
  d.shape = readShape(n, d.local, {"material", "color", "filter"});
  d.material = readMaterialRef(n, table, bodyMaterial);
  d.color = readColor(n);
  d.filter = readFilter(n);
  const ShapeType st = d.shape.type();
  if ((st == ShapeType::Plane || st == ShapeType::HeightField) && type != BodyType::Static)
    n.fail(std::string(st == ShapeType::Plane ? "a plane" : "a height field") +
           " can only belong to a static body");
  if (type == BodyType::Dynamic) {
    try {
      (void)massProperties(d.shape, d.material.density);
    } catch (const InvalidArgument& e) {
      n.fail(std::string("cannot be part of a dynamic body: ") + e.what());
    }
  }
  return d;
}

Vec3 readHalfExtents(const Node& n, const Vec3& fallback) {
  if (!n.has("half_extents")) return fallback;
  Node h = n.at("half_extents");
  const Vec3 v = h.vec3();
  if ((v.array() <= 0).any()) h.fail("half extents must be > 0 (m)");
  return v;
}

void readGenerator(const Node& n, const std::string& type, const MaterialTable& table,
                   std::vector<BodyDesc>& out) {
  const Material material = readMaterialRef(n, table, Material{});
  const Vec3 origin = n.has("position") ? n.at("position").vec3() : Vec3::Zero();
  std::vector<BodyDesc> made;
  try {
    if (type == "pyramid") {
      n.requireObject({"type", "name", "base", "half_extents", "position", "gap", "material"});
      PyramidSettings s;
      if (n.has("name")) s.name = n.at("name").string();
      s.base = int(n.at("base").integer(1, 1000));
      s.halfExtents = readHalfExtents(n, s.halfExtents);
      s.origin = origin;
      if (n.has("gap")) s.gap = Real(n.at("gap").number(0, 1e3));
      s.material = material;
      made = pyramid(s);
    } else if (type == "tower") {
      n.requireObject({"type", "name", "height", "half_extents", "position", "material"});
      TowerSettings s;
      if (n.has("name")) s.name = n.at("name").string();
      s.height = int(n.at("height").integer(1, 100000));
      s.halfExtents = readHalfExtents(n, s.halfExtents);
      s.origin = origin;
      s.material = material;
      made = tower(s);
    } else if (type == "wall") {
      n.requireObject(
          {"type", "name", "rows", "columns", "half_extents", "position", "staggered", "material"});
      WallSettings s;
      if (n.has("name")) s.name = n.at("name").string();
      s.rows = int(n.at("rows").integer(1, 10000));
      s.columns = int(n.at("columns").integer(1, 10000));
      s.halfExtents = readHalfExtents(n, s.halfExtents);
      s.origin = origin;
      if (n.has("staggered")) s.staggered = n.at("staggered").boolean();
      s.material = material;
      made = wall(s);
    } else if (type == "grid") {
      n.requireObject({"type", "name", "counts", "spacing", "position", "shape", "material"});
      GridSettings s;
      if (n.has("name")) s.name = n.at("name").string();
      Node counts = n.at("counts");
      if (counts.requireArray() != 3) counts.fail("expected [nx, ny, nz]");
      long long total = 1;
      for (std::size_t k = 0; k < 3; ++k) {
        s.counts[k] = int(counts.at(k).integer(1, 1000000));
        total *= s.counts[k];
      }
      if (total > 1000000) counts.fail("a grid may hold at most 1000000 bodies");
      if (n.has("spacing")) {
        Node sp = n.at("spacing");
        s.spacing =
            sp.json().is_number() ? Vec3::Constant(Real(sp.number(0, 1e6, true))) : sp.vec3();
      }
      s.origin = origin;
      Transform unused;
      s.shape = readBodyShape(n.at("shape"), BodyType::Dynamic, table, material).shape;
      s.material = material;
      made = grid(s);
    } else if (type == "rain") {
      n.requireObject({"type", "name", "count", "lower", "upper", "shape", "material", "seed"});
      RainSettings s;
      if (n.has("name")) s.name = n.at("name").string();
      s.count = int(n.at("count").integer(1, 1000000));
      s.lower = n.at("lower").vec3();
      s.upper = n.at("upper").vec3();
      if ((s.lower.array() > s.upper.array()).any())
        n.at("upper").fail("upper must be >= lower on every axis");
      s.shape = readBodyShape(n.at("shape"), BodyType::Dynamic, table, material).shape;
      if (n.has("seed")) s.seed = std::uint64_t(n.at("seed").integer(0, (1LL << 53)));
      s.material = material;
      made = rain(s);
    }
  } catch (const InvalidArgument& e) {
    n.fail(e.what());
  }
  for (BodyDesc& d : made) out.push_back(std::move(d));
}

// "ragdoll": the builder's ragdolls on a lattice in world axes, `spacing` apart, the first's
// pelvis at `position`; each NAME_i (NAME alone for one) when there are several, so that the
// "joints" section can name their parts.
void readRagdolls(const Node& n, const MaterialTable& table, Scene& scene) {
  n.requireObject({"type", "name", "position", "orientation", "count", "spacing", "scale",
                   "velocity", "joint_friction", "material", "color"});
  constexpr long long kMaxRagdolls = 10000;
  RagdollSettings s;
  s.material = readMaterialRef(n, table, Material{});
  if (n.has("position")) s.position = n.at("position").vec3();
  if (n.has("orientation")) s.orientation = n.at("orientation").quaternion();
  if (n.has("scale")) s.scale = Real(n.at("scale").number(0, 1e3, /*openLo=*/true));
  if (n.has("velocity")) s.linearVelocity = n.at("velocity").vec3();
  if (n.has("joint_friction")) s.jointFriction = Real(n.at("joint_friction").number(0, 1e6));
  const std::string name = n.has("name") ? n.at("name").string() : std::string("ragdoll");
  std::array<int, 3> counts{1, 1, 1};
  if (n.has("count")) {
    Node c = n.at("count");
    if (c.json().is_array()) {
      if (c.requireArray() != 3) c.fail("expected a count or [nx, ny, nz]");
      for (std::size_t k = 0; k < 3; ++k) counts[k] = int(c.at(k).integer(1, kMaxRagdolls));
    } else {
      counts[0] = int(c.integer(1, kMaxRagdolls));
    }
    if (static_cast<long long>(counts[0]) * counts[1] * counts[2] > kMaxRagdolls)
      c.fail("at most " + std::to_string(kMaxRagdolls) + " ragdolls");
  }
  // Default: 0.24 m between the hands of neighbours, 0.27 m from soles to head, at any scale.
  Vec3 spacing = s.scale * Vec3(Real(0.8), Real(2), Real(0.6));
  if (n.has("spacing")) {
    Node sp = n.at("spacing");
    spacing = sp.json().is_number() ? Vec3::Constant(Real(sp.number(0, 1e6, /*openLo=*/true)))
                                    : sp.vec3();
  }
  const bool several = counts[0] * counts[1] * counts[2] > 1;
  const Vec3 origin = s.position;
  Assembly all;
  try {
    for (int z = 0, i = 0; z < counts[2]; ++z)
      for (int y = 0; y < counts[1]; ++y)
        for (int x = 0; x < counts[0]; ++x, ++i) {
          s.position = origin + spacing.cwiseProduct(Vec3(Real(x), Real(y), Real(z)));
          s.name = several ? name + "_" + std::to_string(i) : name;
          append(all, ragdoll(s));
        }
  } catch (const InvalidArgument& e) {
    n.fail(e.what());
  }
  if (const std::optional<Vec3> color = readColor(n))
    for (BodyDesc& b : all.bodies)
      for (ShapeDesc& shape : b.shapes) shape.color = color;
  io::append(scene, all, n.pointer().to_string());
}

}  // namespace

MaterialTable readMaterials(const Node& n) {
  MaterialTable table;
  if (!n.json().is_object())
    n.fail("expected an object of named materials, got " + typeName(n.json()));
  for (auto it = n.json().begin(); it != n.json().end(); ++it) {
    Material m = readMaterialObject(n.at(it.key()), Material{});
    table.emplace(it.key(), m);
  }
  return table;
}

void readBodies(const Node& n, std::size_t index, const MaterialTable& table, Scene& scene) {
  const std::string type = n.has("type") ? n.at("type").string() : std::string("dynamic");
  if (type == "pyramid" || type == "tower" || type == "wall" || type == "grid" || type == "rain") {
    readGenerator(n, type, table, scene.bodies);
    return;
  }
  if (type == "ragdoll") {
    readRagdolls(n, table, scene);
    return;
  }
  n.requireObject({"name", "type", "position", "orientation", "velocity", "angular_velocity",
                   "shapes", "mass", "inertia", "linear_damping", "angular_damping",
                   "gravity_scale", "bullet", "allow_sleep", "material"});
  BodyDesc d;
  BodySettings& s = d.settings;
  if (!bodyTypeFromName(type, s.type))
    n.at("type").fail("unknown body type \"" + type +
                      "\"; expected static, kinematic, dynamic, or a generator: pyramid, tower, "
                      "wall, grid, rain, ragdoll");
  s.name = n.has("name") ? n.at("name").string() : std::to_string(index);
  if (n.has("position")) s.position = n.at("position").vec3();
  if (n.has("orientation")) s.orientation = n.at("orientation").quaternion();
  if (n.has("velocity")) s.linearVelocity = n.at("velocity").vec3();
  if (n.has("angular_velocity")) s.angularVelocity = n.at("angular_velocity").vec3();
  if (n.has("mass")) s.mass = Real(n.at("mass").number(0, 1e12, /*openLo=*/true));
  if (n.has("inertia")) {
    if (!n.has("mass")) n.at("inertia").fail("\"inertia\" needs \"mass\"");
    s.inertia = n.at("inertia").vec3();
  }
  if (n.has("linear_damping")) s.linearDamping = Real(n.at("linear_damping").number(0, 1e6));
  if (n.has("angular_damping")) s.angularDamping = Real(n.at("angular_damping").number(0, 1e6));
  if (n.has("gravity_scale")) s.gravityScale = Real(n.at("gravity_scale").number(-1e6, 1e6));
  if (n.has("bullet")) s.bullet = n.at("bullet").boolean();
  if (n.has("allow_sleep")) s.allowSleep = n.at("allow_sleep").boolean();
  checked(n, [&] { validate(s); });
  const Material bodyMaterial = readMaterialRef(n, table, Material{});
  if (n.has("shapes")) {
    Node list = n.at("shapes");
    for (std::size_t i = 0; i < list.requireArray(); ++i)
      d.shapes.push_back(readBodyShape(list.at(i), s.type, table, bodyMaterial));
  }
  scene.bodies.push_back(std::move(d));
}

}  // namespace inertia::io::detail
