// The "deformables" section of scene files (DESIGN.md section 4).
#pragma once

#include "inertia/io/scene.h"
#include "json_reader.h"

namespace inertia::io::detail {

/// Reads one entry of "deformables"; `index` names it when it has no "name".
DeformableDesc readDeformable(const Node& n, std::size_t index,
                              const std::vector<BodyDesc>& bodies);

}  // namespace inertia::io::detail
