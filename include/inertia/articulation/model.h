// The model of an articulated body in reduced coordinates: a tree of links, each attached to its
// parent (or to the base) by one joint. Plain data read by the algorithms of dynamics.h.
//
// Conventions (Featherstone 2008, chapter 4): links are numbered so that a parent comes before
// its children (lambda(i) < i). A joint's origin places its joint frame in the parent link's
// frame (in the base frame, the world, for a root link), as URDF does; the link's frame is the
// joint frame moved by the joint. Velocities are in each link's own coordinates, so every motion
// subspace S is constant and the joints' bias accelerations c_J vanish.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <vector>

#include "inertia/articulation/spatial.h"
#include "inertia/core/types.h"
#include "inertia/geometry/shapes.h"

namespace inertia::articulation {

/// A joint's type and its coordinates: q (position) and v (velocity) counts.
/// - Revolute: 1 + 1, the angle (rad) about `axis`.
/// - Prismatic: 1 + 1, the displacement (m) along `axis`.
/// - Spherical: 4 + 3, the unit quaternion [w, x, y, z] of the link in its joint frame, and the
///   angular velocity in the link's axes (rad/s).
/// - Fixed: 0 + 0.
/// - Floating: 7 + 6, the six-DOF joint of a floating base, on root links only: the position (m)
///   and unit quaternion [w, x, y, z] of the link in the base frame, and the link's spatial
///   velocity in its own axes [w; v] (v the velocity of the link's origin).
enum class JointType { Revolute, Prismatic, Spherical, Fixed, Floating };

/// Configuration and velocity sizes of a joint type.
int configurationSize(JointType type);
int velocitySize(JointType type);

/// A PD drive of a revolute or prismatic joint: the generalised force
/// clamp(stiffness (targetPosition - q) + damping (targetVelocity - qd), -maxForce, maxForce).
template <class S>
struct Drive {
  S stiffness = S(0);                               ///< (N m/rad or N/m)
  S damping = S(0);                                 ///< (N m s/rad or N s/m)
  S targetPosition = S(0);                          ///< (rad or m)
  S targetVelocity = S(0);                          ///< (rad/s or m/s)
  S maxForce = std::numeric_limits<S>::infinity();  ///< (N m or N), > 0
};

template <class S>
struct JointSettings {
  JointType type = JointType::Revolute;
  /// The joint frame in the parent link's frame (the base's for a root link).
  Vector3<S> originPosition = Vector3<S>::Zero();  ///< (m)
  Quaternion<S> originOrientation = Quaternion<S>::Identity();
  /// Revolute and prismatic: the axis in the joint frame (normalised when added).
  Vector3<S> axis = Vector3<S>::UnitZ();
  /// Revolute and prismatic: position limits (rad or m), lower <= upper; infinite for none.
  S lower = -std::numeric_limits<S>::infinity();
  S upper = std::numeric_limits<S>::infinity();
  /// Per degree of freedom: viscous damping (N m s/rad or N s/m), Coulomb friction (N m or N),
  /// armature, the rotor inertia added to the diagonal of the mass matrix (kg m^2 or kg), and
  /// the velocity limit (rad/s or m/s, |qd| <= it). Not for floating joints.
  S damping = S(0);
  S friction = S(0);
  S armature = S(0);
  S velocityLimit = std::numeric_limits<S>::infinity();
  /// Revolute and prismatic only.
  Drive<S> drive{};
};

/// Mass properties of a link in its own frame. A massless link (mass 0 and inertia zero, as
/// URDF's links without an inertial) is a frame for shapes and children: the joints that move
/// it must move some mass too (firstLinkMovingNoMass).
template <class S>
struct LinkInertia {
  S mass = S(1);                                 ///< (kg), > 0, or 0 for a massless link
  Vector3<S> centerOfMass = Vector3<S>::Zero();  ///< (m)
  /// About the centre of mass, in the link's axes (kg m^2): the full symmetric tensor, SPD
  /// (zero for a massless link).
  Matrix3<S> inertia = Matrix3<S>::Identity();
};

/// A shape of a link, at `pose` in the link's frame, of uniform `density` (kg/m^3).
struct LinkShape {
  Shape shape;
  Transform pose{};
  Real density = 1000;
};

/// The links' mass properties from their shapes (the geometry layer's massProperties, moved by
/// each pose and combined). Throws InvalidArgument for no shapes or shapes without volume.
template <class S>
LinkInertia<S> inertiaFromShapes(std::span<const LinkShape> shapes);

template <class S>
struct LinkSettings {
  std::string name;
  int parent = -1;  ///< Index of the parent link, -1 for the base.
  JointSettings<S> joint{};
  LinkInertia<S> inertia{};
};

/// One link and its joint, as the algorithms read them.
template <class S>
struct Link {
  std::string name;
  int parent = -1;
  JointType joint = JointType::Fixed;
  PluckerTransform<S> Xtree;  ///< From the parent's frame to the joint frame (X_T).
  Vector3<S> axis = Vector3<S>::UnitZ();
  int qIndex = 0, vIndex = 0;  ///< First coordinate in q and in v.
  int nq = 0, nv = 0;
  S mass = S(0);
  Vector3<S> centerOfMass = Vector3<S>::Zero();  ///< In the link's frame (m).
  Matrix6<S> I;                                  ///< Spatial inertia about the link's origin.
};

/// A tree of links. Build it with addLink, parents first.
template <class S>
class Model {
 public:
  /// Adds a link and returns its index. Throws InvalidArgument naming the link and the field for
  /// a parent that does not exist yet, a floating joint below another link, a negative or
  /// non-finite mass, an inertia that is not symmetric positive definite or breaks the triangle
  /// inequality (not zero, for a massless link), a zero axis, limits with lower > upper, negative
  /// damping, friction, armature or velocity limit, or a drive (or limits) on a joint that is not
  /// revolute or prismatic.
  int addLink(const LinkSettings<S>& settings);

  int linkCount() const { return static_cast<int>(links_.size()); }
  int nq() const { return nq_; }  ///< Size of q.
  int nv() const { return nv_; }  ///< Size of qd (degrees of freedom).
  const Link<S>& link(int i) const { return links_[i]; }
  const std::vector<Link<S>>& links() const { return links_; }
  /// Index of the link named `name`, or -1.
  int findLink(const std::string& name) const;

  /// Motion subspaces of every joint, one column per degree of freedom, in the link's frame:
  /// columns vIndex .. vIndex + nv - 1 are link i's S_i (constant for these joint types).
  const Matrix6X<S>& motionSubspace() const { return S_; }

  /// Per degree of freedom (size nv).
  const VectorX<S>& armature() const { return armature_; }
  const VectorX<S>& damping() const { return damping_; }
  const VectorX<S>& friction() const { return friction_; }
  const VectorX<S>& velocityLimit() const { return velocityLimit_; }
  const VectorX<S>& lower() const { return lower_; }  ///< -inf where none.
  const VectorX<S>& upper() const { return upper_; }  ///< +inf where none.
  const std::vector<Drive<S>>& drives() const { return drives_; }
  /// Replaces the drive of degree of freedom `dof` (InvalidArgument for a bad dof, a joint that
  /// is not revolute or prismatic, or bad gains as addLink checks them).
  void setDrive(int dof, const Drive<S>& drive);
  /// True when the degree of freedom has a drive (stiffness or damping > 0).
  bool hasDrive(int dof) const { return drives_[dof].stiffness > 0 || drives_[dof].damping > 0; }
  /// Per degree of freedom: the index in q of its coordinate for revolute and prismatic joints
  /// (where q and qd match one to one), -1 for spherical and floating joints.
  const std::vector<int>& scalarQIndex() const { return scalarQ_; }

  /// Gravity in the base frame (m/s^2).
  Vector3<S> gravity = Vector3<S>(S(0), S(-9.81), S(0));

  /// The configuration with every joint at zero and every quaternion the identity.
  VectorX<S> neutralConfiguration() const;

 private:
  std::vector<Link<S>> links_;
  Matrix6X<S> S_;
  VectorX<S> armature_, damping_, friction_, velocityLimit_, lower_, upper_;
  std::vector<Drive<S>> drives_;
  std::vector<int> scalarQ_;
  int nq_ = 0, nv_ = 0;
};

/// The first link whose joint has degrees of freedom but moves no mass (the link and all its
/// descendants massless: the mass matrix would be singular), or -1 when there is none.
template <class S>
int firstLinkMovingNoMass(const Model<S>& model);

}  // namespace inertia::articulation
