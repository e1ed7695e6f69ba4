// Internal: a joint as the world keeps it (JointRecord) and as a step solves it
// (JointConstraint). The solver stage is joint_solver.h.
#pragma once

#include <algorithm>
#include <array>
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
  /// The impulses of the joint's locked rows (JointConstraint::lock), kept for the next
  /// step's warm start.
  Eigen::Matrix<Real, RowBlock::kMax, 1> lockImpulse =
      Eigen::Matrix<Real, RowBlock::kMax, 1>::Zero();
  RowBlock spin;  ///< A ball joint's rotation friction (3 angular rows).
  AxisRows cone;  ///< A ball joint's swing limit.
  /// The free degrees of freedom x, y, z, rx, ry, rz of JointRecord::axes (a hinge's angle is
  /// rx, a slider's position and a distance joint's length x, a ball joint's twist rx).
  std::array<AxisRows, 6> axes;
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
  /// anchors, and rotations whose x axis is the joint's axis; they coincide at creation
  /// (except a six-DOF joint's, which the user places).
  Transform frameA;
  Transform frameB;
  /// Per degree of freedom (x, y, z, rx, ry, rz of frame A): locked, or free with limits,
  /// motor, spring and friction. Only the six-DOF joint reads them all.
  std::array<JointAxis, 6> axes;
  std::optional<JointSpring> spring;              ///< A weld's or distance joint's.
  Real friction = 0;                              ///< A ball joint's (N m).
  std::optional<Real> coneLimit;                  ///< A ball joint's (rad).
  Real length = 0, minLength = 0, maxLength = 0;  ///< Distance joints (m).
  Real reference = 0;  ///< Slider: the anchors' offset along the axis at creation (m).
  Real breakForce = kUnbreakable;
  Real breakTorque = kUnbreakable;
  bool collideConnected = false;
  std::string name;
  JointParts parts;
  Vec3 force = Vec3::Zero();   ///< Last step's constraint force on B (N, world).
  Vec3 torque = Vec3::Zero();  ///< (N m)
  bool overloaded = false;     ///< Past a threshold this step: breaks at its end.
};

/// Whether a joint has nothing to solve but its locked rows: no limit, motor, spring or
/// friction on a free coordinate (a plain ball joint or hinge, a rigid weld).
inline bool lockedOnly(const JointRecord& j) {
  const auto driven = [](const JointAxis& a) {
    return !a.locked && (a.limits || a.motor || a.spring || a.friction > 0);
  };
  switch (j.type) {
    case JointType::Ball:
      return j.friction <= 0 && !j.coneLimit && !j.axes[3].limits;
    case JointType::Weld:
      return !j.spring;
    case JointType::Distance:
      return j.minLength == j.maxLength && !j.spring;
    default:
      return std::none_of(j.axes.begin(), j.axes.end(), driven);
  }
}

/// A joint in this step's solver: the solver bodies, and its frames at the step's start, from
/// which each substep's are the bodies' motion since the start (as the contacts' anchors).
struct JointConstraint {
  // The fields every pass reads come first (a large grid's passes are bound by memory).
  int bodyA = -1;  ///< Solver body, -1 for a static body or the world.
  int bodyB = -1;
  int stamp = -1;  ///< The position update its rows and coordinates were prepared for.
  std::uint32_t joint = 0;  ///< JointRecord index.
  /// Nothing but the locked rows to solve (lockedOnly()): the passes leave the record alone.
  bool lockedOnly = false;
  /// A plain ball joint (lockedOnly): its anchors' point constraint is all there is to it.
  bool point = false;
  /// Solved with its tree (joint_trees.h) for the current position update: the colour passes
  /// leave it alone.
  bool inTree = false;
  /// Every locked row of the joint, solved together: a ball joint's anchors (3 rows), a
  /// hinge's anchors and aligned axes (5), a slider's rotation and off-axis offsets (5), a
  /// weld's all (6), a six-DOF joint's locked degrees of freedom. Kept here, in colour order,
  /// so the passes read it in sequence; JointParts::lockImpulse carries its impulses.
  RowBlock lock;
  Vec3 rA = Vec3::Zero();  ///< Anchor minus centre of mass, world (m).
  Vec3 rB = Vec3::Zero();
  Vec3 deltaCenter = Vec3::Zero();  ///< cB - cA (m).
  Quat frameA = Quat::Identity();   ///< World rotation of the joint's frame on A.
  Quat frameB = Quat::Identity();
  Vec3 fallbackAxis = Vec3::UnitY();  ///< A distance joint's direction when its length is 0.
  JointParts* parts = nullptr;        ///< The record's other parts: solved in place.
  std::array<Real, 6> coordinate{};  ///< The free coordinates then (x, y, z, rx, ry, rz).
  Real swing = 0;                    ///< A ball joint's swing then (rad).
};

}  // namespace inertia::detail
