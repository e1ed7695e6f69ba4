// Bodies whose motion another system computes: the links of an articulation. They are bodies of
// the RigidBodySystem for the broad and narrow phase, but the rigid solver neither integrates
// nor pushes them directly: their contact rows (with bodies, and between two members when the
// group collides with itself), and the rows of the ball joints on them (loops),
// are solved in the rigid bodies' substeps, in sequence after the coloured constraints, through
// the owner's response (DESIGN.md section 1:
// dynamics defines the rows and stages, a higher layer implements them for its links).
#pragma once

#include "inertia/core/types.h"

namespace inertia {

/// How a group of driven bodies (an articulation's links, its "members") answers impulses.
/// Within RigidBodySystem::step the calls come in this order, from one thread per group:
///   beginStep(); addPoint() for each contact point on a member, addFrame() for each joint;
///   per substep: integrateVelocities(h); pointVelocity() / applyImpulse() while the contacts
///     are solved, and solveRows() once per iteration after them; integratePositions(h);
///     the same in the relax pass;
/// and then, after the step, the owner moves the member bodies (RigidBodySystem::setDrivenState).
/// The virtual calls are made in sequence, never from parallel workers.
class MultibodyResponse {
 public:
  /// A frame's velocity [v; w] (its point's, m/s, and the member's angular velocity, rad/s) or
  /// impulse [P; L] (N s at the point, N m s), world axes.
  using FrameVector = Eigen::Matrix<Real, 6, 1>;
  using FrameMatrix = Eigen::Matrix<Real, 6, 6>;

  virtual ~MultibodyResponse() = default;
  /// The step starts: forget last step's points, prepare the response at this configuration.
  virtual void beginStep() = 0;
  /// A material point of member `member` at world position `point` (m) at the step's start;
  /// returns its handle for this step.
  virtual int addPoint(int member, const Vec3& point) = 0;
  /// W = J M^-1 J^T: the point's velocity change per unit impulse on it (s/kg, world axes).
  virtual Mat3 pointResponse(int handle) const = 0;
  /// J_a M^-1 J_b^T: point `a`'s velocity change per unit impulse on point `b` (s/kg, world
  /// axes), for rows between two members (a tree's self-contacts and loops);
  /// crossResponse(h, h) is pointResponse(h), and crossResponse(b, a) its transpose.
  virtual Mat3 crossResponse(int a, int b) const = 0;
  /// The point's velocity (m/s, world).
  virtual Vec3 pointVelocity(int handle) const = 0;
  /// The point's displacement since the step's start (m, world).
  virtual Vec3 pointDisplacement(int handle) const = 0;
  /// An impulse (N s, world) on the point: changes the velocities of every member.
  virtual void applyImpulse(int handle, const Vec3& impulse) = 0;

  // Frames: points that also answer angular rows (a joint's locked rows through a link). A
  // frame's handle is a point's too (pointDisplacement, pointVelocity, crossResponse).
  /// A frame of member `member` at world position `point` (m) at the step's start.
  virtual int addFrame(int member, const Vec3& point) = 0;
  /// Frame a's [v; w] change per unit impulse [P; L] on frame b (J_a M^-1 J_b^T).
  virtual FrameMatrix frameResponse(int a, int b) const = 0;
  virtual FrameVector frameVelocity(int handle) const = 0;
  virtual void applyFrameImpulse(int handle, const FrameVector& impulse) = 0;
  /// The member's rotation now (world).
  virtual Quat frameRotation(int handle) const = 0;
  /// The substep's velocity update (gravity, joint forces), then its position update.
  virtual void integrateVelocities(Real h) = 0;
  /// One Gauss-Seidel pass over the group's own rows (an articulation's joint limits and
  /// drives), in each solve and relax iteration beside its contacts, so that the substep's
  /// velocities answer both.
  virtual void solveRows() = 0;
  virtual void integratePositions(Real h) = 0;
};

}  // namespace inertia
