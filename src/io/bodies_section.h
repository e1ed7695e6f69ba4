// The "materials" and "bodies" sections of scene files (DESIGN.md section 4), with the
// generators ("pyramid", "tower", "wall", "grid", "rain") that expand to many bodies.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "inertia/io/scene.h"
#include "json_reader.h"

namespace inertia::io::detail {

using MaterialTable = std::map<std::string, Material, std::less<>>;

/// Reads "materials": an object of name -> material.
MaterialTable readMaterials(const Node& n);

/// Reads one entry of "bodies" (a body or a generator) and appends what it describes.
void readBodies(const Node& n, std::size_t index, const MaterialTable& materials,
                std::vector<BodyDesc>& out);

}  // namespace inertia::io::detail
