// Internal: the solver stages of a step (Box2D v3's, in 3D), each a function a reader can find:
//   prepareContacts      solver bodies, contact and joint constraints (joint_solver.h), their
//                        colouring and the contacts' bundles;
//   then per substep:
//     integrateVelocities  gravity, forces, damping, the implicit gyroscopic term;
//     warmStart            last step's impulses applied again;
//     solve                `iterations` passes with the position bias;
//     integratePositions   the bodies' motion since the step's start;
//     relax                soft_step's passes without the bias;
//   and after the substeps:
//     restitution          Newton's impact law;
//     storeImpulses        into the contacts, for the next step's warm start and the user.
// Contacts run through the SIMD bundles (contact_solver.h) and joints one by one, colour by
// colour on the step's workers, a colour's joints beside its contacts; storeImpulses also
// keeps the joints' and breaks those past their threshold. The LCP solvers (lcp_contact.h) take
// the place of the contacts' warmStart and solve per island, after the joints' passes.
// Contacts on driven bodies (an articulation's links, multibody_contacts.h) are out of the
// graph: each pass runs them in sequence after the colours, and the driven groups integrate
// their velocities and positions beside the solver bodies'.
#pragma once

#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

/// Builds the solver bodies (awake dynamic and kinematic bodies in a contact or a joint; the
/// rest fly free), the contact and joint constraints, their colouring and the bundles.
void prepareContacts(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers);
/// Runs the substeps and stores the impulses. Returns the seconds spent integrating.
double solveSubsteps(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers);

}  // namespace inertia::detail
