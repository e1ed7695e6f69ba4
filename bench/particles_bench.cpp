// 1,000,000 particles under gravity and drag over a ground plane and a sphere, symplectic
// Euler: ms per step at 1 thread, 2 threads and all cores (or the counts of --threads 1,2,16) with
// the speed-up over 1 thread, against the machine's memory bandwidth measured in the same run, at
// the same thread count, by a STREAM triad (McCalpin) over arrays as large as the particle state.
// The bound is (bytes the step must read and write) / bandwidth; the goal is at most 1.5x that
// bound. Every thread count must end with the same bits (ParticleSystem's promise).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "inertia/collision/collider.h"
#include "inertia/core/thread_pool.h"
#include "inertia/particles/particle_system.h"
#include "thread_sweep.h"

using namespace inertia;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// STREAM triad a = b + s c over n doubles, in an arena of as many threads as the step it is
// compared with (a ThreadPool keeps its arena to the library).
// Counts 3 * 8 bytes per element, as STREAM does (write-allocate traffic not counted).
double triadBandwidth(tbb::task_arena& arena, std::size_t n) {
  std::vector<double> a(n, 0), b(n, 1), c(n, 2);
  std::vector<double> times;
  for (int rep = 0; rep < 15; ++rep) {
    auto t0 = Clock::now();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) a[i] = b[i] + 3.0 * c[i];
      });
    });
    times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  if (a[n / 2] != 7.0) std::abort();  // keep the loop from being optimised away
  return 24.0 * double(n) / median(times);
}

ParticleSystem makeSystem(std::size_t n) {
  ParticleSystem ps({.capacity = n, .restitution = Real(0.5), .friction = Real(0.1)});
  ps.addField({GravityField{}});
  ps.addField({LinearDragField{Real(1e-4)}});
  ps.addObstacle({Collider(Shape(Plane{Vec3::UnitY(), 0})), Transform{}});
  ps.addObstacle({Collider(Shape(Sphere{1})), Transform{Vec3(0, 1, 0), Quat::Identity()}});
  // Particles spread over a 20 m cube above the ground, immortal, so the count stays n.
  std::uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return Real(double(state >> 11) * 0x1.0p-53);
  };
  for (std::size_t i = 0; i < n; ++i) {
    ParticlePool::Spawn s;
    s.position = Vec3(20 * next() - 10, 20 * next() + Real(0.1), 20 * next() - 10);
    s.velocity = Vec3(next() - Real(0.5), next() - Real(0.5), next() - Real(0.5));
    s.lifetime = std::numeric_limits<Real>::infinity();
    s.radius = Real(0.01);
    ps.pool().add(s);
  }
  return ps;
}

}  // namespace

// Arguments, all optional: the particle count (default 1,000,000); --threads 1,2,16 to choose the
// thread counts (default: 1, 2 and all cores; 1 is always run).
int main(int argc, char** argv) {
  const std::vector<int> counts = bench::threadCounts(argc, argv);
  if (argc > 2) {
    std::fprintf(stderr, "bench_particles: one argument at most (the particle count), got %d\n",
                 argc - 1);
    return 2;
  }
  const std::size_t n =
      argc > 1 ? std::size_t(bench::parseCount("bench_particles: particle count", argv[1], 1,
                                               1L << 31))
               : 1000000;
  const int steps = 60;
  // Bytes a step must move per particle: read position, velocity (3 Reals each), mass, age,
  // lifetime, radius; write position, velocity, age.
  const double bytesPerParticle = double(sizeof(Real)) * (3 + 3 + 1 + 1 + 1 + 1 + 3 + 3 + 1);
  // Triad arrays as large as the particle state (3 arrays of n * bytesPerParticle / 24 doubles).
  const std::size_t triadN =
      std::max<std::size_t>(1 << 20, std::size_t(double(n) * bytesPerParticle / 24));

  std::printf("particles: %zu, Real = %s, %d steps of 1/60 s, symplectic Euler, %d cores,\n", n,
              sizeof(Real) == 4 ? "float" : "double", steps, bench::allCores());
  std::printf("gravity + linear drag, ground plane + sphere obstacle (swept tests)\n\n");
  std::printf("%-8s %12s %10s %14s %14s %10s\n", "threads", "ms/step", "speed-up", "triad GB/s",
              "bound ms", "ratio");
  double oneThread = 0;
  std::uint64_t oneThreadBits = 0;
  std::vector<int> same, different;
  for (int threads : counts) {
    ThreadPool pool(threads);
    ParticleSystem ps = makeSystem(n);
    for (int i = 0; i < 5; ++i) ps.step(Real(1.0 / 60), &pool);  // warm-up: first-touch, sizes
    std::vector<double> times;
    for (int i = 0; i < steps; ++i) {
      auto t0 = Clock::now();
      ps.step(Real(1.0 / 60), &pool);
      times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    const double step = median(times);
    if (threads == 1) oneThread = step;
    tbb::task_arena arena(threads);
    const double bandwidth = triadBandwidth(arena, triadN);
    const double bound = double(n) * bytesPerParticle / bandwidth;
    std::printf("%-8d %12.2f %10.2f %14.2f %14.2f %10.2f\n", threads, 1e3 * step, oneThread / step,
                bandwidth / 1e9, 1e3 * bound, step / bound);
    if (ps.pool().size() != n) std::abort();
    // Every attribute the step writes: positions, velocities and ages.
    bench::BitHash hash;
    hash.add(std::span<const Real>(ps.pool().positions()));
    hash.add(std::span<const Real>(ps.pool().velocities()));
    hash.add(std::span<const Real>(ps.pool().ages()));
    if (threads == 1) oneThreadBits = hash.value();
    (hash.value() == oneThreadBits ? same : different).push_back(threads);
  }
  std::printf(
      "\nms/step: median of the %d steps; speed-up: 1 thread's ms/step over the count's; triad: "
      "STREAM's a = b + 3c in a TBB arena of the same threads; bound: %.0f bytes a particle / "
      "triad bandwidth; ratio: ms/step over the bound.\n",
      steps, bytesPerParticle);
  if (different.empty())
    std::printf("same bits at %s threads (final positions, velocities and ages, FNV-1a %016llx)\n",
                bench::countList(same).c_str(), static_cast<unsigned long long>(oneThreadBits));
  else
    std::printf(
        "*** DIFFERENT BITS *** at %s threads: the final positions, velocities or ages differ from "
        "1 thread's (same at %s)\n",
        bench::countList(different).c_str(), bench::countList(same).c_str());
  return 0;
}
