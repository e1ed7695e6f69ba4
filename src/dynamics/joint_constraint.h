// Internal: a joint as the world keeps it (JointRecord) and as a step solves it
// (JointConstraint). The solver stage is joint_solver.h.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "inertia/dynamics/joint.h"
#include "joint_parts.h"

namespace inertia::detail {

/// The body slot that stands for the world (a joint's null body A).
inline constexpr std::uint32_t kWorldBody = std::numeric_limits<std::uint32_t>::max();

/// The parts a joint may use, with their accumulated impulses (kept between steps for warm
/// starting; each type uses some of them, see joint_solver.cpp).
struct JointParts {
  RowBlock<3> point;     ///< Anchors together (ball, hinge, weld).
  RowBlock<2> offAxis;   ///< Anchors on the axis (slider).
  RowBlock<3> rotation;  ///< Relative rotation locked (weld, slider).
  RowBlock<2> aligned;   ///< Hinge axes aligned.
  RowBlock<3> spin;      ///< Rotation friction (ball).
  AxisRows axis;         ///< The free coordinate: spring, motor, friction, limits.
};

struct JointRecord {
  std::uint32_t generation = 1;
  bool alive = false;
  bool enabled = true;
  bool broken = false;
  JointType type = JointType::Ball;
  std::uint32_t bodyA = kWorldBody;  ///< Body slot, or kWorldBody.
  std::uint32_t bodyB = 0;
  /// The joint's frames in the bodies' origin frames (A's in the world's for kWorldBody): the
  /// anchors, and rotations whose x axis is the joint's axis; they coincide at creation.
  Transform frameA;
  Transform frameB;
  std::optional<JointLimits> limits;
  std::optional<JointMotor> motor;
  std::optional<JointSpring> spring;
  Real friction = 0;
  Real length = 0, minLength = 0, maxLength = 0;  ///< Distance joints (m).
  Real reference = 0;  ///< Slider: the anchors' offset along the axis at creation (m).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name;
  JointParts parts;
  Vec3 force = Vec3::Zero();   ///< Last step's constraint force on B (N, world).
  Vec3 torque = Vec3::Zero();  ///< (N m)
};

/// A joint in this step's solver: the solver bodies, and its frames at the step's start, from
/// which each substep's are the bodies' motion since the start (as the contacts' anchors).
struct JointConstraint {
  std::uint32_t joint = 0;  ///< JointRecord index.
  int bodyA = -1;           ///< Solver body, -1 for a static body or the world.
  int bodyB = -1;
  Vec3 rA = Vec3::Zero();  ///< Anchor minus centre of mass, world (m).
  Vec3 rB = Vec3::Zero();
  Vec3 deltaCenter = Vec3::Zero();  ///< cB - cA (m).
  Quat frameA = Quat::Identity();   ///< World rotation of the joint's frame on A.
  Quat frameB = Quat::Identity();
  Softness spring{};                  ///< Of the joint's spring.
  Softness servo{};                   ///< Of its motor's servo.
  Vec3 fallbackAxis = Vec3::UnitY();  ///< A distance joint's direction when its length is 0.
  JointParts parts;
};

}  // namespace inertia::detail
