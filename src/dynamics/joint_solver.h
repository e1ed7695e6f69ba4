// Internal: the joints' solver stage, beside the contacts' in each substep (solver_stages.h):
//   addJointEdges        this step's joints (an awake dynamic body on either side), their
//                        solver bodies and graph edges;
//   prepareJoints        their constraints in colour order: anchors and frames at the step's
//                        start;
//   warmStartJoint / solveJoint, per joint, colour by colour with the contacts;
//   storeJoints          impulses kept for the next step, forces, and breaking.
// Joints are soft constraints in the soft step (Box2D v3: twice the contact stiffness, damping
// ratio 2, relaxed without bias like the contacts), rigid rows with Baumgarte's feedback for
// pgs and the LCP solvers; with the LCP solvers their rows join their island's LCP
// (appendJointLcpRows).
#pragma once

#include <span>

#include "rigid_body_data.h"

namespace inertia::detail {
struct LcpRow;
}

namespace inertia::detail {

/// How a pass treats a joint's position error.
struct JointPass {
  Softness rigid{};  ///< The locked rows' coefficients (soft, Baumgarte or relax).
  Real h = 0;        ///< Substep (s).
  Real invH = 0;
  /// The relax pass: springs and servos sit it out. Their implicit rows were solved in the
  /// substep's iterations; solving them again after the position update would make each
  /// substep a different integrator (it restarts the implicit step from the new position),
  /// which measurably slows and damps the spring (joint_solver_test.cpp).
  bool relax = false;
  /// Which position update the pass follows (2 per substep: the solve passes, then the relax
  /// passes): a joint's rows and effective masses are computed once for each.
  int stamp = 0;
};

/// The pass coefficients of the soft step, pgs, and the relaxation.
JointPass jointPass(const DynamicsSettings& s, Real h, bool useBias);

/// A joint's geometry in the current substep.
struct JointFrame {
  Vec3 rA, rB;  ///< Anchors minus the sides' reference points, the centres of mass (m, world).
  Vec3 d;       ///< B's anchor minus A's (m).
  Quat qA, qB;  ///< The joint's frames on A and B (world rotations).
};

/// The joint's locked rows in frame `f` into `lock` (a ball joint's as a point block, rows
/// unset) and their position errors `C`; `fallbackAxis` is a fixed-length distance joint's
/// direction where its anchors meet.
void lockedRows(const JointRecord& j, const JointFrame& f, const Vec3& fallbackAxis, RowBlock& lock,
                RowBlock::Vector& C);

/// Appends this step's joints' graph edges and their records' indices (D.jointEdges,
/// D.edgeJoints), making solver bodies with `slot(bodyIndex)` (after the contacts', so that
/// worlds without joints are unchanged). prepareJoints makes their constraints.
template <class Slot>
void addJointEdges(RigidBodyData& D, Slot slot) {
  D.jointEdges.clear();
  D.edgeJoints.clear();
  for (std::uint32_t ji = 0; ji < D.joints.size(); ++ji) {
    const JointRecord& j = D.joints[ji];
    if (!j.alive || !j.enabled || drivenJoint(D, j)) continue;
    const bool aActive = j.bodyA != kWorldBody && D.bodies[j.bodyA].type == BodyType::Dynamic &&
                         D.bodies[j.bodyA].awake;
    const BodyRecord& b = D.bodies[j.bodyB];
    if (!aActive && !(b.type == BodyType::Dynamic && b.awake)) continue;
    D.jointEdges.push_back({j.bodyA == kWorldBody ? -1 : slot(j.bodyA), slot(j.bodyB)});
    D.edgeJoints.push_back(ji);
  }
}

/// This step's joint constraints, one per joint edge, made in place in the order `order`
/// (edge indices: the colours' order; empty for edge order), with their frames and anchors at
/// the step's start. Made once where they stay, so that the passes read them in sequence
/// without a sort's copy.
void prepareJoints(RigidBodyData& D, std::span<const std::uint32_t> order, StepWorkers& workers);
/// Applies a joint's accumulated impulses to its bodies (rows prepared for `stamp`).
void warmStartJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                    int stamp);
/// The joint's rows and effective masses for position update `stamp`, when not yet made; a
/// plain ball joint's anchors and error only, without its K^-1, when not `withMass` (a joint
/// tree's, which factors K itself).
void refreshJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                  int stamp, bool withMass = true);
/// One pass over a joint's rows (none for a joint its tree solves: JointConstraint::inTree).
void solveJoint(const RigidBodyData& D, JointConstraint& c, std::vector<SolverBody>& bodies,
                const JointPass& pass);
/// The joint's rows for the LCP solvers (rigid with Baumgarte's bias from `pass`, springs and
/// servos soft through a compliance), prepared for `pass.stamp`; each stores its impulse in the
/// joint's accumulated impulses, which also warm start it. Boxed rows take Lemke's friction
/// groups from `groups` on.
void appendJointLcpRows(const RigidBodyData& D, JointConstraint& c,
                        const std::vector<SolverBody>& bodies, const JointPass& pass,
                        std::vector<LcpRow>& rows, int& groups);
/// After the substeps: impulses into the records, forces (impulse over the substep), and the
/// joints whose force or torque passed their threshold break (disabled, reported once).
void storeJoints(RigidBodyData& D, Real h, StepWorkers& workers);

/// A joint's error from the bodies' poses (the joint records' columns).
JointError jointError(const RigidBodyData& D, const JointRecord& j);
/// The joint's free coordinate from the bodies' poses: hinge angle (rad), slider position (m),
/// distance (m), a ball joint's twist (rad); 0 for the others.
Real jointCoordinate(const RigidBodyData& D, const JointRecord& j);
/// Degree of freedom `axis` (0..5: x, y, z along frame A's axes, m; rx, ry, rz as X-Y-Z Euler
/// angles of B's frame relative to A's, rad).
Real axisCoordinate(const RigidBodyData& D, const JointRecord& j, int axis);

}  // namespace inertia::detail
