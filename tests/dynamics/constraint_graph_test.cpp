// The constraint graph's colouring (src/dynamics/constraint_graph.h) against its definition:
// every joint and contact in exactly one group, no moving body twice in a group but the
// overflow, each kind in its own order within a group, and joints given colours first.
#include "dynamics/constraint_graph.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace inertia;
using namespace inertia::detail;

namespace {

// `count` edges between random bodies of `bodies` (a fifth of them static or kinematic:
// invMass 0), some with one side static (-1).
std::vector<GraphEdge> randomEdges(std::mt19937& rng, int bodies, int count) {
  std::vector<GraphEdge> edges;
  for (int k = 0; k < count; ++k) {
    const int a = int(rng() % unsigned(bodies));
    const int b = rng() % 4 == 0 ? -1 : int(rng() % unsigned(bodies));
    edges.push_back({a, b == a ? -1 : b});
  }
  return edges;
}

std::vector<SolverBody> randomBodies(std::mt19937& rng, int count) {
  std::vector<SolverBody> bodies(static_cast<std::size_t>(count));
  for (SolverBody& b : bodies) b.invMass = rng() % 5 == 0 ? Real(0) : Real(1);
  return bodies;
}

}  // namespace

TEST(ConstraintGraph, ColorsSeparateMovingBodiesAcrossKinds) {
  std::mt19937 rng(5);
  for (int bodyCount : {3, 40, 500}) {
    const std::vector<SolverBody> bodies = randomBodies(rng, bodyCount);
    const std::vector<GraphEdge> joints = randomEdges(rng, bodyCount, 150);
    const std::vector<GraphEdge> contacts = randomEdges(rng, bodyCount, 900);
    ConstraintColoring col;
    colorGraph(joints, contacts, bodies, col);
    ASSERT_EQ(col.offsets.size(), col.jointOffsets.size());
    ASSERT_EQ(col.order.size(), contacts.size());
    ASSERT_EQ(col.jointOrder.size(), joints.size());
    const std::size_t groups = col.offsets.size() - 1;
    EXPECT_LE(groups, std::size_t(kMaxColors + 1));
    std::vector<int> seenJoint(joints.size(), 0), seenContact(contacts.size(), 0);
    for (std::size_t g = 0; g < groups; ++g) {
      std::vector<int> users(bodies.size(), 0);
      auto use = [&](const GraphEdge& e) {
        for (int i : {e.bodyA, e.bodyB})
          if (i >= 0 && bodies[std::size_t(i)].invMass > 0) ++users[std::size_t(i)];
      };
      for (std::uint32_t k = col.jointOffsets[g]; k < col.jointOffsets[g + 1]; ++k) {
        ++seenJoint[col.jointOrder[k]];
        use(joints[col.jointOrder[k]]);
        if (k > col.jointOffsets[g]) {
          EXPECT_LT(col.jointOrder[k - 1], col.jointOrder[k]);
        }
      }
      for (std::uint32_t k = col.offsets[g]; k < col.offsets[g + 1]; ++k) {
        ++seenContact[col.order[k]];
        use(contacts[col.order[k]]);
        if (k > col.offsets[g]) {
          EXPECT_LT(col.order[k - 1], col.order[k]);
        }
      }
      EXPECT_GT(col.jointOffsets[g + 1] - col.jointOffsets[g] + col.offsets[g + 1] - col.offsets[g],
                0u)
          << "empty group " << g;
      if (g + 1 == groups && col.overflow) continue;  // the overflow may share bodies
      for (int n : users) EXPECT_LE(n, 1) << "group " << g << ", " << bodyCount << " bodies";
    }
    for (int n : seenJoint) EXPECT_EQ(n, 1);
    for (int n : seenContact) EXPECT_EQ(n, 1);
    // Three bodies hold 1,050 constraints: past 24 colours. 500 hold about four each.
    if (bodyCount == 3) {
      EXPECT_TRUE(col.overflow);
    }
    if (bodyCount == 500) {
      EXPECT_FALSE(col.overflow);
    }
  }
}

// Joints choose first: a joint and a contact on the same moving body, the contact listed first
// in the scene, still leave colour 0 to the joint.
TEST(ConstraintGraph, JointsTakeTheirColoursFirst) {
  std::vector<SolverBody> bodies(2);
  for (SolverBody& b : bodies) b.invMass = 1;
  const std::vector<GraphEdge> joints = {{0, 1}};
  const std::vector<GraphEdge> contacts = {{0, -1}, {1, -1}};
  ConstraintColoring col;
  colorGraph(joints, contacts, bodies, col);
  ASSERT_EQ(col.jointOffsets.size(), 3u);  // two groups
  EXPECT_EQ(col.jointOffsets[1] - col.jointOffsets[0], 1u);
  EXPECT_EQ(col.offsets[1] - col.offsets[0], 0u);
  EXPECT_EQ(col.offsets[2] - col.offsets[1], 2u);
  EXPECT_FALSE(col.overflow);
}
