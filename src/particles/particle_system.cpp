#include "inertia/particles/particle_system.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "core/thread_pool_impl.h"
#include "dynamics/step_workers.h"
// Hand-vectorised loops for float on x86-64 (SSE2 is part of the base instruction set); the
// plain loops after them finish the batch and are the whole path elsewhere. Both compute the
// same bits: the same IEEE operations on the same values, no contraction (-ffp-contract=off).
#if defined(__SSE2__) && !defined(INERTIA_DOUBLE)
#define INERTIA_PARTICLES_SSE 1
#include <immintrin.h>
#else
#define INERTIA_PARTICLES_SSE 0
#endif

#include "fast_path.h"
#include "impact.h"
#include "inertia/collision/queries.h"
#include "inertia/collision/uniform_grid.h"
#include "inertia/core/error.h"
#include "inertia/geometry/bounds.h"
#include "inertia/ode/step.h"

namespace inertia {

namespace {

// Particles per batch: the unit of parallel work and of integration. Fixed, never derived from
// the thread count, so every run cuts the pool the same way (determinism); small enough that a
// batch's arrays stay in L2 between its integration and collision passes.
constexpr std::size_t kBatch = 2048;
static_assert(kBatch <= detail::kMaxParticleBatch);

// Gap kept between a particle's surface and an obstacle after a correction (m): keeps rounding
// from leaving the centre a hair inside, so "never below the plane" holds exactly.
constexpr Real kSkin = Real(1e-4);

#if INERTIA_PARTICLES_SSE
// The 4 bits of a comparison mask as 4 bytes of 0 or 1 (little endian), for the dead flags.
constexpr std::uint32_t kMaskBytes[16] = {
    0x00000000, 0x00000001, 0x00000100, 0x00000101, 0x00010000, 0x00010001, 0x00010100, 0x00010101,
    0x01000000, 0x01000001, 0x01000100, 0x01000101, 0x01010000, 0x01010001, 0x01010100, 0x01010101};
#endif

// Obstacles the vectorised near test filters against; with more, every particle takes the full
// path (whose loops cull by bounds).
constexpr std::size_t kMaxNearTests = 64;

using NearTest = detail::ParticleNearTest;

// An obstacle's near test: planes by normal and offset, the others by their world box, both
// moved out by the skin.
template <class Cache>
NearTest nearTest(const Cache& c) {
  NearTest t;
  t.plane = c.plane;
  t.n0 = c.normal.x(), t.n1 = c.normal.y(), t.n2 = c.normal.z(), t.offset = c.offset + kSkin;
  t.lo0 = c.bounds.lower[0] - kSkin, t.lo1 = c.bounds.lower[1] - kSkin,
  t.lo2 = c.bounds.lower[2] - kSkin;
  t.hi0 = c.bounds.upper[0] + kSkin, t.hi1 = c.bounds.upper[1] + kSkin,
  t.hi2 = c.bounds.upper[2] + kSkin;
  return t;
}

// Whether particle j's swept box (start a, end b, inflated by its radius r) may touch obstacle
// t. Conservative: a false positive only costs the full test.
inline bool mayTouch(const NearTest& t, const Real* a, const Real* b, Real r) {
  if (t.plane) {
    const Real da = t.n0 * a[0] + t.n1 * a[1] + t.n2 * a[2], db = t.n0 * b[0] + t.n1 * b[1] + t.n2 * b[2];
    return std::min(da, db) < t.offset + r;
  }
  // Bitwise on ints, not && on bools: no branches, so the callers' loops vectorise.
  return (int(std::min(a[0], b[0]) - r <= t.hi0) & int(std::max(a[0], b[0]) + r >= t.lo0) &
          int(std::min(a[1], b[1]) - r <= t.hi1) & int(std::max(a[1], b[1]) + r >= t.lo1) &
          int(std::min(a[2], b[2]) - r <= t.hi2) & int(std::max(a[2], b[2]) + r >= t.lo2)) != 0;
}

// Writes the batch indices of the particles that may touch some obstacle to `list` (in
// increasing order) and returns how many. `a` and `b` hold 3 Reals per particle.
std::size_t nearParticles(std::span<const NearTest> tests, const Real* a, const Real* b, const Real* r,
                          std::size_t count, std::uint16_t* list) {
  std::size_t found = 0, j = 0;
#if INERTIA_PARTICLES_SSE
  {
    // Four particles at a time: their 12 coordinates (3 registers) transposed to x, y and z
    // registers, then every obstacle tested on all four at once.
    auto transpose = [](const float* p, __m128& x, __m128& y, __m128& z) {
      const __m128 p0 = _mm_loadu_ps(p), p1 = _mm_loadu_ps(p + 4), p2 = _mm_loadu_ps(p + 8);
      const __m128 t0 = _mm_shuffle_ps(p0, p1, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
      const __m128 t1 = _mm_shuffle_ps(p1, p2, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
      x = _mm_shuffle_ps(p0, t1, _MM_SHUFFLE(2, 0, 3, 0));
      y = _mm_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 1, 2, 0));
      z = _mm_shuffle_ps(t0, p2, _MM_SHUFFLE(3, 0, 3, 1));
    };
    // Every test's constants broadcast once: planes (n0, n1, n2, offset), boxes (lo, hi).
    struct Wide {
      bool plane;
      __m128 c[6];
    };
    Wide wide[kMaxNearTests];
    for (std::size_t k = 0; k < tests.size(); ++k) {
      const NearTest& t = tests[k];
      wide[k].plane = t.plane;
      const float values[6] = {t.plane ? t.n0 : t.lo0, t.plane ? t.n1 : t.lo1, t.plane ? t.n2 : t.lo2,
                               t.plane ? t.offset : t.hi0, t.hi1, t.hi2};
      for (int q = 0; q < 6; ++q) wide[k].c[q] = _mm_set1_ps(values[q]);
    }
    for (; j + 4 <= count; j += 4) {
      __m128 ax, ay, az, bx, by, bz;
      transpose(a + 3 * j, ax, ay, az);
      transpose(b + 3 * j, bx, by, bz);
      const __m128 rr = _mm_loadu_ps(r + j);
      // The swept box of each particle, inflated by its radius.
      const __m128 lx = _mm_sub_ps(_mm_min_ps(ax, bx), rr), hx = _mm_add_ps(_mm_max_ps(ax, bx), rr);
      const __m128 ly = _mm_sub_ps(_mm_min_ps(ay, by), rr), hy = _mm_add_ps(_mm_max_ps(ay, by), rr);
      const __m128 lz = _mm_sub_ps(_mm_min_ps(az, bz), rr), hz = _mm_add_ps(_mm_max_ps(az, bz), rr);
      __m128 any = _mm_setzero_ps();
      for (std::size_t k = 0; k < tests.size(); ++k) {
        const __m128* c = wide[k].c;
        if (wide[k].plane) {
          const __m128 da = _mm_add_ps(_mm_add_ps(_mm_mul_ps(c[0], ax), _mm_mul_ps(c[1], ay)), _mm_mul_ps(c[2], az));
          const __m128 db = _mm_add_ps(_mm_add_ps(_mm_mul_ps(c[0], bx), _mm_mul_ps(c[1], by)), _mm_mul_ps(c[2], bz));
          any = _mm_or_ps(any, _mm_cmplt_ps(_mm_min_ps(da, db), _mm_add_ps(c[3], rr)));
        } else {
          const __m128 x = _mm_and_ps(_mm_cmple_ps(lx, c[3]), _mm_cmpge_ps(hx, c[0]));
          const __m128 y = _mm_and_ps(_mm_cmple_ps(ly, c[4]), _mm_cmpge_ps(hy, c[1]));
          const __m128 z = _mm_and_ps(_mm_cmple_ps(lz, c[5]), _mm_cmpge_ps(hz, c[2]));
          any = _mm_or_ps(any, _mm_and_ps(_mm_and_ps(x, y), z));
        }
      }
      for (int mask = _mm_movemask_ps(any); mask != 0; mask &= mask - 1)
        list[found++] = std::uint16_t(j + std::size_t(std::countr_zero(unsigned(mask))));
    }
  }
#endif
  for (; j < count; ++j) {
    bool touch = false;
    for (const NearTest& t : tests) touch |= mayTouch(t, a + 3 * j, b + 3 * j, r[j]);
    if (touch) list[found++] = std::uint16_t(j);
  }
  return found;
}

}  // namespace

struct ParticleSystem::Scratch {
  std::vector<ode::Workspace<Real>> workspaces;  // one per batch (position Verlet keeps history)
  ode::Workspace<Real> coupled;                  // the whole pool, when springs couple particles
  std::vector<Real> previous;                    // start positions, when springs couple all
  std::vector<Real> acceleration;                // coupled integration and backward Euler
  std::vector<std::array<ode::Vector<Real>, 3>> probes;  // per batch: backward Euler's probes
  std::vector<std::uint8_t> dead;
  std::vector<std::size_t> deaths;  // per batch, summed after the pass
  // The particles emitted during a step, advanced one by one in chunks of kBatch.
  std::vector<ode::Workspace<Real>> freshWorkspaces;
  std::vector<std::array<ode::Vector<Real>, 3>> freshProbes;
  std::vector<std::size_t> freshDeaths;
  // Particle-particle collisions.
  UniformGrid grid;
  std::vector<Real> snapshotX, snapshotV;
};

ParticleSystem::ParticleSystem(const ParticleSystemSettings& s)
    : settings_(s), pool_(s.capacity), scratch_(std::make_unique<Scratch>()) {
  require(std::isfinite(s.restitution) && s.restitution >= 0 && s.restitution <= 1,
          "ParticleSystemSettings::restitution must be in [0, 1]");
  require(std::isfinite(s.friction) && s.friction >= 0,
          "ParticleSystemSettings::friction must be finite and >= 0");
  require(std::isfinite(s.restitutionThreshold) && s.restitutionThreshold >= 0,
          "ParticleSystemSettings::restitutionThreshold must be finite and >= 0 (m/s)");
  require(!ode::methodName(s.integrator).empty(), "ParticleSystemSettings::integrator is not a method");
  Scratch& w = *scratch_;
  w.workspaces.resize((s.capacity + kBatch - 1) / kBatch);
  if (s.integrator == ode::Method::BackwardEuler) w.probes.resize(w.workspaces.size());
  w.dead.resize(s.capacity);
  w.deaths.resize(w.workspaces.size());
  w.freshWorkspaces.resize(w.workspaces.size());
  w.freshProbes.resize(w.probes.size());
  w.freshDeaths.resize(w.workspaces.size());
}

ParticleSystem::~ParticleSystem() = default;
ParticleSystem::ParticleSystem(ParticleSystem&&) noexcept = default;
ParticleSystem& ParticleSystem::operator=(ParticleSystem&&) noexcept = default;

// Every member (a new one must be added here); the static obstacles' cache entries point into
// obstacles_, so they are pointed at the copy's own.
ParticleSystem::ParticleSystem(const ParticleSystem& other)
    : settings_(other.settings_),
      pool_(other.pool_),
      emitters_(other.emitters_),
      fields_(other.fields_),
      obstacles_(other.obstacles_),
      obstacleCache_(other.obstacleCache_),
      planeCount_(other.planeCount_),
      springs_(other.springs_),
      springIndex_(other.springIndex_),
      scratch_(std::make_unique<Scratch>(*other.scratch_)),
      stats_(other.stats_),
      time_(other.time_) {
  for (std::size_t i = 0; i < obstacles_.size(); ++i)
    obstacleCache_[i].collider = &obstacles_[i].collider;
}

ParticleSystem& ParticleSystem::operator=(const ParticleSystem& other) {
  if (this != &other) *this = ParticleSystem(other);
  return *this;
}

std::size_t ParticleSystem::addEmitter(const EmitterSettings& emitter) {
  emitters_.emplace_back(emitter);  // the Emitter validates
  return emitters_.size() - 1;
}

std::size_t ParticleSystem::addField(const ForceField& field) {
  validate(field);
  fields_.push_back(field);
  return fields_.size() - 1;
}

ParticleSystem::ObstacleCache ParticleSystem::makeCache(const Collider& collider, const Transform& pose) {
  ObstacleCache cache;
  cache.collider = &collider;
  cache.pose = pose;
  cache.bounds = worldBounds(collider.shape(), pose);
  if (const Plane* plane = collider.shape().getIf<Plane>()) {
    // n . x <= offset locally; in the world n' = q n and offset' = offset + n' . p.
    cache.plane = true;
    cache.normal = pose.rotate(plane->normal);
    cache.offset = plane->offset + cache.normal.dot(pose.p);
  }
  return cache;
}

std::size_t ParticleSystem::addObstacle(const Obstacle& obstacle) {
  require(obstacle.pose.p.allFinite() && obstacle.pose.q.coeffs().allFinite() &&
              std::fabs(obstacle.pose.q.norm() - 1) < Real(1e-3),
          "Obstacle::pose must be finite with a unit quaternion");
  obstacles_.push_back(obstacle);
  Obstacle& o = obstacles_.back();
  o.pose.q.normalize();
  // Static obstacles come first in the cache, moving ones after them.
  const std::size_t k = obstacles_.size() - 1;
  obstacleCache_.insert(obstacleCache_.begin() + std::ptrdiff_t(k), makeCache(o.collider, o.pose));
  for (std::size_t i = 0; i < k; ++i) obstacleCache_[i].collider = &obstacles_[i].collider;  // moved
  planeCount_ += obstacleCache_[k].plane ? 1 : 0;
  return k;
}

void ParticleSystem::setMovingObstacles(std::span<const MovingObstacle> obstacles) {
  for (const MovingObstacle& o : obstacles) {
    require(o.collider != nullptr, "MovingObstacle::collider must be set");
    require(o.pose.p.allFinite() && o.pose.q.coeffs().allFinite() &&
                std::fabs(o.pose.q.norm() - 1) < Real(1e-3),
            "MovingObstacle::pose must be finite with a unit quaternion");
    require(o.linearVelocity.allFinite() && o.angularVelocity.allFinite() && o.center.allFinite(),
            "MovingObstacle: velocities and centre must be finite");
  }
  for (std::size_t k = obstacles_.size(); k < obstacleCache_.size(); ++k)
    planeCount_ -= obstacleCache_[k].plane ? 1 : 0;
  obstacleCache_.resize(obstacles_.size());
  for (const MovingObstacle& o : obstacles) {
    Transform pose = o.pose;
    pose.q.normalize();
    ObstacleCache c = makeCache(*o.collider, pose);
    c.moving = !(o.linearVelocity.isZero(0) && o.angularVelocity.isZero(0));
    // A moving plane would have to sweep all space; planes sit on static bodies only.
    if (c.moving && c.plane) c.moving = false;
    c.linearVelocity = o.linearVelocity;
    c.angularVelocity = o.angularVelocity;
    c.center = o.center;
    planeCount_ += c.plane ? 1 : 0;
    obstacleCache_.push_back(c);
  }
}

std::size_t ParticleSystem::addSpring(const ParticleSpring& spring) {
  require(spring.a != spring.b, "ParticleSpring: a spring needs two different particles");
  require(std::isfinite(spring.restLength) && spring.restLength >= 0,
          "ParticleSpring::restLength must be finite and >= 0");
  require(std::isfinite(spring.stiffness) && spring.stiffness >= 0,
          "ParticleSpring::stiffness must be finite and >= 0");
  require(std::isfinite(spring.damping) && spring.damping >= 0,
          "ParticleSpring::damping must be finite and >= 0");
  springs_.push_back(spring);
  resolveSprings();
  scratch_->previous.resize(3 * settings_.capacity);  // coupled integration needs it
  return springs_.size() - 1;
}

ParticleStats ParticleSystem::stats() const {
  ParticleStats s = stats_;
  s.alive = std::int64_t(pool_.size());
  s.dropped = 0;
  for (const Emitter& e : emitters_) s.dropped += e.dropped();
  return s;
}

// Ids increase along the pool (stable compaction keeps the emission order), so a particle is
// found by binary search. Springs whose particle is gone are dropped.
void ParticleSystem::resolveSprings() {
  const auto ids = pool_.ids();
  auto indexOf = [&](std::uint64_t id) -> std::int64_t {
    auto it = std::lower_bound(ids.begin(), ids.end(), id);
    return it != ids.end() && *it == id ? std::int64_t(it - ids.begin()) : -1;
  };
  std::size_t out = 0;
  springIndex_.clear();
  for (const ParticleSpring& s : springs_) {
    const std::int64_t a = indexOf(s.a), b = indexOf(s.b);
    if (a < 0 || b < 0) continue;
    springs_[out++] = s;
    springIndex_.push_back(std::uint32_t(a));
    springIndex_.push_back(std::uint32_t(b));
  }
  springs_.resize(out);
}

void ParticleSystem::springAccelerations(std::span<const Real> x, std::span<const Real> v,
                                         std::span<Real> acc) const {
  const auto m = pool_.masses();
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    const ParticleSpring& sp = springs_[s];
    const std::size_t a = springIndex_[2 * s], b = springIndex_[2 * s + 1];
    const Vec3 d = Eigen::Map<const Vec3>(&x[3 * a]) - Eigen::Map<const Vec3>(&x[3 * b]);
    const Real len = d.norm();
    if (len < Real(1e-12)) continue;  // coincident: no direction to push along
    const Vec3 u = d / len;
    const Vec3 dv = Eigen::Map<const Vec3>(&v[3 * a]) - Eigen::Map<const Vec3>(&v[3 * b]);
    const Vec3 f = -(sp.stiffness * (len - sp.restLength) + sp.damping * dv.dot(u)) * u;
    Eigen::Map<Vec3>(&acc[3 * a]) += f / m[a];
    Eigen::Map<Vec3>(&acc[3 * b]) -= f / m[b];
  }
}

void ParticleSystem::step(Real h, ThreadPool* pool) {
  detail::StepWorkers::run(pool ? &pool->impl().arena : nullptr,
                           [&](detail::StepWorkers& workers) { step(h, workers); });
}

void ParticleSystem::step(Real h, detail::StepWorkers& workers) {
  require(std::isfinite(h) && h > 0, "ParticleSystem::step: h must be finite and > 0 (s)");
  {
    // The particles alive at the step's start move through the whole step; those emitted
    // during it, only from their emission on (Emitter::emit).
    const std::size_t old = pool_.size();
    if (!springs_.empty()) resolveSprings();
    integrate(h, workers);
    for (Emitter& e : emitters_) stats_.emitted += e.emit(pool_, h);
    std::size_t deaths = advanceEmitted(old, h, workers);
    if (settings_.particleCollisions) collideParticles(workers);
    const std::size_t n = pool_.size();
    const std::size_t batches = (old + kBatch - 1) / kBatch;
    for (std::size_t b = 0; b < batches; ++b) deaths += scratch_->deaths[b];
    // The compaction reads every flag: skip it when the pass counted no death. The fused kernel
    // writes only the flags of deaths (a step of immortal particles writes none of the 1 MB a
    // million take): they are cleared after each compaction for the next step.
    std::size_t died = 0;
    if (deaths > 0) {
      died = pool_.removeFlagged({scratch_->dead.data(), n});
      std::fill_n(scratch_->dead.data(), n, std::uint8_t(0));
    }
    stats_.died += std::int64_t(died);
    if (died > 0 && !springs_.empty()) resolveSprings();
    time_ += double(h);
  }
}

// What a step decides once for all its batches: the path (the fused symplectic Euler kernel or
// ode::step), the fields the kernel sums itself and the obstacles it filters against.
struct ParticleSystem::StepPlan {
  bool coupled = false;  // springs: the pool was integrated as one system, start positions in
                         // Scratch::previous
  bool collide = false;
  bool fused = false;
  bool inKernel = false;
  bool nearInKernel = false;
  detail::SimdLevel isa = detail::SimdLevel::Scalar;
  detail::ParticleFieldTerm terms[detail::kMaxParticleTerms];
  std::size_t termCount = 0;
  detail::ParticleNearTest tests[detail::kMaxParticleStepTests];
};

ParticleSystem::StepPlan ParticleSystem::makePlan(bool coupled) const {
  StepPlan plan;
  plan.coupled = coupled;
  plan.collide = !obstacleCache_.empty();
  // Symplectic Euler, the default, takes a fused path: one kernel per batch does what
  // ode::symplecticEuler does (v += h a, then x += h v, element by element: the same bits),
  // keeps the start positions, ages the particles and lists those near an obstacle, in one pass
  // over the batch's arrays. Gravity and linear drag without regions (the usual fields) are
  // summed inside the kernel; other fields are evaluated into a batch buffer first by the same
  // applyFields() the ode layer's callback calls. The other methods go through ode::step.
  plan.fused = !coupled && settings_.integrator == ode::Method::SymplecticEuler;
  plan.isa = detail::particleSimd();
  plan.inKernel = fields_.size() <= detail::kMaxParticleTerms;
  for (std::size_t k = 0; plan.inKernel && k < fields_.size(); ++k) {
    const auto* g = std::get_if<GravityField>(&fields_[k].field);
    const auto* d = std::get_if<LinearDragField>(&fields_[k].field);
    plan.inKernel = !fields_[k].region && (g || d);
    if (g)
      plan.terms[plan.termCount++] = {
          .gravity = true, .g0 = g->g[0], .g1 = g->g[1], .g2 = g->g[2], .negK = 0};
    if (d)
      plan.terms[plan.termCount++] = {.gravity = false, .g0 = 0, .g1 = 0, .g2 = 0, .negK = -d->k};
  }
  // With few obstacles the kernel filters against all of them; with more, collideObstacles()
  // first culls them by each batch's box, which needs the whole batch moved.
  plan.nearInKernel = plan.collide && obstacleCache_.size() <= detail::kMaxParticleStepTests;
  if (plan.nearInKernel)
    for (std::size_t k = 0; k < obstacleCache_.size(); ++k)
      plan.tests[k] = nearTest(obstacleCache_[k]);
  return plan;
}

void ParticleSystem::integrate(Real h, detail::StepWorkers& workers) {
  Scratch& w = *scratch_;
  const std::size_t n = pool_.size();
  if (n == 0) return;
  const bool coupled = !springs_.empty();
  if (coupled) {
    // The whole pool moves at once: keep every start position for the swept tests.
    if (!obstacleCache_.empty()) std::copy_n(pool_.positions().data(), 3 * n, w.previous.data());
    integrateCoupled(h, workers);
  }
  const StepPlan plan = makePlan(coupled);
  const std::size_t batches = (n + kBatch - 1) / kBatch;
  workers.parallelFor(batches, 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t b = first; b != last; ++b) {
      const std::size_t begin = b * kBatch, count = std::min(kBatch, n - begin);
      w.deaths[b] = integrateBatch(plan, b, false, begin, count, h, Real(time_));
    }
  });
}

// Particles emitted during the step, [first, size()): each left its emitter `age` before the
// step's end (Emitter::emit placed it where it left) and moves through that time alone, under
// the fields and with the swept obstacle tests, as a batch of one. Returns how many died.
std::size_t ParticleSystem::advanceEmitted(std::size_t first, Real h,
                                           detail::StepWorkers& workers) {
  Scratch& w = *scratch_;
  const std::size_t n = pool_.size();
  if (first >= n) return 0;
  const StepPlan plan = makePlan(false);
  const std::size_t chunks = (n - first + kBatch - 1) / kBatch;
  workers.parallelFor(chunks, 1, [&](std::size_t firstChunk, std::size_t lastChunk) {
    for (std::size_t c = firstChunk; c != lastChunk; ++c) {
      std::size_t deaths = 0;
      const std::size_t end = std::min(n, first + (c + 1) * kBatch);
      for (std::size_t i = first + c * kBatch; i < end; ++i) {
        Real& age = pool_.ages()[i];
        const Real span = age;
        age = 0;                              // the step adds span back
        w.freshWorkspaces[c].resetHistory();  // a particle of its own: no Verlet history
        deaths += integrateBatch(plan, c, true, i, 1, span, Real(time_) + (h - span));
      }
      w.freshDeaths[c] = deaths;
    }
  });
  std::size_t deaths = 0;
  for (std::size_t c = 0; c < chunks; ++c) deaths += w.freshDeaths[c];
  return deaths;
}

// Integrates particles [begin, begin + count) (count <= kBatch) over [t, t + h], ages them,
// flags the dead and collides them with the obstacles, with the scratch of batch `slot` (of the
// step's batches, or of the chunks of particles emitted during it when `fresh`). Returns how
// many died.
std::size_t ParticleSystem::integrateBatch(const StepPlan& plan, std::size_t slot, bool fresh,
                                           std::size_t begin, std::size_t count, Real h, Real t) {
  Scratch& w = *scratch_;
  ode::Workspace<Real>& workspace = fresh ? w.freshWorkspaces[slot] : w.workspaces[slot];
  const std::size_t n = pool_.size();
  std::span<Real> x = pool_.positions().subspan(3 * begin, 3 * count);
  std::span<Real> v = pool_.velocities().subspan(3 * begin, 3 * count);
  const auto m = pool_.masses().subspan(begin, count);
  // The batch's start positions for the swept tests, on the stack (24 KiB): they stay in
  // cache between integration and collision instead of streaming through memory.
  Real start[3 * kBatch];
  const Real* previous = plan.coupled ? w.previous.data() + 3 * begin : start;
  if (plan.fused) {
    Real acc[3 * kBatch];
    if (!plan.inKernel) {
      // The accelerations start at zero and the fields add to them. A leading gravity
      // field without a region adds the same g to all: start from 0 + g instead (the
      // same bits, one pass fewer).
      std::span<const ForceField> rest = fields_;
      const GravityField* g = fields_.empty() || fields_[0].region
                                  ? nullptr
                                  : std::get_if<GravityField>(&fields_[0].field);
      if (g) {
        const Real g0 = Real(0) + g->g[0], g1 = Real(0) + g->g[1], g2 = Real(0) + g->g[2];
        for (std::size_t i = 0; i < count; ++i) {
          acc[3 * i] = g0;
          acc[3 * i + 1] = g1;
          acc[3 * i + 2] = g2;
        }
        rest = rest.subspan(1);
      } else {
        std::fill_n(acc, 3 * count, Real(0));
      }
      applyFields(rest, FieldBatch{t, x, v, m, {acc, 3 * count}, h});
    }
    std::uint16_t near[kBatch];
    detail::ParticleStepBatch batch{.count = count,
                                    .h = h,
                                    .x = x.data(),
                                    .v = v.data(),
                                    .m = m.data(),
                                    .age = pool_.ages().data() + begin,
                                    .life = pool_.lifetimes().data() + begin,
                                    .radius = pool_.radii().data() + begin,
                                    .acc = plan.inKernel ? nullptr : acc,
                                    .terms = plan.terms,
                                    .termCount = plan.termCount,
                                    .start = start,
                                    .dead = w.dead.data() + begin,
                                    .tests = plan.nearInKernel ? plan.tests : nullptr,
                                    .testCount = plan.nearInKernel ? obstacleCache_.size() : 0,
                                    .list = near};
    if (!fresh && begin + kBatch < n) {
      const std::size_t next = begin + kBatch;
      batch.next[0] = pool_.positions().data() + 3 * next;
      batch.next[1] = pool_.velocities().data() + 3 * next;
      batch.next[2] = pool_.masses().data() + next;
      batch.next[3] = pool_.ages().data() + next;
      batch.next[4] = pool_.lifetimes().data() + next;
      batch.next[5] = pool_.radii().data() + next;
      batch.nextCount = std::min(kBatch, n - next);
    }
    const detail::ParticleStepCounts counts = detail::stepParticleBatch(plan.isa, batch);
    if (plan.nearInKernel)
      collideObstacles(begin, begin + count, start, near, counts.listed);
    else if (plan.collide)
      collideObstacles(begin, begin + count, start);
    return counts.deaths;
  }
  if (!plan.coupled) {
    if (plan.collide) std::copy_n(x.data(), 3 * count, start);
    auto accel = [&](Real time, ode::ConstView<Real> xs, ode::ConstView<Real> vs,
                     ode::View<Real> a) {
      a.setZero();
      applyFields(fields_, FieldBatch{time,
                                      {xs.data(), std::size_t(xs.size())},
                                      {vs.data(), std::size_t(vs.size())},
                                      m,
                                      {a.data(), std::size_t(a.size())},
                                      dragStep(settings_.integrator, h)});
    };
    if (settings_.integrator == ode::Method::BackwardEuler) {
      // Matrix-free Jacobian products by forward differences of the fields, and
      // BiCGSTAB: attractors and vortices give non-symmetric Jacobians. The probe
      // buffers are the batch's own, grown once.
      auto& probe = fresh ? w.freshProbes[slot] : w.probes[slot];
      auto product = [&](bool wrtX) {
        return [&, wrtX](Real time, ode::ConstView<Real> xs, ode::ConstView<Real> vs,
                         ode::ConstView<Real> dir, ode::View<Real> out) {
          const Eigen::Index size = xs.size();
          for (auto& buffer : probe) buffer.resize(size);
          const Real scale = std::sqrt(std::numeric_limits<Real>::epsilon()) *
                             (1 + (wrtX ? xs : vs).norm()) / std::max(dir.norm(), Real(1e-30));
          probe[0] = (wrtX ? xs : vs) + scale * dir;
          ode::View<Real> base(probe[1].data(), size), moved(probe[2].data(), size);
          const ode::ConstView<Real> shifted(probe[0].data(), size);
          accel(time, xs, vs, base);
          if (wrtX)
            accel(time, shifted, vs, moved);
          else
            accel(time, xs, shifted, moved);
          out = (moved - base) / scale;
        };
      };
      // Template arguments spelled out: clang before 17 has no aggregate deduction.
      auto dadx = product(true), dadv = product(false);
      ode::SecondOrderSystem<decltype(accel), decltype(dadx), decltype(dadv)> system{accel, dadx,
                                                                                     dadv};
      ode::step(settings_.integrator, system, t, h, x, v, workspace,
                ode::LinearSolverOptions<Real>{.solver = ode::LinearSolver::BiCgStab});
    } else {
      ode::step(settings_.integrator, accel, t, h, x, v, workspace);
    }
  }
  Real* age = pool_.ages().data() + begin;
  const Real* life = pool_.lifetimes().data() + begin;
  std::uint8_t* dead = w.dead.data() + begin;
  std::size_t deaths = 0, i = 0;
#if INERTIA_PARTICLES_SSE
  {
    const __m128 step = _mm_set1_ps(h);
    for (; i + 4 <= count; i += 4) {
      const __m128 a = _mm_add_ps(_mm_loadu_ps(age + i), step);
      _mm_storeu_ps(age + i, a);
      const unsigned mask = unsigned(_mm_movemask_ps(_mm_cmpge_ps(a, _mm_loadu_ps(life + i))));
      std::memcpy(dead + i, &kMaskBytes[mask], 4);
      deaths += std::size_t((0x4332322132212110ull >> (4 * mask)) & 0xF);  // popcount
    }
  }
#endif
  for (; i < count; ++i) {
    const Real a = age[i] + h;
    age[i] = a;
    const bool d = a >= life[i];
    dead[i] = d;
    deaths += d;
  }
  if (plan.collide) collideObstacles(begin, begin + count, previous);
  return deaths;
}

// The full path of collideObstacles() for a system whose only plane is `c`, specialised to a
// particle that meets no other obstacle: the same operations in the same order, so the same
// bits. Returns false, changing nothing, when the particle's path (all its swept boxes and its
// final position, inflated by r) comes near another obstacle's bounds: the full path decides.
bool ParticleSystem::collidePlaneOnly(const ObstacleCache& c, const Real* previous, Real r, Vec3& endOut,
                                      Vec3& velOut) const {
  const Real e = settings_.restitution, mu = settings_.friction,
             threshold = settings_.restitutionThreshold;
  Vec3 vel = velOut;
  Vec3 end1 = endOut;
  Aabb visited;
  visited.extend(end1);
  if (previous) {
    Vec3 start = Eigen::Map<const Vec3>(previous);
    visited.extend(start);
    for (int bounce = 0; bounce < 2; ++bounce) {
      const Vec3 sweep = end1 - start;
      if (sweep.squaredNorm() == 0) break;
      const Real d0 = c.normal.dot(start) - c.offset, d1 = c.normal.dot(end1) - c.offset;
      if (!(d0 >= 0 && d1 < 0)) break;
      const Real f = d0 / (d0 - d1);
      if (!(f < Real(1))) break;  // the full path keeps only hits before the segment's end
      const Vec3 point = start + f * sweep;
      const Vec3 before = vel;
      detail::respondToImpact(vel, c.normal, e, mu, threshold);
      const Real remaining = 1 - f;
      const Real speedBefore = before.norm();
      start = point + c.normal * (r + kSkin);
      end1 = start;
      if (speedBefore > 0) end1 += vel * (remaining * sweep.norm() / speedBefore);
      visited.extend(start);
      visited.extend(end1);
    }
  }
  const Real d = c.normal.dot(end1) - c.offset;
  if (d < r) {
    end1 += c.normal * (r + kSkin - d);
    detail::respondToImpact(vel, c.normal, e, mu, threshold);
  }
  visited.extend(end1);
  visited = visited.inflated(r + kSkin);
  for (const ObstacleCache& o : obstacleCache_)
    if (!o.plane && o.bounds.overlaps(visited)) return false;
  endOut = end1;
  velOut = vel;
  return true;
}

// Springs couple particles across batches: the whole pool is one system. Fields are still
// evaluated batch by batch in parallel; the springs add their forces in a fixed order.
void ParticleSystem::integrateCoupled(Real h, detail::StepWorkers& workers) {
  Scratch& w = *scratch_;
  const std::size_t n = pool_.size();
  const auto m = pool_.masses();
  auto accel = [&](Real time, ode::ConstView<Real> xs, ode::ConstView<Real> vs, ode::View<Real> a) {
    const std::size_t batches = (n + kBatch - 1) / kBatch;
    workers.parallelFor(
        batches, 1, [&](std::size_t first, std::size_t last) {
          for (std::size_t b = first; b != last; ++b) {
            const std::size_t begin = b * kBatch, count = std::min(kBatch, n - begin);
            a.segment(3 * begin, 3 * count).setZero();
            applyFields(fields_, FieldBatch{time, {xs.data() + 3 * begin, 3 * count},
                                            {vs.data() + 3 * begin, 3 * count}, m.subspan(begin, count),
                                            {a.data() + 3 * begin, 3 * count},
                                            dragStep(settings_.integrator, h)});
          }
        });
    springAccelerations({xs.data(), 3 * n}, {vs.data(), 3 * n}, {a.data(), 3 * n});
  };
  ode::step(settings_.integrator, accel, Real(time_), h, pool_.positions(), pool_.velocities(),
            w.coupled);
}

// Lists (as offsets from `begin`) the particles of a batch whose swept box may touch an
// obstacle: a is the batch's start positions, b its end positions.
std::size_t ParticleSystem::nearList(std::size_t begin, std::size_t count, const Real* a0,
                                     const Real* b0, std::uint16_t* list) const {
  const auto radii = pool_.radii();
  // Many obstacles (bodies): first keep those whose box meets the batch's swept box.
  Aabb batchBox;
  if (obstacleCache_.size() > detail::kMaxParticleStepTests) {
    Real reach = 0;
    for (std::size_t j = 0; j < count; ++j) {
      batchBox.extend(Eigen::Map<const Vec3>(a0 + 3 * j));
      batchBox.extend(Eigen::Map<const Vec3>(b0 + 3 * j));
      reach = std::max(reach, radii[begin + j]);
    }
    batchBox = batchBox.inflated(reach + kSkin);
  }
  NearTest tests[kMaxNearTests];
  std::size_t testCount = 0;
  for (const ObstacleCache& c : obstacleCache_) {
    if (obstacleCache_.size() > detail::kMaxParticleStepTests && !c.plane &&
        !c.bounds.overlaps(batchBox))
      continue;
    if (testCount == kMaxNearTests) {
      // Too many to filter: test everyone.
      for (std::size_t j = 0; j < count; ++j) list[j] = std::uint16_t(j);
      return count;
    }
    tests[testCount++] = nearTest(c);
  }
  return nearParticles({tests, testCount}, a0, b0, &radii[begin], count, list);
}

void ParticleSystem::collideObstacles(std::size_t begin, std::size_t end, const Real* previous,
                                      const std::uint16_t* near, std::size_t nearCount) {
  auto xs = pool_.positions();
  auto vs = pool_.velocities();
  const auto radii = pool_.radii();
  const Real e = settings_.restitution, mu = settings_.friction,
             threshold = settings_.restitutionThreshold;
  // Most particles are far from every obstacle. A vectorised pass over the batch lists those
  // whose swept box (inflated by the radius) may touch one; only they take the full path below.
  const std::size_t count = end - begin;
  const Real* a0 = previous ? previous : &xs[3 * begin];
  const Real* b0 = &xs[3 * begin];
  std::uint16_t list[kBatch];
  const std::uint16_t* pending = near ? near : list;
  const std::size_t listed = near ? nearCount : nearList(begin, count, a0, b0, list);
  // The system's only plane, when there is one: particles near nothing else (most often, those
  // resting on the ground) take a short path that computes what the full one would.
  const ObstacleCache* plane = nullptr;
  if (planeCount_ == 1)
    for (const ObstacleCache& c : obstacleCache_)
      if (c.plane) plane = &c;
  // Those go through the kernels several at a time first (particles resting on the ground,
  // landing on it or about to): the kernels leave in the list the particles that cross the
  // plane twice in a step or come near another obstacle, for the scalar paths below.
  std::size_t pendingCount = listed;
  const detail::SimdLevel isa = detail::particleSimd();
  if (plane && previous && isa != detail::SimdLevel::Scalar &&
      obstacleCache_.size() <= detail::kMaxParticleStepTests) {
    Real boxes[6 * detail::kMaxParticleStepTests];
    std::size_t boxCount = 0;
    for (const ObstacleCache& c : obstacleCache_) {
      if (c.plane) continue;
      for (int k = 0; k < 3; ++k) {
        boxes[6 * boxCount + k] = c.bounds.lower[k];
        boxes[6 * boxCount + 3 + k] = c.bounds.upper[k];
      }
      ++boxCount;
    }
    pendingCount = detail::settleParticlesOnPlane(isa, {.n0 = plane->normal.x(),
                                                     .n1 = plane->normal.y(),
                                                     .n2 = plane->normal.z(),
                                                     .offset = plane->offset,
                                                     .restitution = e,
                                                     .friction = mu,
                                                     .threshold = threshold,
                                                     .skin = kSkin,
                                                     .boxes = boxes,
                                                     .boxCount = boxCount,
                                                     .x = &xs[3 * begin],
                                                     .v = &vs[3 * begin],
                                                     .start = previous,
                                                     .radius = &radii[begin],
                                                     .list = pending,
                                                     .listed = listed,
                                                     .rest = list});
    pending = list;
  }
  for (std::size_t l = 0; l < pendingCount; ++l) {
    const std::size_t i = begin + pending[l];
    Eigen::Map<Vec3> x(&xs[3 * i]);
    Eigen::Map<Vec3> v(&vs[3 * i]);
    const Real r = radii[i];
    Vec3 vel = v;
    Vec3 end1 = x;
    if (plane && collidePlaneOnly(*plane, previous ? &previous[3 * (i - begin)] : nullptr, r, end1, vel)) {
      x = end1;
      v = vel;
      continue;
    }
    if (previous) {
      // Continuous against the static obstacles: follow the swept segment, bouncing at most
      // twice within the step.
      Vec3 start = Eigen::Map<const Vec3>(&previous[3 * (i - begin)]);
      for (int bounce = 0; bounce < 2; ++bounce) {
        const Vec3 sweep = end1 - start;
        if (sweep.squaredNorm() == 0) break;
        const Aabb swept = Aabb{start.cwiseMin(end1), start.cwiseMax(end1)}.inflated(r);
        std::optional<RayHit> first;
        for (const ObstacleCache& c : obstacleCache_) {
          const Real maxFraction = first ? first->fraction : Real(1);
          if (c.plane) {
            // Enters the half-space where the signed distance changes sign from + to -.
            const Real d0 = c.normal.dot(start) - c.offset, d1 = c.normal.dot(end1) - c.offset;
            if (d0 >= 0 && d1 < 0) {
              const Real f = d0 / (d0 - d1);
              if (f < maxFraction) first = RayHit{f, start + f * sweep, c.normal};
            }
            continue;
          }
          if (c.moving || !c.bounds.overlaps(swept)) continue;
          auto hit = castRay(*c.collider, c.pose, Ray{start, sweep, maxFraction});
          if (hit && (!first || hit->fraction < first->fraction)) first = hit;
        }
        if (!first) break;
        const Vec3 before = vel;
        detail::respondToImpact(vel, first->normal, e, mu, threshold);
        // The rest of the step continues from the contact with the new velocity.
        const Real remaining = 1 - first->fraction;
        const Real speedBefore = before.norm();
        start = first->point + first->normal * (r + kSkin);
        end1 = start;
        if (speedBefore > 0) end1 += vel * (remaining * sweep.norm() / speedBefore);
      }
    }
    // Discrete: whatever is still within a radius of an obstacle is pushed out along the normal.
    for (const ObstacleCache& c : obstacleCache_) {
      if (c.plane) {
        const Real d = c.normal.dot(end1) - c.offset;
        if (d < r) {
          end1 += c.normal * (r + kSkin - d);
          detail::respondToImpact(vel, c.normal, e, mu, threshold);
        }
        continue;
      }
      if (!c.bounds.inflated(r).contains(end1)) continue;  // farther than r from the shape
      const PointQuery q = queryPoint(*c.collider, c.pose, end1);
      if (q.distance < r) {
        end1 += q.normal * (r + kSkin - q.distance);
        if (c.moving) {
          // Newton and Coulomb on the velocity relative to the surface point touched.
          const Vec3 surface = c.linearVelocity + c.angularVelocity.cross(q.point - c.center);
          Vec3 relative = vel - surface;
          detail::respondToImpact(relative, q.normal, e, mu, threshold);
          vel = relative + surface;
        } else {
          detail::respondToImpact(vel, q.normal, e, mu, threshold);
        }
      }
    }
    x = end1;
    v = vel;
  }
}

// Particles as spheres of their radii, found through a uniform grid (the seeds' broad phase for
// many equal objects). Jacobi: every particle computes its own correction from a snapshot of
// its neighbours, so the result does not depend on the order or the thread count. Two passes.
void ParticleSystem::collideParticles(detail::StepWorkers& workers) {
  Scratch& w = *scratch_;
  const std::size_t n = pool_.size();
  if (n < 2) return;
  const auto radii = pool_.radii();
  const auto masses = pool_.masses();
  Real maxRadius = 0;
  for (std::size_t i = 0; i < n; ++i) maxRadius = std::max(maxRadius, radii[i]);
  if (maxRadius <= 0) return;
  const Real e = settings_.restitution;
  for (int pass = 0; pass < 2; ++pass) {
    w.snapshotX.assign(pool_.positions().begin(), pool_.positions().end());
    w.snapshotV.assign(pool_.velocities().begin(), pool_.velocities().end());
    w.grid.build({w.snapshotX.data(), 3 * n}, 2 * maxRadius);
    auto xs = pool_.positions();
    auto vs = pool_.velocities();
    const std::size_t batches = (n + kBatch - 1) / kBatch;
    workers.parallelFor(
        batches, 1, [&](std::size_t first, std::size_t last) {
          for (std::size_t b = first; b != last; ++b) {
            const std::size_t end = std::min(n, (b + 1) * kBatch);
            for (std::size_t i = b * kBatch; i < end; ++i) {
              const Vec3 xi = Eigen::Map<const Vec3>(&w.snapshotX[3 * i]);
              const Vec3 vi = Eigen::Map<const Vec3>(&w.snapshotV[3 * i]);
              Vec3 dx = Vec3::Zero(), dv = Vec3::Zero();
              w.grid.forEachNear(xi, [&](std::uint32_t j) {
                if (j == i) return;
                const Vec3 d = xi - Eigen::Map<const Vec3>(&w.snapshotX[3 * j]);
                const Real dist = d.norm(), reach = radii[i] + radii[j];
                if (dist >= reach) return;
                // Coincident centres: separate along a fixed axis chosen by the ids' order.
                const Vec3 nrm = dist > Real(1e-9) ? Vec3(d / dist) : Vec3(i < j ? Vec3(-Vec3::UnitY()) : Vec3(Vec3::UnitY()));
                const Real wi = masses[j] / (masses[i] + masses[j]);  // share of the correction
                dx += wi * (reach - dist) * nrm;
                const Real vn = (vi - Eigen::Map<const Vec3>(&w.snapshotV[3 * j])).dot(nrm);
                if (vn < 0) dv -= wi * (1 + e) * vn * nrm;
              });
              Eigen::Map<Vec3>(&xs[3 * i]) += Real(0.5) * dx;  // Jacobi under-relaxation
              Eigen::Map<Vec3>(&vs[3 * i]) += dv;
            }
          }
        });
    if (obstacleCache_.empty()) continue;
    // Corrections may push particles into obstacles: push them back out (discrete test).
    workers.parallelFor(batches, 1, [&](std::size_t first, std::size_t last) {
      for (std::size_t b = first; b != last; ++b)
        collideObstacles(b * kBatch, std::min(n, (b + 1) * kBatch), nullptr);
    });
  }
}

double ParticleSystem::kineticEnergy() const {
  double e = 0;
  const auto m = pool_.masses();
  for (std::size_t i = 0; i < pool_.size(); ++i) e += 0.5 * double(m[i]) * double(pool_.velocity(i).squaredNorm());
  return e;
}

double ParticleSystem::springEnergy() const {
  double e = 0;
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    const double len = double((pool_.position(springIndex_[2 * s]) - pool_.position(springIndex_[2 * s + 1])).norm());
    const double stretch = len - double(springs_[s].restLength);
    e += 0.5 * double(springs_[s].stiffness) * stretch * stretch;
  }
  return e;
}

}  // namespace inertia
