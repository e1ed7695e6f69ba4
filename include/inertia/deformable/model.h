// The mass-spring model of a deformable (seed 002, "Mass-Spring System"): vertices with mass,
// position and velocity, damped springs between them, triangles for surfaces, pinned vertices.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "inertia/core/types.h"

namespace inertia {

/// What a spring resists (seed 002: hair needs bending springs, cloth structural, shear and
/// bending springs). The force law is the same; the kind tells tools and scene files apart.
enum class SpringKind : std::uint8_t {
  Stretch,  ///< Structural: along a rope, the edges of a cloth grid or a lattice.
  Shear,    ///< Diagonals of a cloth cell or a lattice cell.
  Bend,     ///< Skips a vertex (i to i + 2): resists folding.
};

/// A damped spring between vertices a and b (Hooke, with damping along the spring):
///     F_a = -(k (l - L) + c (v_a - v_b) . u) u,   F_b = -F_a,
/// with d = x_a - x_b, l = |d|, u = d / l.
struct Spring {
  std::uint32_t a = 0, b = 0;  ///< Vertex indices, a != b.
  Real restLength = 1;         ///< L (m), > 0.
  Real stiffness = 100;        ///< k (N/m), >= 0.
  Real damping = 0;            ///< c (N s/m), >= 0.
  SpringKind kind = SpringKind::Stretch;
};

/// A deformable's initial state and structure, as the generators (generators.h) build it.
struct MassSpringModel {
  std::vector<Vec3> positions;   ///< m, one per vertex.
  std::vector<Vec3> velocities;  ///< m/s; empty means at rest.
  std::vector<Real> masses;      ///< kg, > 0, one per vertex.
  std::vector<Spring> springs;
  /// Surface triangles, counter-clockwise seen from outside (a cloth: from its +y side).
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Vertices held where they are (velocity zero) whatever the forces.
  std::vector<std::uint32_t> pinned;

  std::size_t vertexCount() const { return positions.size(); }
};

/// Throws InvalidArgument naming the first bad item: sizes that differ, non-finite values,
/// masses <= 0, springs joining a vertex to itself or one that does not exist, rest lengths <= 0,
/// negative stiffness or damping, triangles or pins naming missing vertices.
void validate(const MassSpringModel& model);

}  // namespace inertia
