// URDF robots (through liburdfdom): a URDF file as the settings of a World articulation, the
// same model and link shapes as the scene file's inline "articulations" links (DESIGN.md
// section 4).
//
// How URDF maps onto the model (articulation/model.h):
//  - links in depth-first order from the root (children in urdfdom's order, by joint name);
//  - <inertial>: mass, centre of mass at its origin, and the full inertia tensor turned from the
//    inertial frame (its rpy) into the link's axes, R I R^T; a link without one is massless;
//  - <joint> origin: the joint frame in the parent link's frame, the child link's frame being
//    the joint frame moved by the joint (URDF's convention and the model's); revolute (with
//    limits), continuous (revolute without), prismatic, fixed; a floating joint only from a
//    massless root without collision shapes (the "world" link pattern), which it replaces as a
//    floating base; planar joints and mimic joints are refused;
//  - <limit> velocity: the velocity limit (0: none); effort: kept per joint, the maxForce of a
//    drive given to the joint later (0: none); <dynamics> damping and friction;
//  - <collision>: box, sphere, cylinder (URDF's along z, the Cylinder shape's along y, so turned),
//    and meshes as the convex hull of their vertices (as MuJoCo does for collision meshes):
//    Wavefront OBJ through io/obj.h, other formats (STL, COLLADA, ...) through Assimp; scaled by
//    <mesh scale>. Relative mesh paths and file:// URIs resolve against the URDF file's
//    directory; package:// URIs are refused (there is no ROS package path to search).
//  - <visual>, <gazebo>, <transmission> and the like are ignored.
#pragma once

#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "inertia/world/world.h"

namespace inertia::io {

/// A problem with a URDF file. what() reads "FILE: REASON"; the reason names the link or the
/// joint, or carries what urdfdom reported.
class UrdfError : public std::runtime_error {
 public:
  UrdfError(std::string file, std::string reason);
  const std::string& file() const { return file_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, reason_;
};

struct UrdfOptions {
  /// The root link on a floating joint (six degrees of freedom), else fixed to the base.
  bool floatingBase = false;
  /// The material of every collision shape (its density is not used: URDF gives the masses).
  Material material{};
};

/// A URDF joint kept in the model: the link it moves and its limits that are not the model's.
struct UrdfJoint {
  std::string name;
  int link = -1;  ///< The model's link it attaches to its parent.
  /// <limit effort> (N m or N): the maxForce of a drive given to the joint; infinite for none.
  Real effort = std::numeric_limits<Real>::infinity();
};

/// A robot read from URDF.
struct UrdfRobot {
  std::string name;                       ///< The <robot> name.
  articulation::Model<Real> model;        ///< Links named as in the file.
  std::vector<LinkShapeSettings> shapes;  ///< The collision shapes.
  std::vector<UrdfJoint> joints;          ///< Every joint of the file, in link order.
  /// True when the root link is on a floating joint (options.floatingBase, or a URDF floating
  /// joint from a "world" link).
  bool floatingBase = false;

  /// The joint named `name`, or nullptr.
  const UrdfJoint* findJoint(const std::string& name) const;
};

/// Reads a URDF file. Throws UrdfError for a missing or unreadable file, what urdfdom rejects
/// (bad XML, a missing link, several roots, a link with two parents, ...), an unsupported joint,
/// a collision mesh that cannot be read, or a model that addLink refuses (negative mass, an
/// inertia that is not positive definite, ...) or whose moving joint moves no mass.
UrdfRobot loadUrdf(const std::filesystem::path& file, const UrdfOptions& options = {});

/// Reads URDF text; `name` is used in messages, and relative mesh paths resolve against its
/// directory.
UrdfRobot parseUrdf(const std::string& xml, const std::filesystem::path& name,
                    const UrdfOptions& options = {});

}  // namespace inertia::io
