// The "particle_systems" section of scene files (DESIGN.md section 4).
#pragma once

#include <vector>

#include "inertia/io/scene.h"
#include "json_reader.h"

namespace inertia::io::detail {

/// Reads one entry of "particle_systems"; `index` names it when it has no "name". `bodies`
/// are the scene's (already read): emitters' "attach_to" names one of them.
/// Reads one force field ({"type": "gravity", ...}); particle systems and deformables share them.
ForceField readField(const Node& n);

ParticleSystemDesc readParticleSystem(const Node& n, std::size_t index, const std::vector<BodyDesc>& bodies);

}  // namespace inertia::io::detail
