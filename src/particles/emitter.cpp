#include "inertia/particles/emitter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

#include "inertia/core/error.h"
#include "inertia/core/math.h"
#include "inertia/geometry/mesh.h"

namespace inertia {

namespace {

void checkRange(const Range& r, const char* name, Real lo, bool openLo, bool allowInfinity) {
  auto ok = [&](Real x) {
    if (std::isnan(x)) return false;
    if (std::isinf(x) && !(allowInfinity && x > 0)) return false;
    return openLo ? x > lo : x >= lo;
  };
  require(ok(r.min) && ok(r.max),
          std::string("EmitterSettings::") + name + ": values must be " + (openLo ? "> " : ">= ") +
              std::to_string(lo) + (allowInfinity ? "" : " and finite"));
  require(r.min <= r.max, std::string("EmitterSettings::") + name + ": min must not exceed max");
}

}  // namespace

void validate(const EmitterSettings& s) {
  require(s.pose.p.allFinite() && allFinite(s.pose.q) && std::fabs(s.pose.q.norm() - 1) < 1e-3,
          "EmitterSettings::pose must be finite with a unit quaternion");
  require(std::isfinite(s.radius) && s.radius >= 0, "EmitterSettings::radius must be finite and >= 0");
  require(s.halfExtents.allFinite() && (s.halfExtents.array() >= 0).all(),
          "EmitterSettings::halfExtents must be finite and >= 0");
  require(std::isfinite(s.angle) && s.angle >= 0 && s.angle <= std::numbers::pi_v<Real>,
          "EmitterSettings::angle must be in [0, pi] (rad)");
  require(s.shape != EmitterShape::MeshSurface || s.mesh != nullptr,
          "EmitterSettings::mesh is required for a mesh-surface emitter");
  require(std::isfinite(s.rate) && s.rate >= 0, "EmitterSettings::rate must be finite and >= 0 (1/s)");
  require(s.burst >= 0, "EmitterSettings::burst must be >= 0");
  require(s.direction.allFinite() && s.direction.norm() > Real(1e-6),
          "EmitterSettings::direction must be finite and non-zero");
  require(std::isfinite(s.spread) && s.spread >= 0 && s.spread <= std::numbers::pi_v<Real>,
          "EmitterSettings::spread must be in [0, pi] (rad)");
  checkRange(s.speed, "speed", 0, false, false);
  checkRange(s.lifetime, "lifetime", 0, true, true);
  checkRange(s.mass, "mass", 0, true, false);
  checkRange(s.size, "size", 0, false, false);
  require(s.colorMin.allFinite() && s.colorMax.allFinite(), "EmitterSettings::color must be finite");
}

Emitter::Emitter(const EmitterSettings& settings)
    : settings_(settings), localPose_(settings.pose), rng_(settings.seed) {
  validate(settings_);
  settings_.direction.normalize();
  if (settings_.shape == EmitterShape::MeshSurface) {
    const TriangleMesh& m = *settings_.mesh;
    double sum = 0;
    cumulativeArea_.reserve(m.triangles().size());
    for (const Triangle& t : m.triangles()) {
      const Vec3 &a = m.vertices()[t[0]], &b = m.vertices()[t[1]], &c = m.vertices()[t[2]];
      sum += 0.5 * double((b - a).cross(c - a).norm());
      cumulativeArea_.push_back(sum);
    }
  }
}

void Emitter::setCarrierVelocity(const Vec3& linear, const Vec3& angular, const Vec3& center) {
  require(linear.allFinite() && angular.allFinite() && center.allFinite(),
          "Emitter::setCarrierVelocity: values must be finite");
  carried_ = true;
  carrierLinear_ = linear;
  carrierAngular_ = angular;
  carrierCenter_ = center;
}

Real Emitter::uniform() {
  // The top bits of the generator scaled into [0, 1): exact, and never rounds up to 1.
  if constexpr (std::is_same_v<Real, float>)
    return Real(float(rng_() >> 40) * 0x1.0p-24f);
  else
    return Real(double(rng_() >> 11) * 0x1.0p-53);
}

Vec3 Emitter::unitVector() {
  const Real z = 2 * uniform() - 1;
  const Real phi = 2 * std::numbers::pi_v<Real> * uniform();
  const Real r = std::sqrt(std::max(Real(0), 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 Emitter::tilt(const Vec3& axis, Real halfAngle) {
  // Uniform on the spherical cap: cos(theta) uniform in [cos(halfAngle), 1].
  const Real cosTheta = 1 - uniform() * (1 - std::cos(halfAngle));
  const Real sinTheta = std::sqrt(std::max(Real(0), 1 - cosTheta * cosTheta));
  const Real phi = 2 * std::numbers::pi_v<Real> * uniform();
  const Vec3 u = axis.unitOrthogonal();
  const Vec3 w = axis.cross(u);
  return cosTheta * axis + sinTheta * (std::cos(phi) * u + std::sin(phi) * w);
}

void Emitter::place(Vec3& p, Vec3& d) {
  const EmitterSettings& s = settings_;
  switch (s.shape) {
    case EmitterShape::Point:
      p.setZero();
      d = s.direction;
      break;
    case EmitterShape::Sphere: {
      const Vec3 n = unitVector();
      p = s.radius * std::cbrt(uniform()) * n;  // radius ~ cbrt(u): uniform in volume
      d = n;
      break;
    }
    case EmitterShape::SphereSurface:
      d = unitVector();
      p = s.radius * d;
      break;
    case EmitterShape::Box:
      for (int k = 0; k < 3; ++k) p[k] = (2 * uniform() - 1) * s.halfExtents[k];
      d = s.direction;
      break;
    case EmitterShape::Cone:
      p.setZero();
      d = tilt(s.direction, s.angle);
      break;
    case EmitterShape::Disc: {
      const Real r = s.radius * std::sqrt(uniform());  // sqrt: uniform in area
      const Real phi = 2 * std::numbers::pi_v<Real> * uniform();
      const Vec3 u = s.direction.unitOrthogonal();
      const Vec3 w = s.direction.cross(u);
      p = r * (std::cos(phi) * u + std::sin(phi) * w);
      d = s.direction;
      break;
    }
    case EmitterShape::MeshSurface: {
      const TriangleMesh& m = *s.mesh;
      const double target = double(uniform()) * cumulativeArea_.back();
      std::size_t t = std::size_t(std::upper_bound(cumulativeArea_.begin(), cumulativeArea_.end(), target) -
                                  cumulativeArea_.begin());
      t = std::min(t, cumulativeArea_.size() - 1);
      const Triangle& tri = m.triangles()[t];
      // Uniform barycentric sample (Osada et al. 2002): sqrt of one variable.
      const Real r1 = std::sqrt(uniform()), r2 = uniform();
      p = (1 - r1) * m.vertices()[tri[0]] + r1 * (1 - r2) * m.vertices()[tri[1]] +
          r1 * r2 * m.vertices()[tri[2]];
      d = m.normals()[t];
      break;
    }
  }
  if (s.spread > 0) d = tilt(d, s.spread);
}

std::int64_t Emitter::emit(ParticlePool& pool, Real h) {
  std::int64_t due = 0;
  if (!started_) {
    due += settings_.burst;
    started_ = true;
  }
  carry_ += double(settings_.rate) * double(h);
  const double whole = std::floor(carry_);
  carry_ -= whole;
  due += std::int64_t(whole);

  std::int64_t emitted = 0;
  for (std::int64_t n = 0; n < due; ++n) {
    if (pool.full()) {
      dropped_ += due - n;
      break;
    }
    Vec3 p, d;
    place(p, d);
    ParticlePool::Spawn spawn;
    const Real speed = sample(settings_.speed);
    spawn.velocity = settings_.pose.rotate(d) * speed;
    const Vec3 own = spawn.velocity;  // relative to the carrier
    spawn.lifetime = sample(settings_.lifetime);
    spawn.mass = sample(settings_.mass);
    spawn.radius = sample(settings_.size);
    const Real blend = uniform();
    spawn.color = settings_.colorMin + blend * (settings_.colorMax - settings_.colorMin);
    // Spread the step's particles over the step, as if emitted continuously: emitted at
    // h (1 - u) after the step's start, a particle is h u old at its end, in (0, h]. It is
    // placed where it leaves the emitter; the system's step moves it through its age.
    spawn.age = (1 - uniform()) * h;
    spawn.position = settings_.pose.apply(p);
    if (carried_) {
      // The carrier's velocity at the emission point (a rigid body's v + w x r) is added, and
      // the point has moved with it from the step's start until the emission.
      const Vec3 carrier = carrierLinear_ + carrierAngular_.cross(spawn.position - carrierCenter_);
      spawn.velocity = own + carrier;
      spawn.position += carrier * (h - spawn.age);
    }
    pool.add(spawn);
    ++emitted;
  }
  return emitted;
}

}  // namespace inertia
