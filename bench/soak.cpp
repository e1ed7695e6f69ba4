// Soak test (issue 21): every scene of a folder stepped for a long simulated time, checking what
// a long run must keep: no NaN in any body, particle or deformable vertex; the mechanical energy
// of the bodies and deformables bounded (gravity's potential included; particles are left out,
// emitters feed them energy by design); memory (resident set) flat after the warm-up.
//
//   inertia_soak [--seconds S] [--warmup S] [--check-every N] [SCENE.json | FOLDER]...
//
// The hour-long form (issue 21: 216,000 steps at 60 Hz per scene) is `--seconds 3600`; CTest
// runs `soak_short`, a fraction of a second per scene. Exit status 1 when a scene fails.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "inertia/io/scene.h"
#include "inertia/world/world.h"

namespace {

using namespace inertia;

struct Options {
  double seconds = 60;
  double warmup = 5;
  int checkEvery = 60;  // steps between checks (NaN, energy, memory)
  std::vector<std::filesystem::path> scenes;
};

double residentMiB() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

bool finite(std::span<const Real> values) {
  return std::all_of(values.begin(), values.end(), [](Real x) { return std::isfinite(x); });
}

// Everything a step writes is finite.
bool worldFinite(const World& world) {
  const RigidBodySystem& rb = world.rigidBodies();
  for (BodyId b : rb.bodies()) {
    const Transform t = rb.transform(b);
    if (!t.p.allFinite() || !t.q.coeffs().allFinite() || !rb.linearVelocity(b).allFinite() ||
        !rb.angularVelocity(b).allFinite())
      return false;
  }
  for (ParticleSystemId id : world.particleSystems()) {
    const ParticlePool& pool = world.particleSystem(id).pool();
    if (!finite(pool.positions()) || !finite(pool.velocities())) return false;
  }
  for (DeformableId id : world.deformables())
    if (!finite(world.deformable(id).positions()) || !finite(world.deformable(id).velocities()))
      return false;
  return true;
}

// Kinetic energy plus gravity's potential (-m g . x) of the dynamic bodies, and the deformables'
// kinetic and spring energy (their gravity acts through fields, left out: they hang or rest).
double mechanicalEnergy(const World& world) {
  const RigidBodySystem& rb = world.rigidBodies();
  double e = double(rb.kineticEnergy());
  const Vec3 g = world.settings().gravity;
  for (BodyId b : rb.bodies())
    if (rb.type(b) == BodyType::Dynamic)
      e -= double(rb.mass(b)) * double(g.dot(rb.centerOfMass(b)));
  for (DeformableId id : world.deformables())
    e += world.deformable(id).kineticEnergy() + world.deformable(id).springEnergy();
  return e;
}

struct Result {
  long steps = 0;
  double wall = 0;
  double energyWarm = 0, energyMax = 0;  // at the end of the warm-up, and the largest after it
  double rssWarm = 0, rssEnd = 0;        // MiB
  std::string failure;
};

Result soak(const std::filesystem::path& file, const Options& o) {
  Result r;
  std::unique_ptr<World> world = io::instantiate(io::loadScene(file));
  const double h = double(world->settings().dt);
  const long total = std::lround(o.seconds / h), warm = std::lround(o.warmup / h);
  const auto start = std::chrono::steady_clock::now();
  double energyMin = 0;
  bool warmSeen = false;  // a check inside the warm-up has set energyWarm and energyMin
  for (r.steps = 1; r.steps <= total; ++r.steps) {
    world->step(world->settings().dt);
    if (r.steps % o.checkEvery != 0 && r.steps != warm && r.steps != total) continue;
    if (!worldFinite(*world)) {
      r.failure = "NaN or infinity at t = " + std::to_string(world->time()) + " s";
      break;
    }
    const double e = mechanicalEnergy(*world);
    if (r.steps <= warm) {
      r.energyWarm = r.energyMax = warmSeen ? std::max(r.energyWarm, e) : e;
      energyMin = warmSeen ? std::min(energyMin, e) : e;
      warmSeen = true;
      if (r.steps == warm) r.rssWarm = residentMiB();
      continue;
    }
    r.energyMax = std::max(r.energyMax, e);
    // Bounded: never above the warm-up's largest by more than 10% of the warm-up's scale
    // (its largest magnitude and its swing) plus 1 J. Dissipative scenes lose energy; a
    // blow-up gains orders of magnitude.
    const double scale =
        std::max(std::abs(r.energyWarm), std::abs(energyMin)) + (r.energyWarm - energyMin) + 1;
    if (e > r.energyWarm + 0.1 * scale) {
      r.failure = "energy " + std::to_string(e) + " J at t = " + std::to_string(world->time()) +
                  " s, above the warm-up's " + std::to_string(r.energyWarm) + " J";
      break;
    }
  }
  r.steps = std::min(r.steps, total);
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.rssEnd = residentMiB();
  // Flat: no more than 4 MiB or 5% above the warm-up's resident set (allocator noise).
  if (r.failure.empty() && warm < total && r.rssEnd > r.rssWarm + std::max(4.0, 0.05 * r.rssWarm))
    r.failure = "resident memory grew from " + std::to_string(r.rssWarm) + " to " +
                std::to_string(r.rssEnd) + " MiB after the warm-up";
  return r;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&] {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "inertia_soak: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return std::atof(argv[++i]);
    };
    if (a == "--seconds") {
      o.seconds = value();
    } else if (a == "--warmup") {
      o.warmup = value();
    } else if (a == "--check-every") {
      o.checkEvery = int(value());
    } else if (std::filesystem::is_directory(a)) {
      for (const auto& e : std::filesystem::directory_iterator(a))
        if (e.path().extension() == ".json") o.scenes.push_back(e.path());
    } else {
      o.scenes.push_back(a);
    }
  }
  std::sort(o.scenes.begin(), o.scenes.end());
  if (o.scenes.empty() || !(o.seconds > 0) || !(o.warmup >= 0) || o.warmup > o.seconds ||
      o.checkEvery < 1) {
    std::fprintf(stderr,
                 "usage: inertia_soak [--seconds S] [--warmup S <= S] [--check-every N >= 1] "
                 "SCENE.json|FOLDER...\n");
    std::exit(2);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  int failures = 0;
  std::printf("%-22s %9s %8s %14s %14s %9s %9s  %s\n", "scene", "steps", "wall_s", "E_warmup_J",
              "E_max_J", "rss_warm", "rss_end", "result");
  for (const auto& file : o.scenes) {
    Result r;
    try {
      r = soak(file, o);
    } catch (const std::exception& e) {
      r.failure = std::string("exception: ") + e.what();
    }
    failures += r.failure.empty() ? 0 : 1;
    std::printf("%-22s %9ld %8.2f %14.6g %14.6g %8.1fM %8.1fM  %s\n",
                file.filename().string().c_str(), r.steps, r.wall, r.energyWarm, r.energyMax,
                r.rssWarm, r.rssEnd, r.failure.empty() ? "ok" : r.failure.c_str());
    std::fflush(stdout);
  }
  return failures == 0 ? 0 : 1;
}
