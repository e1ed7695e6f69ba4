#include "inertia/particles/fields.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <numbers>
#include <type_traits>
// Hand-vectorised loops for float on x86-64 (SSE2 is part of the base instruction set); the
// plain loops after them finish the batch and are the whole path elsewhere. Both compute the
// same bits: the same IEEE operations on the same values, no contraction (-ffp-contract=off).
#if defined(__SSE2__) && !defined(INERTIA_DOUBLE)
#define INERTIA_PARTICLES_SSE 1
#include <immintrin.h>
#else
#define INERTIA_PARTICLES_SSE 0
#endif

#include "inertia/core/error.h"

namespace inertia {

namespace {

bool finite(Real x) { return std::isfinite(x); }

// splitmix64 (Steele et al. 2014): a cheap stateless hash, so a turbulence field's modes are
// derived from its seed without a generator's state in the hot path.
std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
Real unitReal(std::uint64_t bits) { return Real(double(bits >> 11) * 0x1.0p-53); }

// One Fourier mode of the vector potential: psi += a * sin(k . x + phase + speed t).
struct Mode {
  Vec3 k, a;
  Real phase;
};

// Mode m of a field: wave vectors of unit length (one eddy size set by `scale`), amplitudes
// normalised so that the flow's magnitude is about `amplitude` whatever the number of modes.
Mode mode(const TurbulenceField& f, int m) {
  std::uint64_t h = splitmix(f.seed * 1315423911ull + std::uint64_t(m));
  auto next = [&h]() { return unitReal(h = splitmix(h)); };
  auto unit = [&]() {
    const Real z = 2 * next() - 1, phi = 2 * std::numbers::pi_v<Real> * next();
    const Real r = std::sqrt(std::max(Real(0), 1 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  Mode md;
  md.k = unit() / f.scale;
  md.a = unit() * (f.amplitude * f.scale / std::sqrt(Real(f.modes)));
  md.phase = 2 * std::numbers::pi_v<Real> * next();
  return md;
}

// curl(a sin(k.x + c)) = cos(k.x + c) (k x a).
Vec3 turbulence(const Mode* modes, int count, const Vec3& x, Real phaseShift) {
  Vec3 out = Vec3::Zero();
  for (int m = 0; m < count; ++m)
    out += std::cos(modes[m].k.dot(x) + modes[m].phase + phaseShift) * modes[m].k.cross(modes[m].a);
  return out;
}

struct Apply {
  const FieldBatch& b;
  const std::optional<Aabb>& region;
  std::size_t n;

  // Calls f(i) for every particle of the batch inside the region (all when there is none:
  // that loop has no test in it, so the compiler can vectorise it).
  template <class F>
  void each(F&& f) const {
    if (!region) {
      for (std::size_t i = 0; i < n; ++i) f(i);
    } else {
      for (std::size_t i = 0; i < n; ++i)
        if (inside(i)) f(i);
    }
  }

  bool inside(std::size_t i) const {
    if (!region) return true;
    for (int k = 0; k < 3; ++k) {
      const Real x = b.positions[3 * i + k];
      if (x < region->lower[k] || x > region->upper[k]) return false;
    }
    return true;
  }
  Vec3 x(std::size_t i) const { return Eigen::Map<const Vec3>(&b.positions[3 * i]); }
  Vec3 v(std::size_t i) const { return Eigen::Map<const Vec3>(&b.velocities[3 * i]); }
  void add(std::size_t i, const Vec3& a) const {
    Eigen::Map<Vec3>(&b.accelerations[3 * i]) += a;
  }
  // The most a drag's rate may be (1/s): 1 / step (FieldBatch::step), unbounded when implicit.
  Real maxRate() const {
    return b.step > 0 ? 1 / b.step : std::numeric_limits<Real>::infinity();
  }

  // Gravity and linear drag act on every particle every step: without a region they are plain
  // loops over the batch's arrays (vectorised), computing the same bits as add() would.
  void operator()(const GravityField& f) const {
    if (region) {
      each([&](std::size_t i) { add(i, f.g); });
      return;
    }
    const Real g0 = f.g[0], g1 = f.g[1], g2 = f.g[2];
    Real* a = b.accelerations.data();
    std::size_t i = 0;
#if INERTIA_PARTICLES_SSE
    {
      // Four particles are 12 consecutive floats: g repeats with period 3 across 3 registers.
      const __m128 p0 = _mm_setr_ps(g0, g1, g2, g0), p1 = _mm_setr_ps(g1, g2, g0, g1),
                   p2 = _mm_setr_ps(g2, g0, g1, g2);
      for (; i + 4 <= n; i += 4) {
        float* q = a + 3 * i;
        _mm_storeu_ps(q, _mm_add_ps(_mm_loadu_ps(q), p0));
        _mm_storeu_ps(q + 4, _mm_add_ps(_mm_loadu_ps(q + 4), p1));
        _mm_storeu_ps(q + 8, _mm_add_ps(_mm_loadu_ps(q + 8), p2));
      }
    }
#endif
    for (; i < n; ++i) {
      a[3 * i] += g0;
      a[3 * i + 1] += g1;
      a[3 * i + 2] += g2;
    }
  }
  void operator()(const LinearDragField& f) const {
    if (region) {
      each([&](std::size_t i) { add(i, -std::min(f.k / b.masses[i], maxRate()) * v(i)); });
      return;
    }
    const Real cap = maxRate();
    Real* a = b.accelerations.data();
    const Real* vs = b.velocities.data();
    const Real* m = b.masses.data();
    std::size_t i = 0;
#if INERTIA_PARTICLES_SSE
    {
      // Four particles at a time: s = max((-k) / m, -cap) (the same bits as -min(k / m, cap)),
      // each s spread over its particle's 3 components by shuffles.
      const __m128 negK = _mm_set1_ps(-f.k), negCap = _mm_set1_ps(-cap);
      for (; i + 4 <= n; i += 4) {
        const __m128 s4 = _mm_max_ps(_mm_div_ps(negK, _mm_loadu_ps(m + i)), negCap);
        const __m128 s0 = _mm_shuffle_ps(s4, s4, _MM_SHUFFLE(1, 0, 0, 0));
        const __m128 s1 = _mm_shuffle_ps(s4, s4, _MM_SHUFFLE(2, 2, 1, 1));
        const __m128 s2 = _mm_shuffle_ps(s4, s4, _MM_SHUFFLE(3, 3, 3, 2));
        float* q = a + 3 * i;
        const float* w = vs + 3 * i;
        _mm_storeu_ps(q, _mm_add_ps(_mm_loadu_ps(q), _mm_mul_ps(s0, _mm_loadu_ps(w))));
        _mm_storeu_ps(q + 4, _mm_add_ps(_mm_loadu_ps(q + 4), _mm_mul_ps(s1, _mm_loadu_ps(w + 4))));
        _mm_storeu_ps(q + 8, _mm_add_ps(_mm_loadu_ps(q + 8), _mm_mul_ps(s2, _mm_loadu_ps(w + 8))));
      }
    }
#endif
    for (; i < n; ++i) {
      const Real s = -std::min(f.k / m[i], cap);
      a[3 * i] += s * vs[3 * i];
      a[3 * i + 1] += s * vs[3 * i + 1];
      a[3 * i + 2] += s * vs[3 * i + 2];
    }
  }
  void operator()(const QuadraticDragField& f) const {
    each([&](std::size_t i) {
      const Vec3 vi = v(i);
      add(i, -std::min((f.k / b.masses[i]) * vi.norm(), maxRate()) * vi);
    });
  }
  void operator()(const WindField& f) const {
    each([&](std::size_t i) {
      add(i, -std::min(f.k / b.masses[i], maxRate()) * (v(i) - f.velocity));
    });
  }
  void operator()(const VortexField& f) const {
    const Vec3 axis = f.axis.normalized();
    for (std::size_t i = 0; i < n; ++i) {
      if (!inside(i)) continue;
      const Vec3 d = x(i) - f.center;
      const Vec3 radial = d - d.dot(axis) * axis;  // from the axis to the particle
      const Real r = radial.norm();
      if (r < Real(1e-9)) continue;  // on the axis the flow is still
      // Rankine: rigid rotation inside the core, omega ~ 1/r^2 (speed ~ 1/r) outside.
      const Real omega = r <= f.coreRadius ? f.angularSpeed
                                           : f.angularSpeed * (f.coreRadius * f.coreRadius) / (r * r);
      const Vec3 rHat = radial / r, tHat = axis.cross(rHat);
      const Vec3 vi = v(i);
      const Vec3 vPlane = vi - vi.dot(axis) * axis;
      const Real vt = vi.dot(tHat);
      // Drag towards the flow omega r tHat in the plane, plus the centripetal acceleration of
      // the particle's own tangential speed, which keeps it on its circle. That speed is capped
      // at the flow's: v_t^2 / r grows without bound near the axis, and an explicit step of a
      // particle crossing there faster than the flow overshot it at a larger v_t each time
      // (1e19 m/s within 0.4 s in scenes/vortex_smoke.json). Capped, the pull is at most
      // omega^2 r, a well of frequency omega; a particle at or below the flow's speed is held
      // exactly as before.
      const Real held = std::min(vt * vt, omega * omega * r * r);
      add(i, std::min(f.tightness, maxRate()) * (omega * r * tHat - vPlane) - (held / r) * rHat);
    }
  }
  void operator()(const AttractorField& f) const {
    for (std::size_t i = 0; i < n; ++i) {
      if (!inside(i)) continue;
      const Vec3 d = f.position - x(i);
      const Real r = d.norm();
      if (r > f.cutoff || r < Real(1e-12)) continue;
      const Vec3 dir = d / r;
      switch (f.falloff) {
        case Falloff::InverseSquare: {
          const Real rc = std::max(r, f.minDistance);
          add(i, (f.strength / (rc * rc)) * dir);
          break;
        }
        case Falloff::Linear: add(i, f.strength * d); break;
        case Falloff::Constant: add(i, f.strength * dir); break;
      }
    }
  }
  void operator()(const TurbulenceField& f) const {
    Mode modes[64];
    for (int m = 0; m < f.modes; ++m) modes[m] = mode(f, m);
    const Real shift = f.speed * b.time;
    for (std::size_t i = 0; i < n; ++i)
      if (inside(i)) add(i, turbulence(modes, f.modes, x(i), shift));
  }
  void operator()(const CustomField& f) const {
    if (!region) {
      f.apply(b);
      return;
    }
    // A region limits a custom field too: run it on the batch, keep what lands inside.
    // Custom fields with regions are rare; this path favours simplicity over speed.
    std::vector<Real> before(b.accelerations.begin(), b.accelerations.end());
    f.apply(b);
    for (std::size_t i = 0; i < n; ++i)
      if (!inside(i))
        for (int k = 0; k < 3; ++k) b.accelerations[3 * i + k] = before[3 * i + k];
  }
};

}  // namespace

void validate(const ForceField& field) {
  if (field.region)
    require(!std::isnan(field.region->lower.sum()) && !std::isnan(field.region->upper.sum()) &&
                field.region->isValid(),
            "ForceField::region must have lower <= upper on every axis");
  std::visit(
      [](const auto& f) {
        using T = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<T, GravityField>) {
          require(f.g.allFinite(), "GravityField::g must be finite");
        } else if constexpr (std::is_same_v<T, LinearDragField> || std::is_same_v<T, QuadraticDragField>) {
          require(finite(f.k) && f.k >= 0, "drag coefficient k must be finite and >= 0");
        } else if constexpr (std::is_same_v<T, WindField>) {
          require(f.velocity.allFinite(), "WindField::velocity must be finite");
          require(finite(f.k) && f.k >= 0, "WindField::k must be finite and >= 0");
        } else if constexpr (std::is_same_v<T, VortexField>) {
          require(f.center.allFinite(), "VortexField::center must be finite");
          require(f.axis.allFinite() && f.axis.norm() > Real(1e-6), "VortexField::axis must be finite and non-zero");
          require(finite(f.angularSpeed), "VortexField::angularSpeed must be finite");
          require(finite(f.coreRadius) && f.coreRadius > 0, "VortexField::coreRadius must be > 0");
          require(finite(f.tightness) && f.tightness >= 0, "VortexField::tightness must be >= 0");
        } else if constexpr (std::is_same_v<T, AttractorField>) {
          require(f.position.allFinite(), "AttractorField::position must be finite");
          require(finite(f.strength), "AttractorField::strength must be finite");
          require(!std::isnan(f.cutoff) && f.cutoff > 0, "AttractorField::cutoff must be > 0");
          require(finite(f.minDistance) && f.minDistance > 0, "AttractorField::minDistance must be > 0");
        } else if constexpr (std::is_same_v<T, TurbulenceField>) {
          require(finite(f.amplitude), "TurbulenceField::amplitude must be finite");
          require(finite(f.scale) && f.scale > 0, "TurbulenceField::scale must be > 0");
          require(finite(f.speed), "TurbulenceField::speed must be finite");
          require(f.modes >= 1 && f.modes <= 64, "TurbulenceField::modes must be in 1..64");
        } else {
          require(bool(f.apply), "CustomField::apply must be set");
        }
      },
      field.field);
}

void applyFields(std::span<const ForceField> fields, const FieldBatch& batch) {
  const std::size_t n = batch.masses.size();
  for (const ForceField& f : fields) std::visit(Apply{batch, f.region, n}, f.field);
}

Vec3 turbulenceAt(const TurbulenceField& f, const Vec3& x, Real time) {
  Mode modes[64];
  for (int m = 0; m < f.modes; ++m) modes[m] = mode(f, m);
  return turbulence(modes, f.modes, x, f.speed * time);
}

}  // namespace inertia
