#include "inertia/particles/particle_system.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

// Gap kept between a particle's surface and an obstacle after a correction (m): keeps rounding
// from leaving the centre a hair inside, so "never below the plane" holds exactly.
constexpr Real kSkin = Real(1e-4);

// Newton's impact model (seed 000): the normal velocity reverses scaled by e; Coulomb friction
// takes at most mu times the normal velocity change off the tangential velocity.
void respond(Vec3& v, const Vec3& n, Real e, Real mu, Real threshold) {
  const Real vn = v.dot(n);
  if (vn >= 0) return;
  const Real ee = -vn < threshold ? Real(0) : e;
  const Real dvn = -(1 + ee) * vn;
  Vec3 vt = v - vn * n;
  const Real vtNorm = vt.norm();
  if (vtNorm > 0) vt *= std::max(Real(0), 1 - mu * dvn / vtNorm);
  v = vt - ee * vn * n;
}

}  // namespace

struct ParticleSystem::Scratch {
  std::vector<ode::Workspace<Real>> workspaces;  // one per batch (position Verlet keeps history)
  ode::Workspace<Real> coupled;                  // the whole pool, when springs couple particles
  std::vector<Real> previous;                    // start positions, when springs couple all
  std::vector<Real> acceleration;                // coupled integration and backward Euler
  std::vector<std::array<ode::Vector<Real>, 3>> probes;  // per batch: backward Euler's probes
  std::vector<std::uint8_t> dead;
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
}

ParticleSystem::~ParticleSystem() = default;
ParticleSystem::ParticleSystem(ParticleSystem&&) noexcept = default;
ParticleSystem& ParticleSystem::operator=(ParticleSystem&&) noexcept = default;

std::size_t ParticleSystem::addEmitter(const EmitterSettings& emitter) {
  emitters_.emplace_back(emitter);  // the Emitter validates
  return emitters_.size() - 1;
}

std::size_t ParticleSystem::addField(const ForceField& field) {
  validate(field);
  fields_.push_back(field);
  return fields_.size() - 1;
}

std::size_t ParticleSystem::addObstacle(const Obstacle& obstacle) {
  require(obstacle.pose.p.allFinite() && obstacle.pose.q.coeffs().allFinite() &&
              std::fabs(obstacle.pose.q.norm() - 1) < Real(1e-3),
          "Obstacle::pose must be finite with a unit quaternion");
  obstacles_.push_back(obstacle);
  Obstacle& o = obstacles_.back();
  o.pose.q.normalize();
  ObstacleCache cache;
  cache.bounds = worldBounds(o.collider.shape(), o.pose);
  if (const Plane* plane = o.collider.shape().getIf<Plane>()) {
    // n . x <= offset locally; in the world n' = q n and offset' = offset + n' . p.
    cache.plane = true;
    cache.normal = o.pose.rotate(plane->normal);
    cache.offset = plane->offset + cache.normal.dot(o.pose.p);
  }
  obstacleCache_.push_back(cache);
  return obstacles_.size() - 1;
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

void ParticleSystem::step(Real h, tbb::task_arena* arena) {
  require(std::isfinite(h) && h > 0, "ParticleSystem::step: h must be finite and > 0 (s)");
  auto run = [&] {
    for (Emitter& e : emitters_) stats_.emitted += e.emit(pool_, h);
    if (!springs_.empty()) resolveSprings();
    integrate(h);
    if (settings_.particleCollisions) collideParticles();
    const std::size_t n = pool_.size();
    const std::size_t died = pool_.removeFlagged({scratch_->dead.data(), n});
    stats_.died += std::int64_t(died);
    if (died > 0 && !springs_.empty()) resolveSprings();
    time_ += double(h);
  };
  if (arena) arena->execute(run);
  else run();
}

void ParticleSystem::integrate(Real h) {
  Scratch& w = *scratch_;
  const std::size_t n = pool_.size();
  if (n == 0) return;
  const Real t = Real(time_);
  const bool coupled = !springs_.empty();
  const bool collide = !obstacles_.empty();
  if (coupled) {
    // The whole pool moves at once: keep every start position for the swept tests.
    if (collide) std::copy_n(pool_.positions().data(), 3 * n, w.previous.data());
    integrateCoupled(h);
  }

  const std::size_t batches = (n + kBatch - 1) / kBatch;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, batches, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
          const std::size_t begin = b * kBatch, count = std::min(kBatch, n - begin);
          std::span<Real> x = pool_.positions().subspan(3 * begin, 3 * count);
          std::span<Real> v = pool_.velocities().subspan(3 * begin, 3 * count);
          // The batch's start positions for the swept tests, on the stack (24 KiB): they stay in
          // cache between integration and collision instead of streaming through memory.
          Real start[3 * kBatch];
          const Real* previous = coupled ? w.previous.data() + 3 * begin : start;
          if (!coupled && collide) std::copy_n(x.data(), 3 * count, start);
          if (!coupled) {
            const auto m = pool_.masses().subspan(begin, count);
            auto accel = [&](Real time, ode::ConstView<Real> xs, ode::ConstView<Real> vs,
                             ode::View<Real> a) {
              a.setZero();
              applyFields(fields_, FieldBatch{time, {xs.data(), std::size_t(xs.size())},
                                              {vs.data(), std::size_t(vs.size())}, m,
                                              {a.data(), std::size_t(a.size())}});
            };
            if (settings_.integrator == ode::Method::BackwardEuler) {
              // Matrix-free Jacobian products by forward differences of the fields, and
              // BiCGSTAB: attractors and vortices give non-symmetric Jacobians. The probe
              // buffers are the batch's own, grown once.
              auto& probe = w.probes[b];
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
                  if (wrtX) accel(time, shifted, vs, moved);
                  else accel(time, xs, shifted, moved);
                  out = (moved - base) / scale;
                };
              };
              ode::SecondOrderSystem system{accel, product(true), product(false)};
              ode::step(settings_.integrator, system, t, h, x, v, w.workspaces[b],
                        ode::LinearSolverOptions<Real>{.solver = ode::LinearSolver::BiCgStab});
            } else {
              ode::step(settings_.integrator, accel, t, h, x, v, w.workspaces[b]);
            }
          }
          auto age = pool_.ages().subspan(begin, count);
          auto life = pool_.lifetimes().subspan(begin, count);
          for (std::size_t i = 0; i < count; ++i) {
            age[i] += h;
            w.dead[begin + i] = age[i] >= life[i];
          }
          if (collide) collideObstacles(begin, begin + count, previous);
        }
      },
      tbb::simple_partitioner());
}

// Springs couple particles across batches: the whole pool is one system. Fields are still
// evaluated batch by batch in parallel; the springs add their forces in a fixed order.
void ParticleSystem::integrateCoupled(Real h) {
  Scratch& w = *scratch_;
  const std::size_t n = pool_.size();
  const auto m = pool_.masses();
  auto accel = [&](Real time, ode::ConstView<Real> xs, ode::ConstView<Real> vs, ode::View<Real> a) {
    const std::size_t batches = (n + kBatch - 1) / kBatch;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, batches, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const std::size_t begin = b * kBatch, count = std::min(kBatch, n - begin);
            a.segment(3 * begin, 3 * count).setZero();
            applyFields(fields_, FieldBatch{time, {xs.data() + 3 * begin, 3 * count},
                                            {vs.data() + 3 * begin, 3 * count}, m.subspan(begin, count),
                                            {a.data() + 3 * begin, 3 * count}});
          }
        },
        tbb::simple_partitioner());
    springAccelerations({xs.data(), 3 * n}, {vs.data(), 3 * n}, {a.data(), 3 * n});
  };
  ode::step(settings_.integrator, accel, Real(time_), h, pool_.positions(), pool_.velocities(),
            w.coupled);
}

void ParticleSystem::collideObstacles(std::size_t begin, std::size_t end, const Real* previous) {
  auto xs = pool_.positions();
  auto vs = pool_.velocities();
  const auto radii = pool_.radii();
  const Real e = settings_.restitution, mu = settings_.friction,
             threshold = settings_.restitutionThreshold;
  // Most particles are far from every obstacle. A branch-free pass over the batch marks those
  // whose swept box (inflated by the radius) may touch one; only they take the full path.
  const std::size_t count = end - begin;
  float near[kBatch];
  std::fill_n(near, count, 0.0f);
  const Real* a0 = previous ? previous : &xs[3 * begin];
  const Real* b0 = &xs[3 * begin];
  const Real* r0 = &radii[begin];
  for (const ObstacleCache& c : obstacleCache_) {
    if (c.plane) {
      const Real n0 = c.normal.x(), n1 = c.normal.y(), n2 = c.normal.z(), off = c.offset + kSkin;
      for (std::size_t j = 0; j < count; ++j) {
        const Real* a = a0 + 3 * j;
        const Real* b = b0 + 3 * j;
        const Real da = n0 * a[0] + n1 * a[1] + n2 * a[2], db = n0 * b[0] + n1 * b[1] + n2 * b[2];
        near[j] += std::min(da, db) < off + r0[j] ? 1.0f : 0.0f;
      }
    } else {
      const Vec3 lo = c.bounds.lower.array() - kSkin, hi = c.bounds.upper.array() + kSkin;
      for (std::size_t j = 0; j < count; ++j) {
        const Real* a = a0 + 3 * j;
        const Real* b = b0 + 3 * j;
        const Real r = r0[j];
        const bool overlap = std::min(a[0], b[0]) - r <= hi[0] && std::max(a[0], b[0]) + r >= lo[0] &&
                             std::min(a[1], b[1]) - r <= hi[1] && std::max(a[1], b[1]) + r >= lo[1] &&
                             std::min(a[2], b[2]) - r <= hi[2] && std::max(a[2], b[2]) + r >= lo[2];
        near[j] += overlap ? 1.0f : 0.0f;
      }
    }
  }
  for (std::size_t i = begin; i < end; ++i) {
    if (near[i - begin] == 0.0f) continue;
    Eigen::Map<Vec3> x(&xs[3 * i]);
    Eigen::Map<Vec3> v(&vs[3 * i]);
    const Real r = radii[i];
    Vec3 vel = v;
    Vec3 end1 = x;
    if (previous) {
      // Continuous: follow the swept segment, bouncing at most twice within the step.
      Vec3 start = Eigen::Map<const Vec3>(&previous[3 * (i - begin)]);
      for (int bounce = 0; bounce < 2; ++bounce) {
        const Vec3 sweep = end1 - start;
        if (sweep.squaredNorm() == 0) break;
        const Aabb swept = Aabb{start.cwiseMin(end1), start.cwiseMax(end1)}.inflated(r);
        std::optional<RayHit> first;
        for (std::size_t k = 0; k < obstacles_.size(); ++k) {
          const ObstacleCache& c = obstacleCache_[k];
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
          if (!c.bounds.overlaps(swept)) continue;
          auto hit = castRay(obstacles_[k].collider, obstacles_[k].pose, Ray{start, sweep, maxFraction});
          if (hit && (!first || hit->fraction < first->fraction)) first = hit;
        }
        if (!first) break;
        const Vec3 before = vel;
        respond(vel, first->normal, e, mu, threshold);
        // The rest of the step continues from the contact with the new velocity.
        const Real remaining = 1 - first->fraction;
        const Real speedBefore = before.norm();
        start = first->point + first->normal * (r + kSkin);
        end1 = start;
        if (speedBefore > 0) end1 += vel * (remaining * sweep.norm() / speedBefore);
      }
    }
    // Discrete: whatever is still within a radius of an obstacle is pushed out along the normal.
    for (std::size_t k = 0; k < obstacles_.size(); ++k) {
      const ObstacleCache& c = obstacleCache_[k];
      if (c.plane) {
        const Real d = c.normal.dot(end1) - c.offset;
        if (d < r) {
          end1 += c.normal * (r + kSkin - d);
          respond(vel, c.normal, e, mu, threshold);
        }
        continue;
      }
      if (!c.bounds.inflated(r).contains(end1)) continue;  // farther than r from the shape
      const PointQuery q = queryPoint(obstacles_[k].collider, obstacles_[k].pose, end1);
      if (q.distance < r) {
        end1 += q.normal * (r + kSkin - q.distance);
        respond(vel, q.normal, e, mu, threshold);
      }
    }
    x = end1;
    v = vel;
  }
}

// Particles as spheres of their radii, found through a uniform grid (the seeds' broad phase for
// many equal objects). Jacobi: every particle computes its own correction from a snapshot of
// its neighbours, so the result does not depend on the order or the thread count. Two passes.
void ParticleSystem::collideParticles() {
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
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, batches, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t b = r.begin(); b != r.end(); ++b) {
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
        },
        tbb::simple_partitioner());
    if (obstacles_.empty()) continue;
    // Corrections may push particles into obstacles: push them back out (discrete test).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batches, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t b = r.begin(); b != r.end(); ++b)
                          collideObstacles(b * kBatch, std::min(n, (b + 1) * kBatch), nullptr);
                      },
                      tbb::simple_partitioner());
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
