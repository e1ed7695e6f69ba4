// Handles: small values {index, generation}; all-zero is null (Box2D, Jolt, Rapier).
#pragma once

#include <cstdint>

namespace inertia {

/// A handle to an object owned by a World. `generation` starts at 1, so a default-constructed
/// id is null, and a handle to a removed object is detected (World::isValid) even after its
/// slot is reused.
template <class Tag>
struct Id {
  std::uint32_t index = 0;
  std::uint32_t generation = 0;

  bool isNull() const { return generation == 0; }
  friend bool operator==(const Id&, const Id&) = default;
};

// The handles are declared here, below every layer, so that a layer can name an object of a
// higher one (an emitter riding on a body) without including it.
struct BodyTag;
/// A rigid body in a World.
using BodyId = Id<BodyTag>;
struct ShapeTag;
/// A shape attached to a body.
using ShapeId = Id<ShapeTag>;
struct JointTag;
/// A joint between two bodies (or a body and the world).
using JointId = Id<JointTag>;
struct ParticleSystemTag;
/// A particle system in a World.
using ParticleSystemId = Id<ParticleSystemTag>;
struct DeformableTag;
/// A mass-spring deformable in a World.
using DeformableId = Id<DeformableTag>;
struct ArticulationTag;
/// A reduced-coordinate articulation in a World.
using ArticulationId = Id<ArticulationTag>;

}  // namespace inertia
