#include "deformables_section.h"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "inertia/core/error.h"
#include "inertia/deformable/generators.h"
#include "particles_section.h"
#include "shape_reader.h"

namespace inertia::io::detail {

namespace {

// Keys every deformable accepts, whatever its type.
constexpr std::string_view kCommonKeys[] = {
    "name",    "type",        "mass",           "thickness",          "stiffness",
    "damping", "integrator",  "self_collision", "friction",           "pinned",
    "attach",  "tear_strain", "fields",         "collide_with_bodies"};

void requireDeformableKeys(const Node& n, std::initializer_list<std::string_view> own) {
  std::vector<std::string_view> all(std::begin(kCommonKeys), std::end(kCommonKeys));
  all.insert(all.end(), own.begin(), own.end());
  n.requireObject(all);
}

SpringStiffness readStiffness(const Node& n) {
  SpringStiffness k;
  if (!n.has("stiffness")) return k;
  Node s = n.at("stiffness");
  s.requireObject({"stretch", "shear", "bend"});
  if (s.has("stretch")) k.stretch = Real(s.at("stretch").number(0, 1e12));
  if (s.has("shear")) k.shear = Real(s.at("shear").number(0, 1e12));
  if (s.has("bend")) k.bend = Real(s.at("bend").number(0, 1e12));
  return k;
}

int readCount(const Node& n, long long hi) { return int(n.integer(1, hi)); }

MassSpringModel readRope(const Node& n, Real mass, const SpringStiffness& k, Real c) {
  requireDeformableKeys(n, {"from", "to", "segments"});
  RopeSettings s{.from = n.at("from").vec3(),
                 .to = n.at("to").vec3(),
                 .segments = 10,
                 .mass = mass,
                 .stiffness = k,
                 .damping = c};
  if (n.has("segments")) s.segments = readCount(n.at("segments"), 100000);
  return checked(n, [&] { return rope(s); });
}

// Hair on a head: strands rooted over the cap of a sphere about "position" (hair()).
MassSpringModel readHair(const Node& n, Real mass, const SpringStiffness& k, Real c) {
  requireDeformableKeys(n, {"position", "orientation", "radius", "cap_angle", "strands",
                            "segments", "length", "root_body", "root_stiffness"});
  HairSettings s{.pose = readPose(n), .mass = mass, .stiffness = k, .damping = c};
  if (n.has("radius")) s.radius = Real(n.at("radius").number(0, 1e4, true));
  if (n.has("cap_angle")) s.capAngle = Real(n.at("cap_angle").number(0, 3.14159265358979, true));
  if (n.has("strands")) s.strands = readCount(n.at("strands"), 1000000);
  if (n.has("segments")) s.segments = readCount(n.at("segments"), 10000);
  if (n.has("length")) s.length = Real(n.at("length").number(0, 1e4, true));
  return checked(n, [&] { return hair(s); });
}

MassSpringModel readCloth(const Node& n, Real mass, const SpringStiffness& k, Real c) {
  requireDeformableKeys(n, {"position", "orientation", "size", "resolution"});
  ClothSettings s{.pose = readPose(n), .mass = mass, .stiffness = k, .damping = c};
  if (n.has("size")) {
    Node size = n.at("size");
    if (size.requireArray() != 2) size.fail("expected [x, z] (m)");
    for (std::size_t i = 0; i < 2; ++i) s.size[i] = Real(size.at(i).number(0, 1e4, true));
  }
  if (n.has("resolution")) {
    Node r = n.at("resolution");
    if (r.requireArray() != 2) r.fail("expected [nx, nz] (cells)");
    for (std::size_t i = 0; i < 2; ++i) s.resolution[i] = readCount(r.at(i), 4096);
  }
  return checked(n, [&] { return cloth(s); });
}

// "shape": {"type": "box", "half_extents": [...]}, {"type": "sphere", "radius": r} or a closed
// {"type": "mesh", "obj": FILE} (or its "vertices" and "triangles", as a body's mesh shape);
// the resolution is [nx, ny, nz] cells for a box, the subdivision level for a sphere, the
// interior lattice's cells along the longest side for a mesh.
MassSpringModel readSoftBody(const Node& n, Real mass, const SpringStiffness& k, Real c) {
  requireDeformableKeys(n, {"position", "orientation", "shape", "resolution"});
  Node shape = n.at("shape");
  const std::string type = shape.at("type").string();
  const Transform pose = readPose(n);
  if (type == "box") {
    shape.requireObject({"type", "half_extents"});
    SoftBoxSettings s{.pose = pose,
                      .halfExtents = shape.at("half_extents").vec3(),
                      .mass = mass,
                      .stiffness = k,
                      .damping = c};
    if (n.has("resolution")) {
      Node r = n.at("resolution");
      if (r.requireArray() != 3) r.fail("expected [nx, ny, nz] (cells) for a box");
      for (std::size_t i = 0; i < 3; ++i) s.resolution[i] = readCount(r.at(i), 256);
    }
    return checked(n, [&] { return softBox(s); });
  }
  if (type == "sphere") {
    shape.requireObject({"type", "radius"});
    SoftSphereSettings s{.pose = pose,
                         .radius = Real(shape.at("radius").number(0, 1e4, true)),
                         .mass = mass,
                         .stiffness = k,
                         .damping = c};
    if (n.has("resolution")) s.subdivisions = int(n.at("resolution").integer(0, 5));
    return checked(n, [&] { return softSphere(s); });
  }
  if (type == "mesh") {
    Transform meshPose;
    const Shape read = readShape(shape, meshPose);
    SoftMeshSettings s{.pose = pose * meshPose,
                       .mesh = read.getIf<TriangleMesh>(),
                       .mass = mass,
                       .stiffness = k,
                       .damping = c};
    if (n.has("resolution")) s.resolution = int(n.at("resolution").integer(1, 64));
    return checked(shape, [&] { return softMesh(s); });
  }
  shape.at("type").fail("unknown soft body shape \"" + type + "\"; expected box, sphere or mesh");
}

std::uint32_t readVertex(const Node& n, std::size_t vertices) {
  return std::uint32_t(n.integer(0, (long long)vertices - 1));
}

// Explicit "vertices", "springs" ([a, b] pairs: stretch springs at rest) and "triangles".
MassSpringModel readMesh(const Node& n, Real mass, const SpringStiffness& k, Real c) {
  requireDeformableKeys(n, {"position", "orientation", "vertices", "springs", "triangles"});
  const Transform pose = readPose(n);
  MassSpringModel m;
  Node vertices = n.at("vertices");
  for (std::size_t i = 0; i < vertices.requireArray(); ++i)
    m.positions.push_back(pose.apply(vertices.at(i).vec3()));
  if (m.positions.empty()) vertices.fail("a mesh needs at least one vertex");
  m.masses.assign(m.positions.size(), mass / Real(m.positions.size()));
  if (n.has("springs")) {
    Node list = n.at("springs");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      Node s = list.at(i);
      if (s.requireArray() != 2) s.fail("expected a pair of vertex indices [a, b]");
      const std::uint32_t a = readVertex(s.at(std::size_t(0)), m.positions.size());
      const std::uint32_t b = readVertex(s.at(std::size_t(1)), m.positions.size());
      const Real rest = (m.positions[a] - m.positions[b]).norm();
      if (!(rest > 0)) s.fail("the spring's vertices coincide (rest length 0)");
      m.springs.push_back({a, b, rest, k.stretch, c, SpringKind::Stretch});
    }
  }
  if (n.has("triangles")) {
    Node list = n.at("triangles");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      Node t = list.at(i);
      if (t.requireArray() != 3) t.fail("expected three vertex indices [a, b, c]");
      m.triangles.push_back({readVertex(t.at(std::size_t(0)), m.positions.size()),
                             readVertex(t.at(std::size_t(1)), m.positions.size()),
                             readVertex(t.at(std::size_t(2)), m.positions.size())});
    }
  }
  return m;
}

void readSettings(const Node& n, DeformableSettings& s) {
  if (n.has("thickness")) s.thickness = Real(n.at("thickness").number(0, 1e3, true));
  if (n.has("friction")) s.friction = Real(n.at("friction").number(0, 1e3));
  if (n.has("tear_strain")) s.tearStrain = Real(n.at("tear_strain").number(0, 1e6));
  if (n.has("collide_with_bodies")) s.collideWithBodies = n.at("collide_with_bodies").boolean();
  if (n.has("integrator")) {
    Node i = n.at("integrator");
    const std::string name = i.string();
    auto method = name == "implicit_euler" ? std::optional(ode::Method::BackwardEuler)
                                           : ode::methodFromName(name);
    if (!method) {
      std::string names = "implicit_euler";
      for (std::string_view m : ode::kMethodNames) names += ", " + std::string(m);
      i.fail("unknown integrator \"" + name + "\"; expected one of " + names);
    }
    s.integrator = *method;
  }
  if (n.has("self_collision")) s.selfCollision = n.at("self_collision").boolean();
}

// "attach": [{"vertex", "body", "anchor" (in the body's frame), "stiffness", "damping"}].
void readAttachments(const Node& n, const std::vector<BodyDesc>& bodies, DeformableDesc& d) {
  if (!n.has("attach")) return;
  Node list = n.at("attach");
  for (std::size_t i = 0; i < list.requireArray(); ++i) {
    Node a = list.at(i);
    a.requireObject({"vertex", "body", "anchor", "stiffness", "damping"});
    Attachment at;
    at.vertex = readVertex(a.at("vertex"), d.model.vertexCount());
    const std::string name = a.at("body").string();
    if (std::none_of(bodies.begin(), bodies.end(),
                     [&](const BodyDesc& b) { return b.settings.name == name; }))
      a.at("body").fail("no body is named \"" + name + "\"");
    if (a.has("anchor")) at.anchor = a.at("anchor").vec3();
    if (a.has("stiffness")) at.stiffness = Real(a.at("stiffness").number(0, 1e12, true));
    if (a.has("damping")) at.damping = Real(a.at("damping").number(0, 1e12));
    d.attachments.push_back(at);
    d.attachmentBodies.push_back(name);
  }
}

// Hair's "root_body": the roots, pinned by hair(), are instead attached to the named body where
// they start (a head that moves carries them), by springs of "root_stiffness" (1e4 N/m).
void attachRoots(const Node& n, const std::vector<BodyDesc>& bodies, DeformableDesc& d) {
  if (!n.has("root_body")) {
    if (n.has("root_stiffness")) n.at("root_stiffness").fail("needs \"root_body\"");
    return;
  }
  const std::string name = n.at("root_body").string();
  const auto body = std::find_if(bodies.begin(), bodies.end(),
                                 [&](const BodyDesc& b) { return b.settings.name == name; });
  if (body == bodies.end()) n.at("root_body").fail("no body is named \"" + name + "\"");
  const Transform pose{body->settings.position, body->settings.orientation.normalized()};
  const Real stiffness =
      n.has("root_stiffness") ? Real(n.at("root_stiffness").number(0, 1e12, true)) : Real(1e4);
  for (const std::uint32_t root : d.model.pinned) {
    d.attachments.push_back({.vertex = root,
                             .anchor = pose.applyInverse(d.model.positions[root]),
                             .stiffness = stiffness});
    d.attachmentBodies.push_back(name);
  }
  d.model.pinned.clear();
}

}  // namespace

DeformableDesc readDeformable(const Node& n, std::size_t index,
                              const std::vector<BodyDesc>& bodies) {
  DeformableDesc d;
  const std::string type = n.at("type").string();
  d.settings.name = n.has("name") ? n.at("name").string() : std::to_string(index);
  const Real mass = n.has("mass") ? Real(n.at("mass").number(0, 1e9, true)) : Real(1);
  const Real damping = n.has("damping") ? Real(n.at("damping").number(0, 1e9)) : Real(0);
  const SpringStiffness k = readStiffness(n);
  if (type == "rope")
    d.model = readRope(n, mass, k, damping);
  else if (type == "hair")
    d.model = readHair(n, mass, k, damping);
  else if (type == "cloth")
    d.model = readCloth(n, mass, k, damping);
  else if (type == "soft_body")
    d.model = readSoftBody(n, mass, k, damping);
  else if (type == "mesh")
    d.model = readMesh(n, mass, k, damping);
  else
    n.at("type").fail("unknown deformable type \"" + type +
                      "\"; expected rope, hair, cloth, soft_body or mesh");
  readSettings(n, d.settings);
  if (type == "hair") attachRoots(n, bodies, d);
  if (n.has("pinned")) {
    Node list = n.at("pinned");
    for (std::size_t i = 0; i < list.requireArray(); ++i)
      d.model.pinned.push_back(readVertex(list.at(i), d.model.vertexCount()));
  }
  readAttachments(n, bodies, d);
  if (n.has("fields")) {
    Node list = n.at("fields");
    for (std::size_t i = 0; i < list.requireArray(); ++i) d.fields.push_back(readField(list.at(i)));
  }
  checked(n, [&] {
    validate(d.settings);
    validate(d.model);
  });
  return d;
}

}  // namespace inertia::io::detail
