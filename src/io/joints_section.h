// The "joints" section of scene files (DESIGN.md section 4): ball, hinge, slider, weld and
// distance joints between the scene's bodies, named by their "name", or a body and the world.
#pragma once

#include <vector>

#include "inertia/io/scene.h"
#include "json_reader.h"

namespace inertia::io::detail {

/// Reads one entry of "joints"; `index` names it when it has no "name". `bodies` are the
/// scene's (already read): "body_a" and "body_b" name one of them each.
JointDesc readJoint(const Node& n, std::size_t index, const std::vector<BodyDesc>& bodies);

}  // namespace inertia::io::detail
