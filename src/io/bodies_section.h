// The "materials" and "bodies" sections of scene files (DESIGN.md section 4), with the
// generators ("pyramid", "tower", "wall", "grid", "rain") that expand to many bodies and
// "ragdoll", which expands to bodies and the joints between them.
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

/// A shape's or body's "material": a name from `table` or an inline object; absent gives
/// `fallback`.
Material readMaterialRef(const Node& owner, const MaterialTable& table, const Material& fallback);

/// Reads one entry of "bodies" (a body or a generator) and appends what it describes to
/// `scene.bodies`, and a jointed generator's joints to `scene.joints` (their pointer the
/// entry's, their bodies indices into scene.bodies).
void readBodies(const Node& n, std::size_t index, const MaterialTable& materials, Scene& scene);

}  // namespace inertia::io::detail
