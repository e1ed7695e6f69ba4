// Continuous collision of convex shapes: shape casts (translation only) and the time of impact
// of shapes that translate and rotate, by conservative advancement. On bare colliders and
// transforms, without a world.
//
// Convex shapes only: sphere, capsule, box, cylinder, hull (any other type throws
// InvalidArgument). Inputs must be finite with unit quaternions; results never NaN.
#pragma once

#include <optional>

#include "inertia/collision/collider.h"
#include "inertia/core/types.h"

namespace inertia {

/// Where a cast shape first touches another.
struct ShapeCastHit {
  /// Fraction of the translation at which the shapes touch, in [0, 1]; 0 when they overlap
  /// (or are within the tolerance) at the start.
  Real fraction = 0;
  Vec3 point = Vec3::Zero();  ///< Contact point on B's surface (m, world), A moved to the hit.
  /// Unit normal of B's surface at the hit, facing A (world): the direction that pushes A out.
  /// At an initial overlap, the direction that separates A from B fastest.
  Vec3 normal = Vec3::UnitY();
};

/// How castShape works.
struct ShapeCastSettings {
  /// The cast stops when the shapes are within this distance (m), > 0: the hit fraction is
  /// conservative (the shapes are 0 .. tolerance apart there) and short of the exact one by at
  /// most tolerance / (closing speed along the normal per unit fraction). In float, shapes
  /// much larger than the gap (a 100 m ground box) may stop short by more: the support planes
  /// through far corners tilt with the rounding of the search direction (~eps * size^2 / gap).
  Real tolerance = Real(1e-4);
};

/// Sweeps convex `a` from `poseA` along `translationA` (m, world; no rotation) against convex
/// `b` fixed at `poseB`, and returns the first contact, by GJK ray casting against the
/// Minkowski difference (van den Bergen, "Ray casting against general convex objects with
/// application to continuous collision detection", 2004). Nothing when A's path misses B.
std::optional<ShapeCastHit> castShape(const Collider& a, const Transform& poseA,
                                      const Vec3& translationA, const Collider& b,
                                      const Transform& poseB,
                                      const ShapeCastSettings& settings = {});

/// The motion of a shape over the unit time interval [0, 1]. The origin of the shape's frame
/// moves linearly from start.p to end.p; the rotation turns at constant angular velocity about
/// that origin (slerp along the shortest arc from start.q to end.q, so a sweep cannot express
/// turns of more than half a revolution). at(t) gives the pose at time t.
struct Sweep {
  Transform start;
  Transform end;

  /// The pose at t in [0, 1].
  Transform at(Real t) const;
  /// Velocity of the frame's origin (m per unit t).
  Vec3 linearVelocity() const { return end.p - start.p; }
  /// Angular velocity (rad per unit t, world frame): end.q = exp(angularVelocity) * start.q.
  Vec3 angularVelocity() const;
};

/// How timeOfImpact works.
struct ToiSettings {
  /// Separation to stop at (m), >= 0: the shapes end this far apart (a solver's slop).
  Real targetSeparation = 0;
  /// Accepted excess over the target (m), > 0: the returned separation lies in
  /// [targetSeparation, targetSeparation + tolerance] up to rounding.
  Real tolerance = Real(1e-3);
  /// Cap on advancement steps; reaching it reports ToiStatus::Failed.
  int maxIterations = 64;
};

enum class ToiStatus {
  Hit,          ///< The shapes reach the target separation at t.
  Separated,    ///< They stay farther apart than the target over the whole interval (t = 1).
  Overlapping,  ///< They overlap at the start (t = 0; normal and points from penetration).
  Failed,       ///< Iteration cap reached; t is still conservative (no contact before it).
};

/// The answer of timeOfImpact.
struct ToiResult {
  ToiStatus status = ToiStatus::Separated;
  Real t = 1;  ///< Time of impact in [0, 1] (fraction of the sweeps).
  /// Signed distance of the shapes (m) at t; for Separated, at the last time measured.
  Real separation = 0;
  Vec3 normal = Vec3::UnitY();  ///< Unit, from A to B, with `separation` (world).
  Vec3 pointA = Vec3::Zero();   ///< Closest point on A, with `separation` (m, world).
  Vec3 pointB = Vec3::Zero();   ///< Closest point on B, with `separation` (m, world).
  int iterations = 0;           ///< Distance queries made.
};

/// The first time in [0, 1] at which convex `a` moving by `sweepA` and `b` moving by `sweepB`
/// come within the target separation, by conservative advancement (Mirtich, "Impulse-based
/// dynamic simulation of rigid body systems", 1996, and Mirtich 2000): from the current
/// distance d and normal n (GJK/EPA), advance by dt = (d - aim) / mu, where
///   mu = (vA - vB) . n + |omegaA| rA + |omegaB| rB
/// bounds the closing speed of the gap along n (r = the farthest point of a shape from its
/// frame's origin). The gap along the fixed n cannot shrink faster than mu, so every step lands
/// before contact: the returned t never passes the first contact, and at t the separation is
/// within the tolerance of the target. mu <= 0 means the gap along n never shrinks: Separated.
ToiResult timeOfImpact(const Collider& a, const Sweep& sweepA, const Collider& b,
                       const Sweep& sweepB, const ToiSettings& settings = {});

}  // namespace inertia
