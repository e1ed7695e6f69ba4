// Joints: constraints between two bodies, or a body and the world (the seeds' part on
// constraints: ball, revolute, prismatic, weld; limits as one-sided rows, motors, springs,
// joints that break under excessive force). Each type has its settings struct, filled with
// designated initialisers:
//
//   world.createJoint(HingeJointSettings{.bodyA = door, .bodyB = frame,
//                                        .anchorA = {0, 0, 0}, .anchorB = {0.5f, 0, 0},
//                                        .limits = JointLimits{-1.5f, 0}});
//
// Anchors and axes are in each body's own frame (of its origin); with a null bodyA (the world)
// anchorA and axisA are world coordinates. Angles and positions along a joint's axis are
// measured from the bodies' poses when the joint was created (zero there).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "inertia/core/id.h"
#include "inertia/core/types.h"

namespace inertia {

enum class JointType : std::uint8_t { Ball, Hinge, Slider, Universal, Weld, Distance, SixDof };

/// The scene-file name of a joint type ("ball", "hinge", "slider", "universal", "weld",
/// "distance", "six_dof").
std::string_view jointTypeName(JointType type);

/// Bounds of a joint's free coordinate: an angle (rad) or a position along an axis (m).
/// lower <= upper; lower == upper locks it there.
struct JointLimits {
  Real lower = 0;
  Real upper = 0;
};

/// A motor on a joint's free coordinate. It drives the coordinate's speed to `speed` with at
/// most `maxForce`; with a `target` it is a servo instead, driving the coordinate to the
/// target like a critically damped spring of `servoFrequency`, with at most `maxForce`.
struct JointMotor {
  Real speed = 0;                ///< Target speed (rad/s for a rotation, m/s for a translation).
  Real maxForce = 0;             ///< Largest torque (N m) or force (N) it exerts, >= 0.
  std::optional<Real> target{};  ///< Servo: target angle (rad) or position (m).
  Real servoFrequency = 2;       ///< Servo stiffness as a frequency (Hz, > 0).
};

/// A spring on a joint's coordinate (Catto's soft constraint): its stiffness and damping given
/// as the frequency and damping ratio of the oscillation of the bodies' effective mass, so
/// that it behaves the same whatever the masses.
struct JointSpring {
  Real frequency = 1;     ///< Undamped frequency (Hz, > 0).
  Real dampingRatio = 0;  ///< 1 is critical damping (>= 0).
  Real rest = 0;          ///< Rest angle (rad) or position (m); a distance joint's is its length.
};

/// One degree of freedom of a joint (a six-DOF joint has six: translations along and rotations
/// about its frame A's axes): locked, or free within optional limits, with an optional motor,
/// spring and friction.
struct JointAxis {
  bool locked = true;
  std::optional<JointLimits> limits{};
  std::optional<JointMotor> motor{};
  std::optional<JointSpring> spring{};  ///< Towards its rest.
  Real friction = 0;                    ///< Force (N) or torque (N m) resisting motion, >= 0.
};

inline constexpr Real kUnbreakable = std::numeric_limits<Real>::infinity();

/// Ball-and-socket (spherical): the anchors coincide; rotation is free, within an optional cone
/// about the joint's axis (the swing of B's axis from A's) and optional twist limits about it
/// (shoulders and hips). Without those and friction, a side may be an articulation's link (a
/// loop closure; the only joint a link takes).
struct BallJointSettings {
  BodyId bodyA{};  ///< Null: the world.
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();      ///< (m, A's frame; world when A is null)
  Vec3 anchorB = Vec3::Zero();      ///< (m, B's frame)
  Vec3 axisA = Vec3::UnitX();       ///< The cone's and twist's axis in A's frame (not zero).
  Vec3 axisB = Vec3::UnitX();       ///< The same axis in B's frame.
  std::optional<Real> coneLimit{};  ///< Largest swing angle (rad, in (0, pi)).
  std::optional<JointLimits> twistLimits{};  ///< Twist about the axis (rad, within [-pi, pi]).
  Real friction = 0;                         ///< Torque resisting rotation (N m, >= 0).
  Real breakForce = kUnbreakable;            ///< Breaks above this constraint force (N).
  Real breakTorque = kUnbreakable;           ///< Breaks above this constraint torque (N m).
  bool collideConnected = false;             ///< The two bodies collide with each other.
  std::string name{};
};

/// Hinge (revolute): the anchors coincide and the axes stay aligned; rotation about the axis.
struct HingeJointSettings {
  BodyId bodyA{};
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();
  Vec3 anchorB = Vec3::Zero();
  Vec3 axisA = Vec3::UnitZ();           ///< Hinge axis in A's frame (normalised; not zero).
  Vec3 axisB = Vec3::UnitZ();           ///< The same axis in B's frame.
  std::optional<JointLimits> limits{};  ///< Angle of B about the axis relative to A (rad).
  std::optional<JointMotor> motor{};
  std::optional<JointSpring> spring{};  ///< Towards the rest angle.
  Real friction = 0;                    ///< Torque resisting rotation (N m, >= 0).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name{};
};

/// Slider (prismatic): no relative rotation; B's anchor moves along A's axis only.
struct SliderJointSettings {
  BodyId bodyA{};
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();
  Vec3 anchorB = Vec3::Zero();
  Vec3 axisA = Vec3::UnitX();           ///< Sliding axis in A's frame (normalised; not zero).
  std::optional<JointLimits> limits{};  ///< Position of B's anchor along the axis (m).
  std::optional<JointMotor> motor{};
  std::optional<JointSpring> spring{};  ///< Towards the rest position.
  Real friction = 0;                    ///< Force resisting sliding (N, >= 0).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name{};
};

/// Universal (Cardan): the anchors coincide; A turns about axisA, B about axisB, and the two
/// axes stay perpendicular (they must be perpendicular at creation). Each angle has its own
/// limits.
struct UniversalJointSettings {
  BodyId bodyA{};
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();
  Vec3 anchorB = Vec3::Zero();
  Vec3 axisA = Vec3::UnitX();            ///< In A's frame.
  Vec3 axisB = Vec3::UnitY();            ///< In B's frame; perpendicular to axisA at creation.
  std::optional<JointLimits> limitsA{};  ///< Angle about axisA (rad, within [-pi, pi]).
  std::optional<JointLimits> limitsB{};  ///< Angle about axisB (rad, within [-pi/2, pi/2]).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name{};
};

/// Six degrees of freedom (the seeds' N-DOF joint): frames on A and B (each in its body's
/// frame; A's in the world's for a null A); the translations of B's frame origin along A's
/// frame axes x, y, z and the rotations of B's frame relative to A's as X-Y-Z Euler angles rx,
/// ry, rz, each locked, free or limited, with a motor, spring and friction. Every other type
/// is one (a hinge: all locked but rx). ry must stay within (-pi/2, pi/2) (the Euler angles'
/// gimbal lock); rx and rz within [-pi, pi].
struct SixDofJointSettings {
  BodyId bodyA{};
  BodyId bodyB{};
  Transform frameA{};               ///< (m, A's frame)
  Transform frameB{};               ///< (m, B's frame)
  std::array<JointAxis, 6> axes{};  ///< x, y, z, rx, ry, rz; all locked by default (a weld).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name{};
};

/// Weld (fixed): the anchors coincide and the relative rotation stays as it was created; with
/// a spring, both the position and the rotation are springs (a soft weld).
struct WeldJointSettings {
  BodyId bodyA{};
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();
  Vec3 anchorB = Vec3::Zero();
  std::optional<JointSpring> spring{};  ///< `rest` unused.
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name{};
};

/// Distance: the anchors' distance stays within [minLength, maxLength] (a rope when minLength
/// is 0); with a spring it is pulled towards `length` inside those bounds. Rotation is free.
struct DistanceJointSettings {
  BodyId bodyA{};
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();
  Vec3 anchorB = Vec3::Zero();
  /// Rest length (m); negative: the anchors' distance at creation.
  Real length = -1;
  /// Bounds (m), 0 <= minLength <= maxLength; negative: equal to `length` (a rigid rod unless
  /// there is a spring).
  Real minLength = -1;
  Real maxLength = -1;
  std::optional<JointSpring> spring{};  ///< `rest` unused (the rest length is `length`).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name{};
};

/// How far a joint is from satisfied, from the bodies' poses.
struct JointError {
  Real position = 0;  ///< The anchors' distance off the joint's allowed motion (m).
  Real angle = 0;     ///< The angle of its locked rotations off their lock (rad).
};

/// A joint that broke in the last step (its force or torque passed the threshold).
struct JointEvent {
  JointId joint{};
  Vec3 force = Vec3::Zero();   ///< The constraint force when it broke (N, on B, world).
  Vec3 torque = Vec3::Zero();  ///< (N m)
};

}  // namespace inertia
