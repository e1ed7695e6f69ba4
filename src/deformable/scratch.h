// A deformable's step scratch: buffers sized at the first step and reused (no allocation in a
// step after warm-up, except the obstacles' caches when they change).
#pragma once

#include <vector>

#include "deformable/implicit_euler.h"
#include "inertia/deformable/deformable.h"
#include "inertia/geometry/bounds.h"
#include "inertia/ode/workspace.h"

namespace inertia {

struct Deformable::Scratch {
  ode::Workspace<Real> workspace;       // the ode layer's stage buffers (explicit methods)
  std::vector<Real> forces;             // N, 3 per vertex
  std::vector<Real> fieldAcceleration;  // m/s^2, 3 per vertex
  std::vector<Real> fieldDamping;       // kg/s per vertex (linear drag and wind)
  std::vector<Real> start;              // positions at the step's start, for swept collisions
  std::vector<Real> startVelocity;      // velocities at the step's start (explicit methods)
  detail::ImplicitEuler implicit;
  std::vector<detail::AttachmentTerm> attachments;  // the implicit step's view of attachments_
  std::vector<detail::VertexContact> contacts;      // vertices held against dynamic bodies
  std::vector<std::size_t> contactObstacles;  // each one's index into moving_, or a static one
  std::vector<Aabb> obstacleBounds;           // world bounds of obstacles_, then of moving_
  DeformableCollisionCache selfCollision;
};

}  // namespace inertia
