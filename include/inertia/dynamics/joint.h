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

#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "inertia/core/id.h"
#include "inertia/core/types.h"

namespace inertia {

enum class JointType : std::uint8_t { Ball, Hinge, Slider, Weld, Distance };

/// The scene-file name of a joint type ("ball", "hinge", "slider", "weld", "distance").
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

inline constexpr Real kUnbreakable = std::numeric_limits<Real>::infinity();

/// Ball-and-socket (spherical): the anchors coincide; rotation is free.
struct BallJointSettings {
  BodyId bodyA{};  ///< Null: the world.
  BodyId bodyB{};
  Vec3 anchorA = Vec3::Zero();      ///< (m, A's frame; world when A is null)
  Vec3 anchorB = Vec3::Zero();      ///< (m, B's frame)
  Real friction = 0;                ///< Torque resisting rotation (N m, >= 0).
  Real breakForce = kUnbreakable;   ///< Breaks above this constraint force (N).
  Real breakTorque = kUnbreakable;  ///< Breaks above this constraint torque (N m).
  bool collideConnected = false;    ///< The two bodies collide with each other.
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
