// Force fields acting on particles ("attractors" in seed 000; forces of seed 003).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <variant>

#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"
#include "inertia/ode/method.h"

namespace inertia {

/// Uniform acceleration g (m/s^2), independent of mass.
struct GravityField {
  Vec3 g = Vec3(0, Real(-9.81), 0);
};

/// Linear (viscous, Stokes) drag F = -k v (k in kg/s). Terminal velocity m g / k.
struct LinearDragField {
  Real k = Real(0.1);
};

/// Quadratic (aerodynamic) drag F = -k |v| v (k in kg/m).
struct QuadraticDragField {
  Real k = Real(0.01);
};

/// Drag towards the wind: F = -k (v - wind) (k in kg/s).
struct WindField {
  Vec3 velocity = Vec3(1, 0, 0);  ///< m/s
  Real k = Real(0.1);
};

/// A vortex about an axis through `center`: the flow rotates rigidly at `angularSpeed` (rad/s,
/// counter-clockwise about `axis`) inside `coreRadius` and with speed falling off as 1/r
/// outside (a Rankine vortex). Particles are dragged towards the flow's velocity u with
/// `tightness` (1/s, a = tightness (u - v) in the plane normal to the axis) and held on their
/// circle by the centripetal acceleration of their own tangential speed v_t (v_t^2 / r towards
/// the axis, v_t capped at the flow's speed omega r so that the pull stays bounded near the
/// axis): a particle at rest spins up without falling inwards, and one moving with the flow
/// circles at exactly the promised angular velocity.
struct VortexField {
  Vec3 center = Vec3::Zero();     ///< m
  Vec3 axis = Vec3::UnitY();      ///< normalised when validated
  Real angularSpeed = 1;          ///< rad/s inside the core
  Real coreRadius = 1;            ///< m, > 0
  Real tightness = 5;             ///< 1/s, >= 0
};

/// How an attractor's strength falls with distance r.
enum class Falloff : std::uint8_t {
  InverseSquare,  ///< a = strength / r^2 (r clamped below at minDistance)
  Linear,         ///< a = strength * r (a spring towards the point)
  Constant,       ///< a = strength
};

/// A point attractor (strength > 0) or repeller (< 0): the seeds' magnet. Acceleration along
/// the direction to `position`, scaled by the falloff; nothing beyond `cutoff` (m).
struct AttractorField {
  Vec3 position = Vec3::Zero();  ///< m
  Real strength = 1;             ///< m^3/s^2 (inverse square), 1/s^2 (linear) or m/s^2
  Falloff falloff = Falloff::InverseSquare;
  Real cutoff = std::numeric_limits<Real>::infinity();  ///< m
  Real minDistance = Real(0.05);  ///< m: the inverse square is clamped inside it
};

/// Curl-noise turbulence (Bridson et al. 2007): a = amplitude * curl(psi)(x / scale, t), with
/// psi a sum of `modes` random Fourier modes per component. The curl of any potential is
/// divergence-free, so the flow stirs without sources or sinks.
struct TurbulenceField {
  Real amplitude = 1;      ///< m/s^2
  Real scale = 1;          ///< m: size of the eddies
  Real speed = 0;          ///< how fast the pattern changes (rad/s of the modes' phases)
  int modes = 8;           ///< 1..64
  std::uint64_t seed = 1;
};

/// What a custom field sees: the live particles of one batch (all spans the same length,
/// vectors as 3 Reals per particle) and where to add accelerations (m/s^2).
struct FieldBatch {
  Real time;                              ///< s
  std::span<const Real> positions;        ///< m
  std::span<const Real> velocities;       ///< m/s
  std::span<const Real> masses;           ///< kg
  std::span<Real> accelerations;          ///< add to it, do not overwrite
  /// The explicit step these accelerations are for (s), or 0 for an implicit one. The drags
  /// (linear, quadratic, wind, a vortex's tightness) act at a rate of at most 1 / step: a drag
  /// whose time constant m / k is shorter than the step made an explicit step overshoot the
  /// terminal velocity, and past k step / m = 2 diverge to NaN (1 g particles in a drag of
  /// 1 kg/s at 60 Hz). Held at 1 / step, the velocity relaxes within about a step; below it
  /// nothing changes. (The terminal velocity under gravity is then g step, above the true
  /// g m / k: the backward_euler integrator holds a stiff drag exactly.)
  Real step = 0;
};

/// FieldBatch::step for a step h of `method`: h; 0 for backward_euler, which holds a stiff drag
/// itself; 2 h for position Verlet, whose velocity (a difference of positions and the last
/// acceleration) makes a drag at rate r diverge past r h = 1 (its amplification at r h = 1 is
/// -1; at 1/2, 0.64).
inline Real dragStep(ode::Method method, Real h) {
  if (method == ode::Method::BackwardEuler) return 0;
  return method == ode::Method::Verlet ? 2 * h : h;
}

/// A field written by the user, called once per batch of particles (never per particle), on
/// worker threads: it must be a pure function of the batch, without shared mutable state.
struct CustomField {
  std::function<void(const FieldBatch&)> apply{};
};

/// Any field, optionally limited to a region (particles outside it feel nothing).
struct ForceField {
  std::variant<GravityField, LinearDragField, QuadraticDragField, WindField, VortexField,
               AttractorField, TurbulenceField, CustomField>
      field;
  std::optional<Aabb> region{};  ///< m (world)
};

/// Throws InvalidArgument naming the first bad parameter (non-finite values, negative drag,
/// zero vortex axis, non-positive core radius, ...).
void validate(const ForceField& field);

/// Adds the accelerations of `fields` for a batch to batch.accelerations.
/// Fields are applied in order; each one's loop is over the batch (vectorisable).
void applyFields(std::span<const ForceField> fields, const FieldBatch& batch);

/// The acceleration (m/s^2) a turbulence field gives at x (m) and time t (s), for tests and tools.
Vec3 turbulenceAt(const TurbulenceField& f, const Vec3& x, Real time);

}  // namespace inertia
