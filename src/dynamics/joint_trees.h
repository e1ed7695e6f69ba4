// Internal: plain ball joints that form trees, solved exactly as one block per tree (Baraff,
// "Linear-time dynamics using Lagrange multipliers", SIGGRAPH 1996, in the joints' own space),
// and their anchors projected together after each position update (post-stabilisation, Cline
// and Pai 2003). Solved one by one, Gauss-Seidel passes the load of a chain's lower links up to
// its top joint a link per pass, and the soft rows correct the drift of each position update
// (second order in the substep) at their 120 Hz: a 20-link chain whipping down from horizontal
// opened its joints by 14 mm (bench/joints_bench.cpp). Solved together,
//   K lambda = -(J v + bias),   K = J M^-1 J^T,
// each pass meets every joint of the tree at once; the soft coefficients apply to the tree as
// to one joint, dlambda = -massScale K^-1 (J v + bias) - impulseScale lambda_acc, and since
// massScale + impulseScale = 1 a pass after an exact one changes nothing. After the position
// update the bodies move by dx = -M^-1 J^T K^-1 C, which closes the anchors to second order in
// C; the factor made there serves the projection, the relaxation and the next substep's solve
// (the projection turns the arms by C / r, a thousandth of a radian, which K follows to that
// order).
//
// K couples two joints only through a body they share, so eliminating the joints from the
// leaves to the root (the reverse of a breadth-first walk over the bodies) leaves each joint's
// remaining neighbours on one body, its parent, where they are coupled already: the block
// LDL^T factor fills nothing outside K's pattern, in time linear in the joints for bounded
// degree. A body that does not move (the world, a static or kinematic body) couples nothing,
// so a chain held at both ends is still a tree.
//
// The trees are built each step from the graph's joint constraints (buildJointTrees). A
// component with a loop, or with another kind of joint on one of its bodies, stays with the
// colours' Gauss-Seidel passes whole: the projection moves a tree's bodies for its own joints
// alone, which the others would feel as a pull each substep (a joint grid's spanning tree,
// projected, blew up). So do the joints of a tree whose factor fails (a pivot lost to
// rounding). The joints keep their place in the colours, their warm start and their
// accumulated impulses; JointConstraint::inTree tells the colour passes to leave a factored
// tree's joints alone.
#pragma once

#include <cstdint>
#include <vector>

#include "core/union_find.h"
#include "inertia/core/types.h"

namespace inertia::detail {

struct RigidBodyData;
struct JointPass;
class StepWorkers;

/// This step's joint trees, their factors and scratch (kept between steps: no allocation
/// once warm).
struct JointTrees {
  /// Per tree, its range of `joints`: constraint indices in breadth-first order from the
  /// tree's root body (eliminated in reverse).
  std::vector<std::uint32_t> treeOffsets, joints;
  /// Per entry of `joints`: its range of `up`, the entries it couples with that are eliminated
  /// after it (smaller indices, on its parent body).
  std::vector<std::uint32_t> upOffsets, up;
  /// Per entry of `joints`: which side of the joint is its parent body (the side towards the
  /// root: 0 for A, 1 for B).
  std::vector<std::uint8_t> parentSide;
  /// Per `up` entry k of joint d: K_kd, then L_kd = K_kd D_d^-1 after factoring.
  std::vector<Mat3> coupling, lower;
  /// Per entry: the pivot block D_d (Schur complement), its inverse; the pass's right side.
  std::vector<Mat3> pivot, pivotInverse;
  std::vector<Vec3> rhs;
  /// Per tree: the position update its factor was made for; whether it was made.
  std::vector<int> stamps;
  std::vector<std::uint8_t> factored;
  /// Per tree: nothing but its joints acts on its bodies (no contact, no other joint), so the
  /// first pass of each position update solves it and the passes after it change nothing.
  std::vector<std::uint8_t> alone;
  // Building scratch: bodies' union-find; per component (at its root) its joints and whether
  // it is left out; the loops' closing joints; per solver body its joints (CSR), its edges and
  // a visit mark; the walk's queue.
  UnionFind bodies;
  std::vector<std::uint32_t> componentSize, loops, bodyJointOffsets, bodyJoints, bodyEdges, queue;
  std::vector<std::uint8_t> eligible, excluded, visited;
  std::vector<std::uint32_t> entryOf;  // per constraint: its entry in `joints`

  std::size_t treeCount() const { return treeOffsets.empty() ? 0 : treeOffsets.size() - 1; }
};

/// Groups this step's plain ball joints (JointConstraint::point) into trees of two or more
/// joints over moving bodies. After prepareJoints.
void buildJointTrees(RigidBodyData& D);

/// One pass over every tree: each tree's joints refreshed and factored for `pass.stamp` when
/// not yet, then solved exactly together (the trees in parallel: they share no moving body).
/// After the first pass (`firstPass`) of a position update, a tree alone is left as it is: with the soft
/// coefficients' massScale + impulseScale = 1, an exact solve leaves the next one nothing.
void solveJointTrees(RigidBodyData& D, const JointPass& pass, bool firstPass, StepWorkers& workers);

/// After a position update (`pass.stamp`): each tree's bodies moved so that its joints'
/// anchors meet to first order (post-stabilisation, Cline and Pai 2003): dx = -M^-1 J^T K^-1 C,
/// each joint's C shortened to at most kMaxJointBias times the substep.
void projectJointTrees(RigidBodyData& D, const JointPass& pass, StepWorkers& workers);

}  // namespace inertia::detail
