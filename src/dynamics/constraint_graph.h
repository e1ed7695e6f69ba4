// Internal: the constraint graph (Box2D v3's constraint_graph.c, in 3D). Every constraint of a
// step is an edge between two solver bodies: contacts today, joints, and later the rows that
// articulations and deformables add. The graph is coloured so that no two constraints of a
// colour share a moving body (static and kinematic bodies are shared freely): a colour's
// constraints can then be solved in parallel with the result they would have in sequence.
// Constraints that find no free colour among kMaxColors form a last, overflow group, solved in
// sequence. Within each colour, joints are solved before contacts (as Box2D v3 does), so the
// contacts see the joints' impulses of the same pass.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "solver_body.h"

namespace inertia::detail {

/// An edge of the graph: its two solver bodies, -1 for a static body (or the world).
struct GraphEdge {
  int bodyA = -1;
  int bodyB = -1;
};

inline constexpr int kMaxColors = 24;
/// Constraints per block of a colour's parallel pass.
inline constexpr std::uint32_t kColorGrain = 64;

/// The constraints of each kind grouped by colour; every kind has the same groups (the colours
/// some constraint uses, in order, then the overflow).
struct ConstraintColoring {
  std::vector<std::uint32_t> order;    ///< Contact indices, colour by colour.
  std::vector<std::uint32_t> offsets;  ///< Group g's contacts: order[offsets[g], offsets[g + 1]).
  std::vector<std::uint32_t> jointOrder;    ///< Joint indices, colour by colour.
  std::vector<std::uint32_t> jointOffsets;  ///< Group g's joints, likewise.
  bool overflow = false;                    ///< The last group is the overflow.
  // Scratch of colorGraph(), kept so that colouring a step does not allocate.
  std::vector<std::uint64_t> used;
  std::vector<std::uint8_t> color;
  std::vector<GraphEdge> edges;  // colorConstraints()'s edges (the step makes its own)
};

/// Colours the joints, then the contacts, greedily in their order (Box2D v3): each takes the
/// first colour in which neither of its moving bodies is used yet. Deterministic, independent
/// of any thread count; within a group each kind keeps its order.
void colorGraph(std::span<const GraphEdge> joints, std::span<const GraphEdge> contacts,
                const std::vector<SolverBody>& bodies, ConstraintColoring& out);

}  // namespace inertia::detail
