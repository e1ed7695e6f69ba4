// Touching the simulation with the mouse: picking a body by a ray (World::castRay), dragging
// it with a damped spring towards the mouse, and shooting balls from the camera. No GL here.
#pragma once

#include <optional>

#include "inertia/collision/queries.h"
#include "inertia/world/world.h"

namespace inertia::viewer {

/// A damped spring from a point of a body to a target point, as a mouse joint: its stiffness
/// and damping scale with the body's mass so every body follows at the same `frequency`.
struct MouseSpring {
  BodyId body{};
  Vec3 localAnchor = Vec3::Zero();  ///< Grabbed point in the body's frame (m).
  Vec3 target = Vec3::Zero();       ///< Where the mouse is (m, world).
  Real distance = 0;                ///< Distance (m) from the eye to the grabbed point.
  Real frequency = 3;               ///< Undamped natural frequency (Hz).
  Real dampingRatio = Real(0.7);
  Real maxAcceleration = 200;  ///< Force limit over mass (m/s^2).
  Real angularDamping = 8;     ///< Rate (1/s) at which spinning is damped while held.
};

/// The dynamic body the ray hits first, held at the hit point; nullopt when the ray hits
/// nothing or a static or kinematic body. `ray.direction` need not be unit.
std::optional<MouseSpring> pickBody(const World& world, const Ray& ray);

/// Where the held point should go for a mouse ray: the point of the ray at the grab distance.
Vec3 springTarget(const MouseSpring& spring, const Ray& ray);

/// The spring's force (N) on the body at its anchor, F = k (target - anchor) - c v_anchor with
/// k = m (2 pi f)^2 and c = 2 m zeta (2 pi f), clamped to m maxAcceleration.
Vec3 springForce(const World& world, const MouseSpring& spring);

/// Applies the spring's force at the anchor and its spin damping for the next step (a
/// Playback::beforeStep). Does nothing when the body no longer exists.
void applySpring(World& world, const MouseSpring& spring);

/// A ball to shoot.
struct BallSettings {
  Real radius = Real(0.25);  ///< m
  Real speed = 30;           ///< m/s along the ray
  Real density = 2000;       ///< kg/m^3
};

/// Adds a dynamic sphere at the ray's origin moving along its direction at ball.speed, marked as
/// a bullet (continuous collision). Returns its id.
BodyId shootBall(World& world, const Ray& ray, const BallSettings& ball = {});

}  // namespace inertia::viewer
