// Scene builders: the stacks, walls, piles and rains that tests, benchmarks, the scene-file
// generators and the viewer's samples share (one place, as Box2D's shared/ folder).
// They return plain descriptions, so a benchmark can build the same scene in a peer engine.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "inertia/dynamics/body.h"
#include "inertia/geometry/shapes.h"
#include "inertia/world/world.h"

namespace inertia {

/// A shape of a body description.
struct ShapeDesc {
  Shape shape = Sphere{Real(0.5)};
  Material material{};
  Transform local{};  ///< Relative to the body's origin.
  /// Drawing colour (rgb, 0..1) from the scene's "color"; the simulation ignores it.
  std::optional<Vec3> color{};
};

/// A body with its shapes, ready to add to a world.
struct BodyDesc {
  BodySettings settings{};
  std::vector<ShapeDesc> shapes;
};

/// Adds a described body to `world` (InvalidArgument as createBody / addShape).
BodyId addBody(World& world, const BodyDesc& desc);

/// A 2D-style pyramid (a wall) of boxes in the x-y plane: `base` boxes in the bottom row, one
/// fewer per row above, base (base + 1) / 2 in all. `origin` is the centre of the bottom face
/// of the bottom row; `gap` (m) separates neighbours in a row.
struct PyramidSettings {
  int base = 10;
  Vec3 halfExtents = Vec3::Constant(Real(0.5));
  Vec3 origin = Vec3::Zero();
  Real gap = 0;
  Material material{};
};
std::vector<BodyDesc> pyramid(const PyramidSettings& settings);

/// A single column of `height` boxes standing on `origin` (centre of the bottom face).
struct TowerSettings {
  int height = 10;
  Vec3 halfExtents = Vec3::Constant(Real(0.5));
  Vec3 origin = Vec3::Zero();
  Material material{};
};
std::vector<BodyDesc> tower(const TowerSettings& settings);

/// A brick wall of `rows` x `columns` boxes in the x-y plane, alternate rows shifted by half
/// a brick when `staggered`; `origin` is the centre of its bottom face.
struct WallSettings {
  int rows = 5;
  int columns = 10;
  Vec3 halfExtents = Vec3(Real(0.5), Real(0.25), Real(0.25));
  Vec3 origin = Vec3::Zero();
  bool staggered = true;
  Material material{};
};
std::vector<BodyDesc> wall(const WallSettings& settings);

/// counts.x x counts.y x counts.z copies of `shape` on a lattice of `spacing` (m), the first at
/// `origin`, y up (a pile when dropped). Orientation identity.
struct GridSettings {
  std::array<int, 3> counts{10, 10, 10};
  Vec3 spacing = Vec3::Constant(Real(1.1));
  Vec3 origin = Vec3::Zero();
  Shape shape = Sphere{Real(0.5)};
  Material material{};
};
std::vector<BodyDesc> grid(const GridSettings& settings);

/// `count` copies of `shape` at uniformly random positions in [lower, upper] with uniformly
/// random orientations (Shoemake's method), from a seeded generator (same seed, same scene).
struct RainSettings {
  int count = 100;
  Vec3 lower = Vec3(-5, 5, -5);
  Vec3 upper = Vec3(5, 15, 5);
  Shape shape = Box{Vec3::Constant(Real(0.5))};
  Material material{};
  std::uint64_t seed = 1;
};
std::vector<BodyDesc> rain(const RainSettings& settings);

}  // namespace inertia
