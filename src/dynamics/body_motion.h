// Internal: the bodies' speeds at the start of a step, and their motion at its end. Bodies in
// the solver take its velocities and motion; kinematic bodies move by their velocities; free
// dynamic bodies fly with the world's ode method and the momentum-conserving rotation
// splitting (integrate.h). Then the sleep timers. `beside(D)` runs on one worker meanwhile: a
// stage that shares no data with the bodies' motion (the contact events).
#pragma once

#include "rigid_body_data.h"
#include "step_workers.h"

namespace inertia::detail {

/// Scales every awake dynamic body's velocities down to its speed caps: an impulse or a velocity
/// given between steps (applyImpulse, setLinearVelocity, a deformable's contacts) can leave
/// any, and the broad phase's swept boxes and the warm start overflowed float from there.
void capStartSpeeds(RigidBodyData& D, StepWorkers& workers);

void finalizeBodies(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers,
                    void (*beside)(RigidBodyData&));

}  // namespace inertia::detail
