// Internal: the contact manager, the first stages of a step.
//   - updateBroadPhase: moves the proxies of awake bodies (boxes swept over the step for fast
//     bodies) in the broad phase (collision::BroadPhase), keeps last step's candidate pairs whose
//     fat boxes still overlap, queries the proxies whose fat box changed, and adds the static
//     planes' pairs;
//   - updateContacts: the narrow phase (collide() with a speculative margin, or last step's
//     manifold carried along while the pair barely moved), the contacts of resting bodies kept,
//     and the warm start's impulses matched to last step's points by (shapes, sub-shapes,
//     feature id), with a stage that shares no data with the matching (the islands) beside it;
//   - reportContactEvents: pairs that began or stopped touching.
#pragma once

#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

void updateBroadPhase(RigidBodyData& D, Real dt, const ContactTuning& tuning, StepWorkers& workers);
void updateContacts(RigidBodyData& D, Real dt, const ContactTuning& tuning, StepWorkers& workers,
                    void (*beside)(RigidBodyData&));
void reportContactEvents(RigidBodyData& D);

}  // namespace inertia::detail
