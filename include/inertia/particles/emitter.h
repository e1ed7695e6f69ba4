// Emitters: where new particles appear, how fast, for how long (seed 000, "practical design of
// particle systems": point, sphere, box and cone emitters).
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "inertia/core/id.h"
#include "inertia/core/types.h"
#include "inertia/particles/pool.h"

namespace inertia {

class TriangleMesh;

/// A closed interval [min, max] sampled uniformly; min == max gives a constant.
struct Range {
  Real min = 0;
  Real max = 0;
  static Range constant(Real x) { return {x, x}; }
};

/// Where an emitter places particles and which way it sends them, in its local frame. The base
/// direction is `direction` for point, box and disc emitters, the outward radial direction for
/// sphere emitters, the surface normal for mesh emitters and, for cones, a direction drawn
/// uniformly within `angle` of `direction`; `spread` then tilts it uniformly within a cone of
/// that half-angle.
enum class EmitterShape : std::uint8_t {
  Point,          ///< At the origin.
  Sphere,         ///< Uniform in the ball of `radius`.
  SphereSurface,  ///< Uniform on the sphere of `radius`.
  Box,            ///< Uniform in the box of `halfExtents`.
  Cone,           ///< At the apex (origin); directions within `angle` of `direction`.
  Disc,           ///< Uniform on the disc of `radius` in the plane normal to `direction`.
  MeshSurface,    ///< Uniform by area on the surface of `mesh`.
};

/// Settings of an emitter (designated initialisers; the defaults make a point fountain).
struct EmitterSettings {
  EmitterShape shape = EmitterShape::Point;
  Transform pose{};                        ///< Local frame in the world (m).
  Real radius = Real(0.5);                 ///< Sphere and disc radius (m).
  Vec3 halfExtents = Vec3::Constant(Real(0.5));  ///< Box (m).
  Real angle = Real(0.3);                  ///< Cone half-angle (rad), 0..pi.
  std::shared_ptr<const TriangleMesh> mesh{};  ///< For MeshSurface.

  Real rate = 0;             ///< Particles per second (fractions carry over between steps).
  std::int64_t burst = 0;    ///< Particles emitted at the first step.
  Vec3 direction = Vec3::UnitY();  ///< Base direction (local; normalised).
  Real spread = 0;           ///< Half-angle of the random tilt of the direction (rad), 0..pi.
  Range speed{1, 1};         ///< m/s
  Range lifetime{1, 1};      ///< s, > 0 (infinity allowed: immortal particles)
  Range mass{Real(1e-3), Real(1e-3)};    ///< kg, > 0
  Range size{Real(0.01), Real(0.01)};    ///< Particle radius (m), >= 0
  Vec3 colorMin = Vec3::Ones();  ///< A particle's colour is a random blend of the two.
  Vec3 colorMax = Vec3::Ones();
  std::uint64_t seed = 1;    ///< Same seed, same particles.
  /// The rigid body the emitter rides on, in a World (null: fixed in the world). `pose` is
  /// then relative to the body's origin; before every step the world moves the emitter with
  /// the body, and new particles get the body's velocity at their emission point, v + w x r,
  /// on top of their emission velocity (turned with the body).
  BodyId attachTo{};
  /// Scene files name the body instead: io::instantiate() resolves the name into attachTo.
  std::string attachToName{};
};

/// Throws InvalidArgument naming the first bad field (negative rate, empty or reversed
/// ranges, non-finite values, zero direction, a mesh emitter without a mesh, ...).
void validate(const EmitterSettings& settings);

/// An emitter with its own random stream (std::mt19937_64, turned into reals by bit
/// manipulation rather than std::uniform_real_distribution, whose output the standard leaves
/// to the implementation): same settings, same particles, on every platform.
class Emitter {
 public:
  explicit Emitter(const EmitterSettings& settings);

  const EmitterSettings& settings() const { return settings_; }
  /// Moves the emitter (e.g. attached to a moving body).
  void setPose(const Transform& pose) { settings_.pose = pose; }
  /// The pose it was created with (relative to its body when attached).
  const Transform& localPose() const { return localPose_; }
  /// The velocity field of what carries the emitter, v(x) = linear + angular x (x - center)
  /// (m/s, rad/s, m): added to every new particle's velocity at its emission point. Zero by
  /// default; a World sets it for emitters attached to bodies.
  void setCarrierVelocity(const Vec3& linear, const Vec3& angular, const Vec3& center);

  /// Emits the particles due over a step of `h` seconds (the burst on the first call, then
  /// rate * h plus the carried fraction) into `pool`. Each new particle leaves the emitter at
  /// a random time within the step and is placed where it leaves it (with a carrier, where the
  /// emission point has moved to by then), with the time from then to the step's end, in
  /// (0, h], as its age: ParticleSystem::step then moves it through that time, with the
  /// fields and the swept obstacle tests, so a fast stream is not emitted in clumps once per
  /// step. Returns how many were emitted; those that did not fit in a full pool are counted in
  /// dropped().
  std::int64_t emit(ParticlePool& pool, Real h);

  std::int64_t dropped() const { return dropped_; }

 private:
  Real uniform();  // [0, 1)
  // A constant range returns its value as is (also infinity, which min + 0 * (max - min) is not).
  Real sample(const Range& r) { return r.min == r.max ? r.min : r.min + (r.max - r.min) * uniform(); }
  Vec3 unitVector();
  Vec3 tilt(const Vec3& axis, Real halfAngle);  // uniform on the cap of that half-angle
  void place(Vec3& position, Vec3& direction);

  EmitterSettings settings_;
  Transform localPose_{};
  bool carried_ = false;  // a carrier velocity was set (else nothing is added: same bits as before)
  Vec3 carrierLinear_ = Vec3::Zero(), carrierAngular_ = Vec3::Zero(), carrierCenter_ = Vec3::Zero();
  std::mt19937_64 rng_;
  std::vector<double> cumulativeArea_;  // mesh emitters: area prefix sums for sampling
  double carry_ = 0;
  bool started_ = false;
  std::int64_t dropped_ = 0;
};

}  // namespace inertia
