// The "articulations" section of scene files (DESIGN.md section 4): reduced-coordinate trees
// with inline links or from a URDF file (io/urdf.h).
#pragma once

#include "bodies_section.h"
#include "inertia/io/scene.h"
#include "json_reader.h"

namespace inertia::io::detail {

/// Reads one entry of "articulations"; `index` names it when it has no "name".
ArticulationDesc readArticulation(const Node& n, std::size_t index, const MaterialTable& materials);

}  // namespace inertia::io::detail
