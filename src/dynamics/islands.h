// Internal: islands. One union-find serves every grouping of the step:
//   - sleeping and waking (buildIslands, sleepIslands): bodies linked by the constraint
//     graph's edges between dynamic bodies (contacts and enabled joints). An island with one awake
//     body, or touching a moving kinematic body, wakes whole; an island whose every body has rested
//     for ContactTuning::timeToSleep falls asleep whole;
//   - the direct LCP solvers (groupConstraints): constraints linked through a shared solver
//     body, each island one LCP. Built once a step into scratch kept from step to step.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "constraint_graph.h"
#include "core/union_find.h"

namespace inertia {
struct DynamicsSettings;
}

namespace inertia::detail {

struct RigidBodyData;

/// Constraints grouped into islands: island i is constraints[offsets[i], offsets[i + 1]), the
/// islands in the order of their first constraint, each constraint's index in order.
struct ConstraintIslands {
  std::vector<std::uint32_t> constraints;
  std::vector<std::uint32_t> offsets;
  // Scratch, kept so that grouping a step does not allocate.
  UnionFind sets;
  std::vector<std::int32_t> islandOfRoot;
  std::vector<std::uint32_t> next;
};

/// Groups the edges over `bodyCount` solver bodies into islands: edges that share a body
/// (index >= 0; -1, a static body, links nothing) are in the same island.
void groupConstraints(std::span<const GraphEdge> edges, std::size_t bodyCount,
                      ConstraintIslands& out);

/// Builds the islands of this step's contacts and wakes every body of an awake island.
void buildIslands(RigidBodyData& D);
/// After the motion: islands that rested long enough fall asleep (when `s.sleeping`);
/// kinematic bodies are awake while they move.
void sleepIslands(RigidBodyData& D, const DynamicsSettings& s);

}  // namespace inertia::detail
