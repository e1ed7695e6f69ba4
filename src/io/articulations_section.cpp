#include "articulations_section.h"

#include <map>
#include <optional>
#include <string>

#include "inertia/core/error.h"
#include "inertia/io/urdf.h"
#include "shape_reader.h"

namespace inertia::io::detail {

namespace {

namespace art = inertia::articulation;

art::JointType jointType(const Node& n) {
  const std::string t = n.string();
  if (t == "revolute") return art::JointType::Revolute;
  if (t == "prismatic") return art::JointType::Prismatic;
  if (t == "spherical") return art::JointType::Spherical;
  if (t == "fixed") return art::JointType::Fixed;
  n.fail("unknown joint type \"" + t + "\" (revolute, prismatic, spherical, fixed)");
}

art::Drive<Real> readDrive(const Node& n) {
  n.requireObject({"stiffness", "damping", "target", "target_velocity", "max_force"});
  art::Drive<Real> d;
  if (n.has("stiffness")) d.stiffness = Real(n.at("stiffness").number(0, 1e12));
  if (n.has("damping")) d.damping = Real(n.at("damping").number(0, 1e12));
  if (n.has("target")) d.targetPosition = Real(n.at("target").number());
  if (n.has("target_velocity")) d.targetVelocity = Real(n.at("target_velocity").number());
  if (n.has("max_force")) d.maxForce = Real(n.at("max_force").number(0, 1e30, true));
  return d;
}

// A link's joint; its own "q" and "qd" go to `q` and `qd` (by link name).
art::JointSettings<Real> readJoint(const Node& n) {
  n.requireObject({"type", "axis", "origin", "limits", "damping", "friction", "armature",
                   "velocity_limit", "drive", "q", "qd"});
  art::JointSettings<Real> j;
  j.type = jointType(n.at("type"));
  if (n.has("axis")) {
    Node a = n.at("axis");
    j.axis = a.vec3();
    if (j.axis.norm() < Real(1e-6)) a.fail("the axis must not be zero");
  }
  if (n.has("origin")) {
    Node o = n.at("origin");
    o.requireObject({"position", "orientation"});
    const Transform t = readPose(o);
    j.originPosition = t.p;
    j.originOrientation = t.q;
  }
  if (n.has("limits")) {
    Node l = n.at("limits");
    if (l.requireArray() != 2) l.fail("limits are [lower, upper]");
    j.lower = Real(l.at(0).number());
    j.upper = Real(l.at(1).number());
    if (j.lower > j.upper) l.fail("the lower limit is above the upper");
  }
  if (n.has("damping")) j.damping = Real(n.at("damping").number(0, 1e12));
  if (n.has("friction")) j.friction = Real(n.at("friction").number(0, 1e12));
  if (n.has("armature")) j.armature = Real(n.at("armature").number(0, 1e12));
  if (n.has("velocity_limit")) j.velocityLimit = Real(n.at("velocity_limit").number(0, 1e30, true));
  if (n.has("drive")) j.drive = readDrive(n.at("drive"));
  return j;
}

// A coordinate value: a number for a one-dof joint, an array for a spherical one.
void readCoordinates(const Node& n, art::VectorX<Real>& out, int index, int count) {
  if (count == 0) n.fail("the joint has no coordinates");
  if (count == 1) {
    out(index) = Real(n.number());
    return;
  }
  if (n.requireArray() != std::size_t(count))
    n.fail("expected " + std::to_string(count) + " numbers");
  for (int k = 0; k < count; ++k) out(index + k) = Real(n.at(std::size_t(k)).number());
}

struct LinkEntry {
  Node node;
  std::string name;
};

// One link: its settings into the model and its shapes; fails at the link on a refused one.
void readLink(const Node& n, const MaterialTable& materials, bool floatingRoot,
              WorldArticulationSettings& s) {
  n.requireObject({"name", "parent", "joint", "mass", "com", "inertia", "shapes"});
  art::LinkSettings<Real> link;
  link.name = n.at("name").string();
  if (s.model.findLink(link.name) >= 0)
    n.at("name").fail("duplicate link name \"" + link.name + "\"");
  if (n.has("parent") && !n.at("parent").json().is_null()) {
    Node p = n.at("parent");
    link.parent = s.model.findLink(p.string());
    if (link.parent < 0)
      p.fail("no earlier link named \"" + p.string() + "\" (parents come before their children)");
  }
  const bool root = link.parent < 0;
  if (root && floatingRoot) {
    if (n.has("joint")) n.at("joint").fail("the floating base's root link has no joint");
    link.joint.type = art::JointType::Floating;
  } else {
    link.joint = readJoint(n.at("joint"));
  }
  const int index = s.model.linkCount();
  // Shapes: with the link's material; they also give the mass properties when none are given.
  std::vector<art::LinkShape> massShapes;
  if (n.has("shapes")) {
    Node list = n.at("shapes");
    for (std::size_t k = 0; k < list.requireArray(); ++k) {
      Node sh = list.at(k);
      LinkShapeSettings shape;
      shape.link = index;
      shape.shape = readShape(sh, shape.pose, {"material", "color"});
      shape.material = readMaterialRef(sh, materials, Material{});
      const ShapeType t = shape.shape.type();
      if (t == ShapeType::Plane || t == ShapeType::HeightField)
        sh.fail("planes and height fields cannot be parts of a link");
      massShapes.push_back({shape.shape, shape.pose, shape.material.density});
      s.shapes.push_back(shape);
    }
  }
  if (n.has("mass")) {
    link.inertia.mass = Real(n.at("mass").number(0, 1e12, true));
    if (n.has("com")) link.inertia.centerOfMass = n.at("com").vec3();
    if (n.has("inertia")) {
      Node in = n.at("inertia");
      const Vec3 d = in.vec3();
      if ((d.array() <= 0).any()) in.fail("principal moments must be > 0 (kg m^2)");
      link.inertia.inertia = d.asDiagonal();
    } else {
      // A small ball's inertia about the centre of mass: 2/5 m (0.05 m)^2.
      link.inertia.inertia = Mat3::Identity() * Real(0.4 * 0.0025) * link.inertia.mass;
    }
  } else {
    for (const char* key : {"com", "inertia"})
      if (n.has(key)) n.at(key).fail("only with \"mass\"");
    if (massShapes.empty()) n.fail("a link needs \"mass\" or shapes to take it from");
    link.inertia =
        checked(n.at("shapes"), [&] { return art::inertiaFromShapes<Real>(massShapes); });
  }
  checked(n, [&] { s.model.addLink(link); });
}

// "q", "qd" or "drives" keyed by name: `find` gives the link a name stands for (-1 for none).
template <class Find, class F>
void forEachNamed(const Node& n, const char* kind, Find find, F f) {
  if (!n.json().is_object())
    n.fail(std::string("expected an object of ") + kind + " name -> value");
  for (const auto& [key, value] : n.json().items()) {
    Node v = n.at(key);
    const int link = find(key);
    if (link < 0) v.fail(std::string("no ") + kind + " named \"" + key + "\"");
    f(link, v);
  }
}

// Inline links; their joints' own "q" and "qd" are read after the section's pose.
void readLinks(const Node& links, const MaterialTable& materials, bool floating,
               WorldArticulationSettings& s) {
  if (links.requireArray() == 0) links.fail("an articulation needs at least one link");
  for (std::size_t i = 0; i < links.requireArray(); ++i) {
    Node l = links.at(i);
    const bool floatingRoot = floating && s.model.linkCount() == 0;
    if (floating && i > 0 && l.has("parent") && l.at("parent").json().is_null())
      l.at("parent").fail("a floating base has one root link, the first");
    readLink(l, materials, floatingRoot, s);
  }
}

// A URDF robot (io/urdf.h), its path relative to the scene file's directory.
UrdfRobot readUrdf(const Node& n, bool floating) {
  Node u = n.at("urdf");
  try {
    return loadUrdf(u.path("URDF"), {.floatingBase = floating});
  } catch (const UrdfError& e) {
    u.fail(e.what());
  }
}

}  // namespace

ArticulationDesc readArticulation(const Node& n, std::size_t index,
                                  const MaterialTable& materials) {
  n.requireObject({"name", "urdf", "base", "position", "orientation", "q", "qd", "drives", "links",
                   "self_collision"});
  ArticulationDesc d;
  d.pointer = n.pointer().to_string();
  WorldArticulationSettings& s = d.settings;
  s.name = n.has("name") ? n.at("name").string() : "articulation" + std::to_string(index);
  if (n.has("self_collision")) s.selfCollision = n.at("self_collision").boolean();
  bool floating = false;
  if (n.has("base")) {
    Node b = n.at("base");
    const std::string base = b.string();
    if (base != "fixed" && base != "floating") b.fail("base is \"fixed\" or \"floating\"");
    floating = base == "floating";
  }
  const Transform pose = readPose(n);
  // Names in "q", "qd" and "drives": the links' for inline links, the joints' for URDF.
  std::optional<UrdfRobot> robot;
  if (n.has("urdf")) {
    if (n.has("links")) n.at("links").fail("an articulation takes \"urdf\" or \"links\", not both");
    robot = readUrdf(n, floating);
    if (robot->floatingBase && !floating && n.has("base"))
      n.at("base").fail("the URDF's root is on a floating joint: the base is \"floating\"");
    floating = robot->floatingBase;
    s.model = std::move(robot->model);
    s.shapes = std::move(robot->shapes);
  } else {
    readLinks(n.at("links"), materials, floating, s);
  }
  // Initial state: the neutral configuration, the floating base at the pose, then each joint's
  // own "q"/"qd" and the section's.
  s.q = s.model.neutralConfiguration();
  s.qd = art::VectorX<Real>::Zero(s.model.nv());
  if (floating) {
    s.q.head<3>() = pose.p;
    s.q.segment<4>(3) << pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z();
  } else {
    s.base = pose;
  }
  if (!robot) {
    Node links = n.at("links");
    for (std::size_t i = 0; i < links.requireArray(); ++i) {
      Node l = links.at(i);
      if (!l.has("joint")) continue;
      const art::Link<Real>& link = s.model.link(int(i));
      Node j = l.at("joint");
      if (j.has("q")) readCoordinates(j.at("q"), s.q, link.qIndex, link.nq);
      if (j.has("qd")) readCoordinates(j.at("qd"), s.qd, link.vIndex, link.nv);
    }
  }
  const char* kind = robot ? "joint" : "link";
  auto find = [&](const std::string& name) {
    if (!robot) return s.model.findLink(name);
    const UrdfJoint* j = robot->findJoint(name);
    return j ? j->link : -1;
  };
  if (n.has("q"))
    forEachNamed(n.at("q"), kind, find, [&](int i, const Node& v) {
      readCoordinates(v, s.q, s.model.link(i).qIndex, s.model.link(i).nq);
    });
  if (n.has("qd"))
    forEachNamed(n.at("qd"), kind, find, [&](int i, const Node& v) {
      readCoordinates(v, s.qd, s.model.link(i).vIndex, s.model.link(i).nv);
    });
  if (n.has("drives"))
    forEachNamed(n.at("drives"), kind, find, [&](int i, const Node& v) {
      if (s.model.link(i).nv != 1) v.fail("drives are for revolute and prismatic joints");
      art::Drive<Real> drive = readDrive(v);
      // A URDF joint's effort limit bounds its drive unless the drive says otherwise.
      if (robot && !v.has("max_force"))
        for (const UrdfJoint& j : robot->joints)
          if (j.link == i) drive.maxForce = j.effort;
      checked(v, [&] { s.model.setDrive(s.model.link(i).vIndex, drive); });
    });
  return d;
}

}  // namespace inertia::io::detail
