// Internal: the contacts that touch a driven body (multibody.h), a solver stage beside the
// coloured contacts and joints (solver_stages.h). Their rows are the contacts' (a normal row per
// point with the same soft or Baumgarte bias, two friction rows clamped to Coulomb's disc,
// restitution after the substeps, warm starting), but a side on a driven body answers through
// its group's response: its velocity is the point's, its effective mass comes from
// W = J M^-1 J^T, and its impulses change every member's velocity. Every link of a tree shares
// the reduced coordinates, so these rows run in sequence, in contact order, after each pass's
// colours: the same at any thread count. Rolling and spinning friction are not applied to them.
//
// The joints with a driven body on a side (RigidBodyData::multibodyJoints: joints of any type
// without limits, motors, springs or friction, which close loops through articulations) are
// their locked rows (lockedRows, as the coloured joints'), solved as one block before the
// contacts through each side's 6 x 6 response (a driven side's frame at its anchor, with the
// coupling where both sides are in one tree): their velocity K-solved to zero with the joints'
// softness (JointPass: soft in the soft step, Baumgarte's feedback for pgs, none in the
// relaxation), warm started from last step's impulses, their force and torque reported and
// checked against the break thresholds as any joint's.
#pragma once

#include "joint_solver.h"
#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

/// This step's driven contacts (RigidBodyData::multibodyContacts already lists them): each
/// group's beginStep, the points, their effective masses and last step's impulses.
void prepareMultibodyContacts(RigidBodyData& D, const DynamicsSettings& s, const Softness& soft,
                              const Softness& staticSoft);
/// The groups' substep velocity and position updates (the groups in parallel).
void integrateMultibodyVelocities(RigidBodyData& D, Real h, StepWorkers& workers);
void integrateMultibodyPositions(RigidBodyData& D, Real h, StepWorkers& workers);
/// Applies the accumulated impulses again (a substep's warm start).
void warmStartMultibodyContacts(RigidBodyData& D);
/// The joints' rows made for position update `stamp` (JointPass::stamp) when they were not
/// yet, then their accumulated impulses applied again.
void warmStartMultibodyJoints(RigidBodyData& D, int stamp);
/// One pass over the driven joints' rows.
void solveMultibodyJoints(RigidBodyData& D, const JointPass& pass);
/// Their impulses into the joints (for the next step's warm start), their forces, and whether
/// they broke (storeJoints breaks them with the others).
void storeMultibodyJoints(RigidBodyData& D, Real h);
/// One pass over the rows.
void solveMultibodyContacts(RigidBodyData& D, const BiasMode& mode);
/// One pass over each group's own rows (an articulation's joint rows), in group order, after
/// the contacts' pass: the joints answer the contacts' impulses in the same iteration.
void solveMultibodyRows(RigidBodyData& D);
/// Newton's impact law after the substeps, then the impulses into the contacts.
void restituteMultibodyContacts(RigidBodyData& D, Real threshold);
void storeMultibodyContacts(RigidBodyData& D);

}  // namespace inertia::detail
