// The joint trees' stage (joint_trees.h): building the trees, factoring K = L D L^T per tree
// after each position update, and the exact solve of each pass.
#include "joint_trees.h"

#include <algorithm>
#include <array>
#include <limits>

#include "inertia/core/math.h"
#include "joint_solver.h"
#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

bool moving(const RigidBodyData& D, int slot) {
  return slot >= 0 && D.solverBodies[std::size_t(slot)].invMass > 0;
}

// Per moving body its eligible joints, in constraint order (CSR over solver bodies).
void indexJointsByBody(RigidBodyData& D) {
  JointTrees& T = D.jointTrees;
  const std::size_t nb = D.solverBodies.size();
  T.bodyJointOffsets.assign(nb + 1, 0);
  for (std::size_t k = 0; k < D.jointConstraints.size(); ++k) {
    if (!T.eligible[k]) continue;
    const JointConstraint& c = D.jointConstraints[k];
    for (int slot : {c.bodyA, c.bodyB})
      if (moving(D, slot)) ++T.bodyJointOffsets[std::size_t(slot) + 1];
  }
  for (std::size_t b = 0; b < nb; ++b) T.bodyJointOffsets[b + 1] += T.bodyJointOffsets[b];
  T.bodyJoints.resize(T.bodyJointOffsets[nb]);
  T.queue.assign(T.bodyJointOffsets.begin(), T.bodyJointOffsets.end() - 1);  // fill cursors
  for (std::uint32_t k = 0; k < D.jointConstraints.size(); ++k) {
    if (!T.eligible[k]) continue;
    const JointConstraint& c = D.jointConstraints[k];
    for (int slot : {c.bodyA, c.bodyB})
      if (moving(D, slot)) T.bodyJoints[T.queue[std::size_t(slot)]++] = k;
  }
}

// Plain ball joints with a moving side, in components (over the moving bodies they join) that
// hold no loop and whose bodies no other joint touches: the projection moves a tree's bodies
// for its own joints alone, which a loop's closing joint or a hinge on them would feel as a
// pull each substep (a joint grid's spanning tree so projected blew up). The number of them per
// component, at its union-find root.
std::size_t markEligible(RigidBodyData& D) {
  JointTrees& T = D.jointTrees;
  const std::size_t nc = D.jointConstraints.size();
  const auto point = [](const JointConstraint& c) { return c.point; };
  if (std::count_if(D.jointConstraints.begin(), D.jointConstraints.end(), point) < 2) return 0;
  const std::size_t nb = D.solverBodies.size();
  T.bodies.reset(nb);
  T.excluded.assign(nb, 0);
  const auto exclude = [&](int slot) {
    if (moving(D, slot)) T.excluded[T.bodies.find(std::uint32_t(slot))] = 1;
  };
  T.loops.clear();
  for (std::uint32_t k = 0; k < nc; ++k) {
    const JointConstraint& c = D.jointConstraints[k];
    if (c.point && moving(D, c.bodyA) && moving(D, c.bodyB) &&
        !T.bodies.unite(std::uint32_t(c.bodyA), std::uint32_t(c.bodyB)))
      T.loops.push_back(k);
  }
  for (std::uint32_t k : T.loops) exclude(D.jointConstraints[k].bodyA);
  for (const JointConstraint& c : D.jointConstraints)
    if (!c.point) exclude(c.bodyA), exclude(c.bodyB);
  for (const MultibodyJoint& m : D.multibodyJoints) exclude(m.a.body), exclude(m.b.body);
  T.eligible.assign(nc, 0);
  T.componentSize.assign(nb, 0);
  std::size_t count = 0;
  for (std::size_t k = 0; k < nc; ++k) {
    const JointConstraint& c = D.jointConstraints[k];
    if (!c.point) continue;
    const int slot = moving(D, c.bodyA) ? c.bodyA : c.bodyB;
    if (!moving(D, slot)) continue;
    const std::uint32_t root = T.bodies.find(std::uint32_t(slot));
    if (T.excluded[root]) continue;
    T.eligible[k] = 1;
    ++T.componentSize[root];
    ++count;
  }
  return count;
}

// Per solver body, the graph's edges (contacts and joints) and the driven bodies' constraints
// on it.
void countBodyEdges(RigidBodyData& D) {
  JointTrees& T = D.jointTrees;
  T.bodyEdges.assign(D.solverBodies.size(), 0);
  const auto add = [&](int slot) {
    if (slot >= 0) ++T.bodyEdges[std::size_t(slot)];
  };
  for (const GraphEdge& e : D.contactEdges) add(e.bodyA), add(e.bodyB);
  for (const GraphEdge& e : D.jointEdges) add(e.bodyA), add(e.bodyB);
  for (const MultibodyContact& m : D.multibodyContacts) add(m.a.body), add(m.b.body);
  for (const MultibodyJoint& m : D.multibodyJoints) add(m.a.body), add(m.b.body);
}

// One tree's joints in breadth-first order from body `root` (each joint found from its parent
// body, the side nearer the root); whether its joints are all that act on its bodies.
bool walkTree(RigidBodyData& D, std::uint32_t root) {
  JointTrees& T = D.jointTrees;
  T.queue.clear();
  T.queue.push_back(root);
  T.visited[root] = 1;
  for (std::size_t q = 0; q < T.queue.size(); ++q) {
    const std::uint32_t body = T.queue[q];
    for (std::uint32_t i = T.bodyJointOffsets[body]; i < T.bodyJointOffsets[body + 1]; ++i) {
      const std::uint32_t k = T.bodyJoints[i];
      if (T.entryOf[k] != kNone) continue;
      const JointConstraint& c = D.jointConstraints[k];
      const std::uint8_t side = c.bodyA == int(body) ? 0 : 1;
      T.entryOf[k] = std::uint32_t(T.joints.size());
      T.joints.push_back(k);
      T.parentSide.push_back(side);
      const int other = side == 0 ? c.bodyB : c.bodyA;
      if (moving(D, other) && !T.visited[std::size_t(other)]) {
        T.visited[std::size_t(other)] = 1;
        T.queue.push_back(std::uint32_t(other));
      }
    }
  }
  return std::all_of(T.queue.begin(), T.queue.end(), [&](std::uint32_t body) {
    return T.bodyEdges[body] == T.bodyJointOffsets[body + 1] - T.bodyJointOffsets[body];
  });
}

// The solver body on a joint's side (0: A, 1: B) and the joint's arm and sign there: the
// anchor rows are J = s [I, -[r]x] on that body's (v, w), s = -1 on A and +1 on B.
int sideBody(const JointConstraint& c, int side) { return side == 0 ? c.bodyA : c.bodyB; }
const Vec3& sideArm(const JointConstraint& c, int side) {
  return side == 0 ? c.lock.armA : c.lock.armB;
}

// 3 x 3 products written out: Eigen's were calls, not inlined, and most of the factor's time.
Mat3 product(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) c(i, j) = a(i, 0) * b(0, j) + a(i, 1) * b(1, j) + a(i, 2) * b(2, j);
  return c;
}
// a b^T
Mat3 productTransposed(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) c(i, j) = a(i, 0) * b(j, 0) + a(i, 1) * b(j, 1) + a(i, 2) * b(j, 2);
  return c;
}
// a^T v
Vec3 transposedTimes(const Mat3& a, const Vec3& v) {
  return {a(0, 0) * v.x() + a(1, 0) * v.y() + a(2, 0) * v.z(),
          a(0, 1) * v.x() + a(1, 1) * v.y() + a(2, 1) * v.z(),
          a(0, 2) * v.x() + a(1, 2) * v.y() + a(2, 2) * v.z()};
}

// (1/m) I - [r]x I^-1 [s]x: a body's part of K between rows with arms r and s on it. Column j
// is e_j / m - r x (I^-1 (s x e_j)).
Mat3 bodyCoupling(const SolverBody& body, const Vec3& r, const Vec3& s) {
  const std::array<Vec3, 3> sx = {Vec3(0, s.z(), -s.y()), Vec3(-s.z(), 0, s.x()),
                                  Vec3(s.y(), -s.x(), 0)};
  Mat3 k;
  for (int j = 0; j < 3; ++j) {
    const Vec3 t = times(body.invInertia, sx[std::size_t(j)]);
    k.col(j) = -r.cross(t);
    k(j, j) += body.invMass;
  }
  return k;
}

// The inverse of a symmetric positive definite 3x3 block by its adjugate; false where its
// determinant is lost to rounding.
bool invertPivot(const Mat3& k, Mat3& inverse) {
  const Real scale = k.trace();
  if (!(k.determinant() > std::numeric_limits<Real>::epsilon() * scale * scale * scale))
    return false;
  inverse = k.inverse();
  return inverse.allFinite();
}

// K's blocks for tree t: each joint's pivot (its moving sides) and its coupling to the joints
// in its `up` list (on its parent body).
void assembleTree(RigidBodyData& D, std::size_t t) {
  JointTrees& T = D.jointTrees;
  for (std::uint32_t e = T.treeOffsets[t]; e < T.treeOffsets[t + 1]; ++e) {
    const JointConstraint& c = D.jointConstraints[T.joints[e]];
    Mat3& pivot = T.pivot[e];
    pivot.setZero();
    for (int side : {0, 1})
      if (moving(D, sideBody(c, side)))
        pivot += bodyCoupling(D.solverBodies[std::size_t(sideBody(c, side))], sideArm(c, side),
                              sideArm(c, side));
    const int p = T.parentSide[e];
    const SolverBody& parent = D.solverBodies[std::size_t(sideBody(c, p))];
    for (std::uint32_t u = T.upOffsets[e]; u < T.upOffsets[e + 1]; ++u) {
      const JointConstraint& k = D.jointConstraints[T.joints[T.up[u]]];
      const int kSide = k.bodyA == sideBody(c, p) ? 0 : 1;
      const Real sign = kSide == p ? 1 : -1;  // s_k s_e
      T.coupling[u] = sign * bodyCoupling(parent, sideArm(k, kSide), sideArm(c, p));
    }
  }
}

// Block L D L^T of tree t's K, eliminating from the last joint of the walk to the first; false
// where a pivot is lost to rounding.
bool factorTree(RigidBodyData& D, std::size_t t) {
  JointTrees& T = D.jointTrees;
  assembleTree(D, t);
  for (std::uint32_t e = T.treeOffsets[t + 1]; e-- > T.treeOffsets[t];) {
    if (!invertPivot(T.pivot[e], T.pivotInverse[e])) return false;
    const std::uint32_t first = T.upOffsets[e], last = T.upOffsets[e + 1];
    for (std::uint32_t u = first; u < last; ++u)
      T.lower[u] = product(T.coupling[u], T.pivotInverse[e]);
    // The Schur complement on the remaining joints, all on e's parent body.
    for (std::uint32_t u = first; u < last; ++u) {
      const std::uint32_t k = T.up[u];
      T.pivot[k] -= productTransposed(T.lower[u], T.coupling[u]);
      for (std::uint32_t w = first; w < last; ++w) {
        const std::uint32_t l = T.up[w];
        if (l >= k) continue;
        std::uint32_t v = T.upOffsets[k];
        while (v < T.upOffsets[k + 1] && T.up[v] != l) ++v;
        if (v == T.upOffsets[k + 1]) return false;  // not on one body: not a tree's pattern
        T.coupling[v] -= productTransposed(T.lower[w], T.coupling[u]);
      }
    }
  }
  return true;
}

// The anchors' relative velocity J v of a point joint.
Vec3 anchorVelocity(const RigidBodyData& D, const JointConstraint& c) {
  Vec3 v = Vec3::Zero();
  if (c.bodyB >= 0) {
    const SolverBody& b = D.solverBodies[std::size_t(c.bodyB)];
    v += b.v + b.w.cross(c.lock.armB);
  }
  if (c.bodyA >= 0) {
    const SolverBody& a = D.solverBodies[std::size_t(c.bodyA)];
    v -= a.v + a.w.cross(c.lock.armA);
  }
  return v;
}

// An impulse on the joint's anchors, to its moving bodies.
void applyImpulse(RigidBodyData& D, const JointConstraint& c, const Vec3& lambda) {
  if (moving(D, c.bodyB)) {
    SolverBody& b = D.solverBodies[std::size_t(c.bodyB)];
    b.v += b.invMass * lambda;
    b.w += times(b.invInertia, c.lock.armB.cross(lambda));
  }
  if (moving(D, c.bodyA)) {
    SolverBody& a = D.solverBodies[std::size_t(c.bodyA)];
    a.v -= a.invMass * lambda;
    a.w -= times(a.invInertia, c.lock.armA.cross(lambda));
  }
}

// x = K^-1 rhs for tree t in place, by its factor.
void solveFactored(JointTrees& T, std::size_t t) {
  const std::uint32_t begin = T.treeOffsets[t], end = T.treeOffsets[t + 1];
  for (std::uint32_t e = end; e-- > begin;)
    for (std::uint32_t u = T.upOffsets[e]; u < T.upOffsets[e + 1]; ++u)
      T.rhs[T.up[u]] -= times(T.lower[u], T.rhs[e]);
  for (std::uint32_t e = begin; e < end; ++e) T.rhs[e] = times(T.pivotInverse[e], T.rhs[e]);
  for (std::uint32_t e = begin; e < end; ++e)
    for (std::uint32_t u = T.upOffsets[e]; u < T.upOffsets[e + 1]; ++u)
      T.rhs[e] -= transposedTimes(T.lower[u], T.rhs[T.up[u]]);
}

// One exact pass over tree t: x = K^-1 (J v + bias) by the factor, then each joint's impulse
// dlambda = -massScale x - impulseScale lambda_acc.
void solveTree(RigidBodyData& D, std::size_t t, const Softness& soft) {
  JointTrees& T = D.jointTrees;
  const std::uint32_t begin = T.treeOffsets[t], end = T.treeOffsets[t + 1];
  for (std::uint32_t e = begin; e < end; ++e) {
    const JointConstraint& c = D.jointConstraints[T.joints[e]];
    const Vec3 bias(jointBias(soft, c.lock.error(0)), jointBias(soft, c.lock.error(1)),
                    jointBias(soft, c.lock.error(2)));
    T.rhs[e] = anchorVelocity(D, c) + bias;
  }
  solveFactored(T, t);
  for (std::uint32_t e = begin; e < end; ++e) {
    JointConstraint& c = D.jointConstraints[T.joints[e]];
    const Vec3 delta =
        -soft.massScale * T.rhs[e] - soft.impulseScale * c.lock.impulse.head<3>();
    c.lock.impulse.head<3>() += delta;
    applyImpulse(D, c, delta);
  }
}

// Tree t's joints refreshed for `stamp` and its K factored; where the factor fails, its
// joints left to the colours' passes, with their K^-1.
void prepareTree(RigidBodyData& D, std::size_t t, int stamp) {
  JointTrees& T = D.jointTrees;
  T.stamps[t] = stamp;
  for (std::uint32_t e = T.treeOffsets[t]; e < T.treeOffsets[t + 1]; ++e)
    refreshJoint(D, D.jointConstraints[T.joints[e]], D.solverBodies, stamp, false);
  T.factored[t] = factorTree(D, t);
  for (std::uint32_t e = T.treeOffsets[t]; e < T.treeOffsets[t + 1]; ++e) {
    JointConstraint& c = D.jointConstraints[T.joints[e]];
    c.inTree = T.factored[t] != 0;
    if (c.inTree) continue;
    c.stamp = -1;  // the colours' passes solve it: its K^-1 too
    refreshJoint(D, c, D.solverBodies, stamp);
  }
}

// v scaled down to length `limit` when longer.
Vec3 clampedNorm(const Vec3& v, Real limit) {
  const Real length = v.norm();
  return length > limit ? Vec3(v * (limit / length)) : v;
}

// A displacement of the anchors (the position analogue of an impulse): the bodies move by
// M^-1 J^T lambda.
void displace(RigidBodyData& D, const JointConstraint& c, const Vec3& lambda) {
  const auto move = [](SolverBody& body, const Vec3& linear, const Vec3& angular) {
    body.dp += linear;
    body.dq = integrateRotation(body.dq, angular, 1);
    body.dR = body.dq.toRotationMatrix();
  };
  if (moving(D, c.bodyB)) {
    SolverBody& b = D.solverBodies[std::size_t(c.bodyB)];
    move(b, b.invMass * lambda, times(b.invInertia, c.lock.armB.cross(lambda)));
  }
  if (moving(D, c.bodyA)) {
    SolverBody& a = D.solverBodies[std::size_t(c.bodyA)];
    move(a, -a.invMass * lambda, -times(a.invInertia, c.lock.armA.cross(lambda)));
  }
}

}  // namespace

void buildJointTrees(RigidBodyData& D) {
  JointTrees& T = D.jointTrees;
  T.treeOffsets.clear();
  T.joints.clear();
  T.parentSide.clear();
  T.upOffsets.clear();
  T.up.clear();
  for (JointConstraint& c : D.jointConstraints) c.inTree = false;
  if (markEligible(D) < 2) return;
  indexJointsByBody(D);
  const std::size_t nb = D.solverBodies.size();
  T.visited.assign(nb, 0);
  T.entryOf.assign(D.jointConstraints.size(), kNone);
  countBodyEdges(D);
  T.treeOffsets.push_back(0);
  T.alone.clear();
  // A component's union-find root is its smallest body (the smaller root wins each union).
  for (std::uint32_t r = 0; r < nb; ++r) {
    if (T.componentSize[r] < 2 || T.bodies.find(r) != r) continue;
    T.alone.push_back(walkTree(D, r));
    T.treeOffsets.push_back(std::uint32_t(T.joints.size()));
  }
  T.upOffsets.push_back(0);
  for (std::size_t e = 0; e < T.joints.size(); ++e) {
    const JointConstraint& c = D.jointConstraints[T.joints[e]];
    const int parent = sideBody(c, T.parentSide[e]);
    for (std::uint32_t i = T.bodyJointOffsets[std::size_t(parent)];
         i < T.bodyJointOffsets[std::size_t(parent) + 1]; ++i) {
      const std::uint32_t other = T.entryOf[T.bodyJoints[i]];
      if (other < e) T.up.push_back(other);
    }
    T.upOffsets.push_back(std::uint32_t(T.up.size()));
  }
  T.coupling.resize(T.up.size());
  T.lower.resize(T.up.size());
  T.pivot.resize(T.joints.size());
  T.pivotInverse.resize(T.joints.size());
  T.rhs.resize(T.joints.size());
  T.stamps.assign(T.treeCount(), -1);
  T.factored.assign(T.treeCount(), 0);
}

void solveJointTrees(RigidBodyData& D, const JointPass& pass, bool firstPass,
                     StepWorkers& workers) {
  JointTrees& T = D.jointTrees;
  // Passes after the first with every tree alone: nothing to do, and no meeting of the workers.
  if (!firstPass && std::all_of(T.alone.begin(), T.alone.end(), [](auto a) { return a != 0; }))
    return;
  workers.parallelFor(
      T.treeCount(),
      [&](std::size_t first, std::size_t last) {
        for (std::size_t t = first; t < last; ++t) {
          if (T.stamps[t] != pass.stamp) prepareTree(D, t, pass.stamp);
          if (T.factored[t] && (firstPass || !T.alone[t])) solveTree(D, t, pass.rigid);
        }
      },
      4);
}

}  // namespace inertia::detail

namespace inertia::detail {

void projectJointTrees(RigidBodyData& D, const JointPass& pass, StepWorkers& workers) {
  const int stamp = pass.stamp;
  // No joint's anchors move more in a substep than its bias would move them (kMaxJointBias):
  // a joint created with its anchors far apart draws them together over several substeps, as
  // the per-joint passes do, instead of carrying its bodies across the scene at once.
  const Real maxStep = kMaxJointBias * pass.h;
  JointTrees& T = D.jointTrees;
  workers.parallelFor(
      T.treeCount(),
      [&](std::size_t first, std::size_t last) {
        for (std::size_t t = first; t < last; ++t) {
          prepareTree(D, t, stamp);
          if (!T.factored[t]) continue;
          for (std::uint32_t e = T.treeOffsets[t]; e < T.treeOffsets[t + 1]; ++e)
            T.rhs[e] =
                clampedNorm(D.jointConstraints[T.joints[e]].lock.error.head<3>(), maxStep);
          solveFactored(T, t);
          for (std::uint32_t e = T.treeOffsets[t]; e < T.treeOffsets[t + 1]; ++e)
            displace(D, D.jointConstraints[T.joints[e]], -T.rhs[e]);
          // The anchors and errors at the positions projected; the factor stays (below).
          for (std::uint32_t e = T.treeOffsets[t]; e < T.treeOffsets[t + 1]; ++e) {
            JointConstraint& c = D.jointConstraints[T.joints[e]];
            c.stamp = -1;
            refreshJoint(D, c, D.solverBodies, stamp, false);
          }
        }
      },
      4);
}

}  // namespace inertia::detail
