// Islands (src/dynamics/islands.h) against a breadth-first search: constraints that share a
// body (static ones, -1, link nothing) are in one island, constraints of different islands
// share no body, and the order is the one the LCP solvers rely on.
#include "dynamics/islands.h"

#include <gtest/gtest.h>

#include <queue>
#include <random>
#include <vector>

using namespace inertia::detail;

namespace {

// The connected component of each edge by breadth-first search over shared bodies.
std::vector<int> components(const std::vector<GraphEdge>& edges, int bodies) {
  std::vector<std::vector<int>> byBody(static_cast<std::size_t>(bodies));
  for (std::size_t k = 0; k < edges.size(); ++k)
    for (int b : {edges[k].bodyA, edges[k].bodyB})
      if (b >= 0) byBody[std::size_t(b)].push_back(int(k));
  std::vector<int> component(edges.size(), -1);
  int next = 0;
  for (std::size_t start = 0; start < edges.size(); ++start) {
    if (component[start] >= 0) continue;
    std::queue<int> open;
    open.push(int(start));
    component[start] = next;
    while (!open.empty()) {
      const GraphEdge& e = edges[std::size_t(open.front())];
      open.pop();
      for (int b : {e.bodyA, e.bodyB}) {
        if (b < 0) continue;
        for (int k : byBody[std::size_t(b)])
          if (component[std::size_t(k)] < 0) {
            component[std::size_t(k)] = next;
            open.push(k);
          }
      }
    }
    ++next;
  }
  return component;
}

}  // namespace

TEST(Islands, GroupConstraintsMatchesBreadthFirstSearch) {
  std::mt19937 rng(9);
  ConstraintIslands islands;  // reused: the scratch must not carry one call into the next
  for (int bodies : {1, 5, 60, 400}) {
    std::vector<GraphEdge> edges;
    for (int k = 0; k < 300; ++k) {
      const int a = rng() % 5 == 0 ? -1 : int(rng() % unsigned(bodies));
      const int b = rng() % 3 == 0 ? -1 : int(rng() % unsigned(bodies));
      edges.push_back({a, b < 0 && a < 0 ? 0 : b});
    }
    groupConstraints(edges, std::size_t(bodies), islands);
    const std::vector<int> expected = components(edges, bodies);
    ASSERT_EQ(islands.constraints.size(), edges.size());
    std::vector<int> islandOf(edges.size(), -1);
    const std::size_t count = islands.offsets.size() - 1;
    for (std::size_t i = 0; i < count; ++i) {
      for (std::uint32_t k = islands.offsets[i]; k < islands.offsets[i + 1]; ++k) {
        ASSERT_EQ(islandOf[islands.constraints[k]], -1) << "constraint in two islands";
        islandOf[islands.constraints[k]] = int(i);
        if (k > islands.offsets[i]) {
          EXPECT_LT(islands.constraints[k - 1], islands.constraints[k]);
        }
      }
      // Islands come in the order of their first constraint.
      if (i > 0) {
        EXPECT_LT(islands.constraints[islands.offsets[i - 1]],
                  islands.constraints[islands.offsets[i]]);
      }
    }
    // The same partition as the search: equal islands exactly where equal components.
    for (std::size_t j = 0; j < edges.size(); ++j)
      for (std::size_t k = j + 1; k < edges.size(); ++k)
        ASSERT_EQ(islandOf[j] == islandOf[k], expected[j] == expected[k])
            << "constraints " << j << " and " << k << ", " << bodies << " bodies";
  }
}
