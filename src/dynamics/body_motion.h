// Internal: the bodies' motion at the end of a step. Bodies in the solver take its velocities
// and motion; kinematic bodies move by their velocities; free dynamic bodies fly with the
// world's ode method and the momentum-conserving rotation splitting (integrate.h). Then the
// sleep timers. `beside(D)` runs on one worker meanwhile: a stage that shares no data with
// the bodies' motion (the contact events).
#pragma once

#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

void finalizeBodies(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers,
                    void (*beside)(RigidBodyData&));

}  // namespace inertia::detail
