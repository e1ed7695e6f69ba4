// Rigid bodies against Bullet 3 (btDiscreteDynamicsWorld: btDbvtBroadphase,
// btSequentialImpulseConstraintSolver with its default 10 iterations) and, when it is installed,
// ODE (hash space, dWorldQuickStep with its default 20 iterations) in the same run, the peers on
// one thread, sleeping off in all, 600 steps of 1/60 s. Inertia runs at 1 thread beside them,
// then at 2 threads and at all cores (or the counts of --threads 1,2,16), with its speed-up over
// 1 thread and a check that every count ends with the same bits. The scenes come from the shared
// builders' BodyDesc lists and are built from the same list in every engine:
// - pyramid: a 2D-style wall of unit boxes, base 40 (820 boxes), on a ground plane;
// - pile: 4,000 spheres (r 0.5 m) in 20 x 20 columns of 10 layers, spacing 1.1 m, falling into
//   a 25 x 25 m box (ground plane + 4 static box walls);
// - rain: 2,000 unit boxes at random positions and orientations (fixed seed) onto a ground plane.
// Friction 0.6, restitution 0, density 1000 kg/m^3, gravity -9.81 m/s^2. Reported: mean ms per
// step (Inertia's phase split from World::phaseTimes()) and stability checks: the pyramid's
// largest box displacement (it "stands" when no box moved more than 0.25 m), bodies below
// y = -1 m (fell through the ground), bodies outside the pile's box, non-finite states and the
// final kinetic energy.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>
#ifdef INERTIA_BENCH_ODE
#include <ode/ode.h>
#endif

#include "inertia/world/builders.h"
#include "inertia/world/world.h"
#include "peers.h"
#include "thread_sweep.h"

using namespace inertia;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kSteps = 600;
constexpr Real kDt = Real(1.0 / 60);
constexpr Real kFriction = Real(0.6);
constexpr double kPileHalfWidth = 12.5;  // m, inner faces of the pile's walls

// A scene: the static bodies (ground, walls) and the dynamic ones, as engine-agnostic lists.
struct Scene {
  std::string name;
  std::vector<BodyDesc> statics;
  std::vector<BodyDesc> dynamics;
};

Material material() { return {.density = 1000, .friction = kFriction, .restitution = 0}; }

BodyDesc ground() {
  BodyDesc d;
  d.settings.type = BodyType::Static;
  d.shapes.push_back({Plane{Vec3::UnitY(), 0}, material(), {}});
  return d;
}

BodyDesc staticBox(const Vec3& center, const Vec3& halfExtents) {
  BodyDesc d;
  d.settings.type = BodyType::Static;
  d.settings.position = center;
  d.shapes.push_back({Box{halfExtents}, material(), {}});
  return d;
}

Scene pyramidScene() {
  return {"pyramid", {ground()}, pyramid({.base = 40, .material = material()})};
}

Scene pileScene() {
  const Real spacing = Real(1.1);
  const Real first = -Real(19) * spacing / 2;  // centres the 20 columns on the origin
  Scene s{"pile",
          {ground()},
          grid({.counts = {20, 10, 20},
                .spacing = Vec3::Constant(spacing),
                .origin = Vec3(first, 1, first),
                .shape = Sphere{Real(0.5)},
                .material = material()})};
  // Walls 1 m thick and 12 m high, inner faces at +-12.5 m.
  const Real c = Real(kPileHalfWidth) + Real(0.5), h = 6;
  s.statics.push_back(staticBox(Vec3(c, h, 0), Vec3(Real(0.5), h, c + Real(0.5))));
  s.statics.push_back(staticBox(Vec3(-c, h, 0), Vec3(Real(0.5), h, c + Real(0.5))));
  s.statics.push_back(staticBox(Vec3(0, h, c), Vec3(c + Real(0.5), h, Real(0.5))));
  s.statics.push_back(staticBox(Vec3(0, h, -c), Vec3(c + Real(0.5), h, Real(0.5))));
  return s;
}

Scene rainScene() {
  // A 40 x 40 x 40 m volume (about 32 m^3 per box): some boxes start overlapping, the same
  // ones in both engines.
  return {"rain",
          {ground()},
          rain({.count = 2000,
                .lower = Vec3(-20, 2, -20),
                .upper = Vec3(20, 42, 20),
                .shape = Box{Vec3::Constant(Real(0.5))},
                .material = material(),
                .seed = 7})};
}

// What a run measured.
struct Result {
  double msPerStep = 0;
  PhaseTimes phases{};  // Inertia only (s, summed over the steps)
  bool hasPhases = false;
  double maxDisplacement = 0;  // m, final position against the start
  int fellThrough = 0;         // bodies below y = -1 m
  int outsideBox = 0;          // pile: bodies outside the walls
  int nonFinite = 0;
  double kineticEnergy = 0;  // J
  // Inertia only: every dynamic body's position, orientation (x, y, z, w), linear and angular
  // velocity, kStateSize Reals a body, which every thread count must reproduce bit for bit.
  std::vector<Real> finalState;
};

constexpr std::size_t kStateSize = 13;

// The checks on final positions, shared by the engines.
void checkPositions(const Scene& scene, const std::vector<Vec3>& final, Result& r) {
  for (std::size_t i = 0; i < final.size(); ++i) {
    const Vec3& p = final[i];
    if (!p.allFinite()) {
      ++r.nonFinite;
      continue;
    }
    r.maxDisplacement =
        std::max(r.maxDisplacement, double((p - scene.dynamics[i].settings.position).norm()));
    if (p.y() < -1) ++r.fellThrough;
    if (scene.name == "pile" &&
        (std::abs(p.x()) > kPileHalfWidth || std::abs(p.z()) > kPileHalfWidth))
      ++r.outsideBox;
  }
}

Result runInertia(const Scene& scene, const SolverSettings& solver, int threads) {
  World world({.solver = solver, .threads = threads, .sleeping = false});
  for (const BodyDesc& d : scene.statics) addBody(world, d);
  std::vector<BodyId> ids;
  ids.reserve(scene.dynamics.size());
  for (const BodyDesc& d : scene.dynamics) ids.push_back(addBody(world, d));

  double total = 0;
  for (int i = 0; i < kSteps; ++i) {
    const auto t0 = Clock::now();
    world.step(kDt);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  Result r;
  r.msPerStep = 1e3 * total / kSteps;
  r.phases = world.phaseTimes();
  r.hasPhases = true;
  std::vector<Vec3> final;
  for (BodyId id : ids) {
    const Transform x = world.transform(id);
    const Vec3 v = world.linearVelocity(id), w = world.angularVelocity(id);
    final.push_back(x.p);
    r.finalState.insert(r.finalState.end(), x.p.data(), x.p.data() + 3);
    r.finalState.insert(r.finalState.end(), x.q.coeffs().data(), x.q.coeffs().data() + 4);
    r.finalState.insert(r.finalState.end(), v.data(), v.data() + 3);
    r.finalState.insert(r.finalState.end(), w.data(), w.data() + 3);
  }
  checkPositions(scene, final, r);
  r.kineticEnergy = double(world.rigidBodies().kineticEnergy());
  return r;
}

Result runBullet(const Scene& scene) {
  bench::BulletWorld world;
  std::vector<btRigidBody*> dynamic;
  for (const BodyDesc& d : scene.statics) world.add(d);
  for (const BodyDesc& d : scene.dynamics) dynamic.push_back(world.add(d));
  double total = 0;
  for (int i = 0; i < kSteps; ++i) {
    const auto t0 = Clock::now();
    world.step(kDt);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  Result r;
  r.msPerStep = 1e3 * total / kSteps;
  std::vector<Vec3> final;
  for (const btRigidBody* b : dynamic) {
    const btVector3& p = b->getCenterOfMassPosition();
    final.emplace_back(Real(p.x()), Real(p.y()), Real(p.z()));
    r.kineticEnergy += bench::BulletWorld::kineticEnergy(*b);
  }
  checkPositions(scene, final, r);
  return r;
}

#ifdef INERTIA_BENCH_ODE
Result runOde(const Scene& scene) {
  bench::OdeWorld w{double(kFriction)};
  std::vector<dBodyID> dynamic;
  for (const BodyDesc& d : scene.statics) w.add(d);
  for (const BodyDesc& d : scene.dynamics) dynamic.push_back(w.add(d));
  double total = 0;
  for (int i = 0; i < kSteps; ++i) {
    const auto t0 = Clock::now();
    w.step(kDt);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  Result r;
  r.msPerStep = 1e3 * total / kSteps;
  std::vector<Vec3> final;
  for (const dBodyID b : dynamic) {
    const dReal* p = dBodyGetPosition(b);
    final.emplace_back(Real(p[0]), Real(p[1]), Real(p[2]));
    r.kineticEnergy += bench::OdeWorld::kineticEnergy(b);
  }
  checkPositions(scene, final, r);
  return r;
}
#endif

std::string phaseSplit(const Result& r) {
  return bench::phaseSplit(r.hasPhases ? &r.phases : nullptr, kSteps);
}

void printTableHeader() {
  std::printf(
      "| scene | engine | bodies | ms/step | Inertia broad / narrow / solver / integ. ms | "
      "max disp. m | below -1 m | outside box | non-finite | final KE J |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
}

void printRow(const Scene& scene, const char* engine, const Result& r) {
  char disp[48] = "-";  // only the pyramid should stay where it was built
  if (scene.name == "pyramid")
    std::snprintf(disp, sizeof disp, "%.3f (%s)", r.maxDisplacement,
                  r.maxDisplacement <= 0.25 ? "stands" : "fell");
  char outside[16] = "-";
  if (scene.name == "pile") std::snprintf(outside, sizeof outside, "%d", r.outsideBox);
  std::printf("| %s | %s | %zu | %.2f | %s | %s | %d | %s | %d | %.4g |\n", scene.name.c_str(),
              engine, scene.dynamics.size(), r.msPerStep, phaseSplit(r).c_str(), disp,
              r.fellThrough, outside, r.nonFinite, r.kineticEnergy);
  std::fflush(stdout);
}

// One Inertia configuration at every thread count, runs[k] at counts[k] (counts[0] is 1).
struct ThreadRuns {
  std::string label;
  SolverSettings solver;
  std::vector<Result> runs;
};

void printThreadTable(const Scene& scene, const std::vector<int>& counts,
                      const std::vector<ThreadRuns>& configs) {
  std::printf(
      "\n| %s: Inertia | threads | ms/step | speed-up vs 1 thread | broad / narrow / solver / "
      "integ. ms |\n",
      scene.name.c_str());
  std::printf("|---|---|---|---|---|\n");
  for (const ThreadRuns& c : configs)
    for (std::size_t k = 0; k < counts.size(); ++k)
      std::printf("| %s | %d | %.2f | %.2f | %s |\n", c.label.c_str(), counts[k],
                  c.runs[k].msPerStep, c.runs[0].msPerStep / c.runs[k].msPerStep,
                  phaseSplit(c.runs[k]).c_str());
}

// The machine's bound on those speed-ups (bench::sideBySideMs): the default solver's
// one-thread run alone, then as many copies of it at once as a count has threads, in turn
// `repeat` times, the fastest of each kept.
void printMachineBound(const Scene& scene, const std::vector<int>& counts, int repeat) {
  std::vector<int> copies;
  for (int n : counts)
    if (n > 1 && n <= bench::allCores()) copies.push_back(n);
  if (copies.empty()) return;
  const auto one = [&scene] { return runInertia(scene, {}, 1).msPerStep; };
  double alone = std::numeric_limits<double>::infinity();
  std::vector<double> together(copies.size(), alone);
  for (int rep = 0; rep < repeat; ++rep) {
    alone = std::min(alone, one());
    for (std::size_t k = 0; k < copies.size(); ++k)
      together[k] = std::min(together[k], bench::sideBySideMs(copies[k], one));
  }
  std::printf(
      "\n| %s: machine bound | copies at once | ms/step alone | ms/step each, side by side | "
      "bound on the speed-up | core-to-core round trip ns |\n|---|---|---|---|---|---|\n",
      scene.name.c_str());
  const double trip = bench::roundTripNs();
  for (std::size_t k = 0; k < copies.size(); ++k)
    std::printf("| defaults, 1 thread each | %d | %.2f | %.2f | %.2f | %.0f |\n", copies[k], alone,
                together[k], copies[k] * alone / together[k], trip);
}

// Compares every thread count's final state with 1 thread's, byte for byte; prints "same bits"
// or a loud line naming the first body that differs. Returns whether all were the same.
bool checkSameBits(const Scene& scene, const std::vector<int>& counts, const ThreadRuns& c) {
  const std::vector<Real>& ref = c.runs[0].finalState;
  bool same = true;
  for (std::size_t k = 1; k < counts.size(); ++k) {
    const std::vector<Real>& s = c.runs[k].finalState;
    std::size_t differ = 0, first = 0;
    for (std::size_t i = 0; i < ref.size() / kStateSize; ++i) {
      if (std::memcmp(&ref[i * kStateSize], &s[i * kStateSize], kStateSize * sizeof(Real)) == 0)
        continue;
      if (differ++ == 0) first = i;
    }
    if (differ == 0) continue;
    same = false;
    // Positions at offset 0 of a body's state, linear velocities at 7.
    const Real* a = &ref[first * kStateSize];
    const Real* b = &s[first * kStateSize];
    const double dx = (Eigen::Map<const Vec3>(b) - Eigen::Map<const Vec3>(a)).norm();
    const double dv = (Eigen::Map<const Vec3>(b + 7) - Eigen::Map<const Vec3>(a + 7)).norm();
    std::printf(
        "*** DIFFERENT BITS *** %s, %s: at %d threads %zu of %zu bodies end otherwise than at 1 "
        "thread (first: body %zu, position off by %.3g m, velocity by %.3g m/s)\n",
        scene.name.c_str(), c.label.c_str(), counts[k], differ, ref.size() / kStateSize, first, dx,
        dv);
  }
  if (same) {
    bench::BitHash hash;
    hash.add(std::span<const Real>(ref));
    std::printf(
        "%s, %s: same bits at %s threads (final positions, orientations and velocities of the %zu "
        "bodies, FNV-1a %016llx)\n",
        scene.name.c_str(), c.label.c_str(), bench::countList(counts).c_str(),
        ref.size() / kStateSize, static_cast<unsigned long long>(hash.value()));
  }
  std::fflush(stdout);
  return same;
}

}  // namespace

// Arguments, all optional: scene names to run (default: all three); --threads 1,2,16 to choose
// Inertia's thread counts (default: 1, 2 and all cores; 1 is always run); --repeat N to time
// each count N times in turn and keep the fastest (default 1).
int main(int argc, char** argv) {
  const std::vector<int> counts = bench::threadCounts(argc, argv);
  const int repeat = bench::repeatCount(argc, argv);
  const std::vector<std::string> only =
      bench::sceneNames(argc, argv, "bench_rigid_bodies", {"pyramid", "pile", "rain"});
#ifdef INERTIA_BENCH_ODE
  dInitODE2(0);
#endif
  std::printf(
      "rigid bodies: %d steps of 1/60 s, peers on 1 thread, Inertia on 1 thread beside them, then "
      "on %s threads below each scene (%d cores), sleeping off, Real = %s, Bullet btScalar = %s; "
      "friction 0.6, restitution 0, density 1000 kg/m^3; Inertia's contact kernels: %s "
      "(INERTIA_SIMD=avx2 or sse2 caps every kernel's set)\n",
      kSteps, bench::countList(counts).c_str(), bench::allCores(),
      sizeof(Real) == 4 ? "float" : "double", sizeof(btScalar) == 4 ? "float" : "double",
      contactSolverInstructionSet());
  int differentBits = 0;
  for (const Scene& scene : {pyramidScene(), pileScene(), rainScene()}) {
    if (!only.empty() && std::find(only.begin(), only.end(), scene.name) == only.end()) continue;
    const WorldSettings defaults;
    std::vector<ThreadRuns> configs = {
        {"Inertia soft_step (defaults: " + std::to_string(defaults.substeps) + " substeps, " +
             std::to_string(defaults.solver.iterations) + " it. + " +
             std::to_string(defaults.solver.relaxIterations) + " relax)",
         {},
         {}},
        {"Inertia soft_step (4 substeps, 2 it. + 1 relax)", {.iterations = 2}, {}}};
    // Inertia on 1 thread against the single-threaded peers, as a table of its own per scene so
    // that the scene's thread counts can follow it.
    std::printf("\n");
    printTableHeader();
    for (ThreadRuns& c : configs) {
      c.runs.push_back(runInertia(scene, c.solver, 1));
      printRow(scene, c.label.c_str(), c.runs[0]);
    }
    printRow(scene, "Bullet SI (10 it., split impulse)", runBullet(scene));
#ifdef INERTIA_BENCH_ODE
    printRow(scene, "ODE QuickStep (20 it.)", runOde(scene));
#endif
    for (ThreadRuns& c : configs)
      for (std::size_t k = 1; k < counts.size(); ++k)
        c.runs.push_back(runInertia(scene, c.solver, counts[k]));
    // --repeat: each count again, in turn, keeping the fastest run (their bits are compared
    // too: every run of every count must end the same).
    for (int rep = 1; rep < repeat; ++rep)
      for (ThreadRuns& c : configs)
        for (std::size_t k = 0; k < counts.size(); ++k) {
          Result r = runInertia(scene, c.solver, counts[k]);
          const std::vector<Real>& first = c.runs[k].finalState;
          if (r.finalState.size() != first.size() ||
              std::memcmp(r.finalState.data(), first.data(), first.size() * sizeof(Real)) != 0) {
            std::printf(
                "*** DIFFERENT BITS *** %s, %s: run %d at %d threads ends otherwise "
                "than the first\n",
                scene.name.c_str(), c.label.c_str(), rep + 1, counts[k]);
            ++differentBits;
          } else if (r.msPerStep < c.runs[k].msPerStep) {
            c.runs[k] = std::move(r);
          }
        }
    printThreadTable(scene, counts, configs);
    for (const ThreadRuns& c : configs) differentBits += checkSameBits(scene, counts, c) ? 0 : 1;
    printMachineBound(scene, counts, repeat);
  }
  std::printf(
      "\nms/step: mean wall-clock time of the %d steps%s. Inertia's phase split from "
      "World::phaseTimes(); its speed-up is its ms/step on 1 thread over that on the count "
      "(WorldSettings::threads, the size of its TBB arena). Machine bound: N independent worlds "
      "on 1 thread each stepped at once share only the machine (caches, memory bandwidth, a "
      "virtual machine's host); N threads of one world share at least that, so N x alone / side "
      "by side bounds any N-thread speed-up on this machine. Core-to-core round trip: two threads "
      "handing a cache line to each other and back, what each meeting of a step's workers "
      "costs at least (one step has hundreds). Bullet: btDiscreteDynamicsWorld, "
      "btDbvtBroadphase, btSequentialImpulseConstraintSolver (defaults: 10 iterations, split "
      "impulse, warm starting 0.85), stepSimulation(1/60, 0), DISABLE_DEACTIVATION.%s Pyramid "
      "max disp.: the largest final displacement of a box from its start; it stands when <= "
      "0.25 m.\n",
      kSteps,
      repeat > 1 ? (" (Inertia's thread table: the fastest of " + std::to_string(repeat) +
                    " runs of each count, taken in turn)")
                       .c_str()
                 : "",
#ifdef INERTIA_BENCH_ODE
      " ODE (double): dHashSpace, up to 4 contacts a pair, dContactApprox1 with mu 0.6, "
      "default ERP 0.2 and CFM, dWorldQuickStep (default 20 iterations), auto-disable off."
#else
      " ODE not built (libode-dev not found)."
#endif
  );
  if (differentBits > 0)
    std::printf(
        "\n*** DIFFERENT BITS *** in %d of Inertia's configurations: its result depends on "
        "the thread count (DESIGN.md section 7 says it must not)\n",
        differentBits);
#ifdef INERTIA_BENCH_ODE
  dCloseODE();
#endif
  return 0;
}
