// Internal: a body as the constraint solvers see it.
#pragma once

#include "inertia/core/types.h"

namespace inertia::detail {

/// A body as the solver sees it: velocities and the motion since the step's start. The float
/// kernels read v, w, dp and dR as runs of consecutive floats (contact_kernels.inl).
struct SolverBody {
  Vec3 v = Vec3::Zero();   ///< Linear velocity of the centre of mass (m/s).
  Vec3 w = Vec3::Zero();   ///< Angular velocity (rad/s).
  Vec3 dp = Vec3::Zero();  ///< Displacement of the centre of mass since the step's start (m).
  /// dq as a matrix, refreshed whenever dq changes (cheaper to apply).
  Mat3 dR = Mat3::Identity();
  Quat dq = Quat::Identity();      ///< Rotation since the step's start.
  Real invMass = 0;                ///< (1/kg); 0 for static and kinematic bodies.
  Mat3 invInertia = Mat3::Zero();  ///< World inverse inertia at the step's start (1/(kg m^2)).
};

}  // namespace inertia::detail
