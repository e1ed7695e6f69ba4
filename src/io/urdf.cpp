#include "inertia/io/urdf.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <mutex>
#include <numbers>
#include <sstream>

#include "inertia/core/error.h"
#include "mesh_file.h"

namespace inertia::io {

UrdfError::UrdfError(std::string file, std::string reason)
    : std::runtime_error(file + ": " + reason),
      file_(std::move(file)),
      reason_(std::move(reason)) {}

const UrdfJoint* UrdfRobot::findJoint(const std::string& name) const {
  for (const UrdfJoint& j : joints)
    if (j.name == name) return &j;
  return nullptr;
}

namespace {

namespace art = inertia::articulation;

// urdfdom reports through console_bridge and returns null: collect what it says at error level
// (the handler is global, hence the lock) instead of letting it print.
class CollectErrors : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR)
      errors += (errors.empty() ? "" : "; ") + text;
  }
  std::string errors;
};

urdf::ModelInterfaceSharedPtr parseWithUrdfdom(const std::string& xml, const std::string& file) {
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  CollectErrors handler;
  console_bridge::OutputHandler* previous = console_bridge::getOutputHandler();
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    handler.errors += (handler.errors.empty() ? "" : "; ") + std::string(e.what());
  }
  console_bridge::useOutputHandler(previous);
  if (!model)
    throw UrdfError(file, "urdfdom cannot parse it: " +
                              (handler.errors.empty() ? "(no reason given)" : handler.errors));
  return model;
}

Vec3 vec(const urdf::Vector3& v) { return Vec3(Real(v.x), Real(v.y), Real(v.z)); }

Transform pose(const urdf::Pose& p) {
  Transform t;
  t.p = vec(p.position);
  t.q = Quat(Real(p.rotation.w), Real(p.rotation.x), Real(p.rotation.y), Real(p.rotation.z))
            .normalized();
  return t;
}

// <inertial>: the tensor given in the inertial frame (origin rpy), turned into the link's axes.
art::LinkInertia<Real> linkInertia(const urdf::Link& link) {
  art::LinkInertia<Real> in;
  if (!link.inertial) {
    in.mass = 0;
    in.inertia.setZero();
    return in;
  }
  const urdf::Inertial& u = *link.inertial;
  const Transform frame = pose(u.origin);
  Mat3 I;
  I << Real(u.ixx), Real(u.ixy), Real(u.ixz), Real(u.ixy), Real(u.iyy), Real(u.iyz), Real(u.ixz),
      Real(u.iyz), Real(u.izz);
  const Mat3 R = frame.q.toRotationMatrix();
  in.mass = Real(u.mass);
  in.centerOfMass = frame.p;
  in.inertia = R * I * R.transpose();
  return in;
}

struct Reader {
  std::string file;
  std::filesystem::path directory;  // of the URDF file: relative mesh paths start here
  UrdfOptions options;
  UrdfRobot robot;

  [[noreturn]] void fail(const std::string& reason) const { throw UrdfError(file, reason); }

  art::JointSettings<Real> jointSettings(const urdf::Joint& j) const;
  std::filesystem::path meshPath(const std::string& filename, const std::string& link) const;
  Shape collisionShape(const urdf::Geometry& g, const std::string& link, Transform& pose) const;
  Real size(double value, const std::string& link, const char* what) const;
  void addLink(const urdf::Link& link, int parent, const urdf::Joint* joint, bool floatingRoot);
};

art::JointSettings<Real> Reader::jointSettings(const urdf::Joint& j) const {
  const std::string where = "joint '" + j.name + "'";
  if (j.mimic) fail(where + ": mimic joints are not supported");
  art::JointSettings<Real> s;
  switch (j.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      s.type = art::JointType::Revolute;
      break;
    case urdf::Joint::PRISMATIC:
      s.type = art::JointType::Prismatic;
      break;
    case urdf::Joint::FIXED:
      s.type = art::JointType::Fixed;
      break;
    case urdf::Joint::PLANAR:
      fail(where +
           " is planar: planar joints are not supported (compose two prismatic joints "
           "and a revolute one through massless links)");
    case urdf::Joint::FLOATING:
      fail(where +
           " is floating: a floating joint is supported only from a root link without "
           "inertial and collision (a \"world\" link), as the robot's floating base");
    default:
      fail(where + " has an unknown type");
  }
  const Transform origin = pose(j.parent_to_joint_origin_transform);
  s.originPosition = origin.p;
  s.originOrientation = origin.q;
  const bool scalar = s.type != art::JointType::Fixed;
  if (!scalar) return s;
  s.axis = vec(j.axis);
  if (j.limits) {
    if (j.type != urdf::Joint::CONTINUOUS) {
      s.lower = Real(j.limits->lower);
      s.upper = Real(j.limits->upper);
    }
    if (j.limits->velocity > 0) s.velocityLimit = Real(j.limits->velocity);
  }
  if (j.dynamics) {
    s.damping = Real(j.dynamics->damping);
    s.friction = Real(j.dynamics->friction);
  }
  return s;
}

std::filesystem::path Reader::meshPath(const std::string& filename, const std::string& link) const {
  const std::string where = "link '" + link + "': collision mesh \"" + filename + "\"";
  if (filename.rfind("package://", 0) == 0)
    fail(where +
         ": package:// URIs are not resolved (there is no ROS package path); give a "
         "path relative to the URDF file");
  std::string path = filename;
  if (path.rfind("file://", 0) == 0) path = path.substr(7);
  if (path.empty()) fail(where + ": empty file name");
  const std::filesystem::path p(path);
  return p.is_absolute() ? p : directory / p;
}

Real Reader::size(double value, const std::string& link, const char* what) const {
  if (!(std::isfinite(value) && value > 0))
    fail("link '" + link + "': the collision " + what + " must be finite and > 0");
  return Real(value);
}

Shape Reader::collisionShape(const urdf::Geometry& g, const std::string& link,
                             Transform& pose) const {
  switch (g.type) {
    case urdf::Geometry::SPHERE:
      return Sphere{size(static_cast<const urdf::Sphere&>(g).radius, link, "sphere's radius")};
    case urdf::Geometry::BOX: {
      const urdf::Vector3& d = static_cast<const urdf::Box&>(g).dim;
      return Box{Real(0.5) * Vec3(size(d.x, link, "box's size"), size(d.y, link, "box's size"),
                                  size(d.z, link, "box's size"))};
    }
    case urdf::Geometry::CYLINDER: {
      // URDF's cylinder is along z, ours along y: turn y onto z (+90 degrees about x).
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      pose.q = (pose.q * Quat(Eigen::AngleAxis<Real>(std::numbers::pi_v<Real> / 2, Vec3::UnitX())))
                   .normalized();
      return Cylinder{size(c.radius, link, "cylinder's radius"),
                      Real(0.5) * size(c.length, link, "cylinder's length")};
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      const std::filesystem::path path = meshPath(m.filename, link);
      std::vector<Vec3> points;
      try {
        points = detail::loadMeshVertices(path);
      } catch (const std::runtime_error& e) {
        fail("link '" + link + "': collision mesh: " + e.what());
      }
      const Vec3 scale = vec(m.scale);
      for (Vec3& p : points) p = p.cwiseProduct(scale);
      try {
        return ConvexHull(points);
      } catch (const InvalidArgument& e) {
        fail("link '" + link + "': collision mesh " + path.string() + ": " + e.what());
      }
    }
  }
  fail("link '" + link + "': unknown collision geometry");
}

// Adds `link` (attached by `joint`, null for the root) and its subtree, parents first.
void Reader::addLink(const urdf::Link& link, int parent, const urdf::Joint* joint,
                     bool floatingRoot) {
  art::LinkSettings<Real> s;
  s.name = link.name;
  s.parent = parent;
  if (joint)
    s.joint = jointSettings(*joint);
  else
    s.joint.type = floatingRoot ? art::JointType::Floating : art::JointType::Fixed;
  s.inertia = linkInertia(link);
  int index = -1;
  try {
    index = robot.model.addLink(s);
  } catch (const InvalidArgument& e) {
    fail("link '" + link.name + "'" + (joint ? " (joint '" + joint->name + "')" : "") + ": " +
         e.what());
  }
  if (joint) {
    UrdfJoint& j = robot.joints.emplace_back();
    j.name = joint->name;
    j.link = index;
    if (joint->limits && joint->limits->effort > 0) j.effort = Real(joint->limits->effort);
  }
  for (const urdf::CollisionSharedPtr& c : link.collision_array) {
    if (!c || !c->geometry) continue;
    LinkShapeSettings shape;
    shape.link = index;
    shape.pose = pose(c->origin);
    try {
      shape.shape = collisionShape(*c->geometry, link.name, shape.pose);
    } catch (const InvalidArgument& e) {
      fail("link '" + link.name + "': collision geometry: " + e.what());
    }
    shape.material = options.material;
    robot.shapes.push_back(shape);
  }
  for (const urdf::JointSharedPtr& child : link.child_joints) {
    urdf::LinkConstSharedPtr childLink;
    for (const urdf::LinkSharedPtr& l : link.child_links)
      if (l->name == child->child_link_name) childLink = l;
    addLink(*childLink, index, child.get(), false);
  }
}

// The "world" link pattern: a root without inertial or collision whose only joint is floating.
const urdf::Joint* floatingFromWorld(const urdf::Link& root) {
  if (root.inertial || !root.collision_array.empty() || root.child_joints.size() != 1)
    return nullptr;
  const urdf::Joint& j = *root.child_joints.front();
  return j.type == urdf::Joint::FLOATING ? &j : nullptr;
}

}  // namespace

UrdfRobot parseUrdf(const std::string& xml, const std::filesystem::path& name,
                    const UrdfOptions& options) {
  Reader r{name.string(), name.parent_path(), options, {}};
  const urdf::ModelInterfaceSharedPtr model = parseWithUrdfdom(xml, r.file);
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) r.fail("no root link");
  r.robot.name = model->getName();
  if (const urdf::Joint* f = floatingFromWorld(*root)) {
    if (f->mimic) r.fail("joint '" + f->name + "': mimic joints are not supported");
    const urdf::Pose& o = f->parent_to_joint_origin_transform;
    double x, y, z, w;
    o.rotation.getQuaternion(x, y, z, w);
    if (o.position.x != 0 || o.position.y != 0 || o.position.z != 0 || x != 0 || y != 0 || z != 0)
      r.fail("joint '" + f->name +
             "': a floating base's origin must be the identity (the base is placed by the "
             "scene's position and orientation)");
    const urdf::LinkConstSharedPtr base = model->getLink(f->child_link_name);
    r.robot.floatingBase = true;
    r.addLink(*base, -1, nullptr, true);
  } else {
    r.robot.floatingBase = options.floatingBase;
    r.addLink(*root, -1, nullptr, options.floatingBase);
  }
  if (const int i = art::firstLinkMovingNoMass(r.robot.model); i >= 0)
    r.fail("link '" + r.robot.model.link(i).name +
           "': its joint moves no mass (the link and every link below it have no <inertial>)");
  return std::move(r.robot);
}

UrdfRobot loadUrdf(const std::filesystem::path& file, const UrdfOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw UrdfError(file.string(), "no such file");
  if (std::filesystem::is_directory(file, ec))
    throw UrdfError(file.string(), "is a directory, not a URDF file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UrdfError(file.string(), "cannot be opened for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return parseUrdf(text.str(), file, options);
}

}  // namespace inertia::io
