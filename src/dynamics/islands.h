// Internal: islands, for sleeping and waking. One union-find over the constraint graph's edges
// between dynamic bodies (today the contacts): an island with one awake body, or touching a
// moving kinematic body, wakes whole; an island whose every body has rested for
// ContactTuning::timeToSleep falls asleep whole.
#pragma once

#include "rigid_body_data.h"

namespace inertia::detail {

/// The root of `i` in the union-find `parent`, halving the path on the way.
inline std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

/// Builds the islands of this step's contacts and wakes every body of an awake island.
void buildIslands(RigidBodyData& D);
/// After the motion: islands that rested long enough fall asleep (when `s.sleeping`);
/// kinematic bodies are awake while they move.
void sleepIslands(RigidBodyData& D, const DynamicsSettings& s);

}  // namespace inertia::detail
