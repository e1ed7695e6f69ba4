// Internal: the solver stages of a step (Box2D v3's, in 3D), each a function a reader can find:
//   prepareContacts      solver bodies, contact constraints, their colouring and bundles;
//   then per substep:
//     integrateVelocities  gravity, forces, damping, the implicit gyroscopic term;
//     warmStart            last step's impulses applied again;
//     solve                `iterations` passes with the position bias;
//     integratePositions   the bodies' motion since the step's start;
//     relax                soft_step's passes without the bias;
//   and after the substeps:
//     restitution          Newton's impact law;
//     storeImpulses        into the contacts, for the next step's warm start and the user.
// Contacts run through the SIMD bundles (contact_solver.h) colour by colour on the step's
// workers; the LCP solvers (lcp_contact.h) take the place of warmStart and solve per island.
#pragma once

#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

/// Builds the solver bodies (awake dynamic and kinematic bodies in a contact; the rest fly
/// free), the contact constraints, their colouring and the bundles.
void prepareContacts(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers);
/// Runs the substeps and stores the impulses. Returns the seconds spent integrating.
double solveSubsteps(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers);

}  // namespace inertia::detail
