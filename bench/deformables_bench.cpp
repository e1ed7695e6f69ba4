// Deformables against Bullet's soft bodies (btSoftBody), in the same run when Bullet was found
// at configure time.
//
// Cloth: a 1 m square of N x N cells (100 by default, the argument changes it; structural,
// shear and bend springs of 5,000, 500 and 5 N/m, 0.5 kg, damping 0.01 N s/m, thickness 1 cm or
// 0.4 of a cell if less: 4 mm at 100 cells) released flat
// 0.6 m above a static sphere of radius 0.3 m, stepped 120 times at 1/60 s with Inertia's
// implicit Euler (Newton on the incremental potential, modified PCG, tolerance 1e-6 and 1e-3),
// with and without self-collision, on 1, 2 and all threads (the bytes compared). Bullet: the
// same grid from btSoftBodyHelpers::CreatePatch with its shear diagonals and bending
// constraints (distance 2), the same mass, margin 0.01 m, linear stiffness 1, 10 position
// iterations, in a btSoftRigidDynamicsWorld.
//
// Hair: 1,000 strands of 32 segments (33,000 vertices), 0.25 m long, rooted over a head (a
// static sphere of radius 0.1 m) within 1.3 rad of its top by hair(), stretch and bend springs
// of 2,000 and 0.5 N/m, 20 g in all, released straight out and stepped 120 times. Bullet: 1,000
// CreateRope strands between the same root and tip, root fixed, bending constraints
// (distance 2), the same mass, 10 position iterations.
//
// Reported beside the time per step: how far the model ends up stretched (the largest
// stretch-spring strain, (l - L) / L), how deep a vertex went into the obstacle (distance below
// its surface, over all steps; hair roots excluded) and the fastest vertex at the end (jitter
// at rest).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

#ifdef INERTIA_BENCH_BULLET
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>
#endif

using namespace inertia;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kSteps = 120;
constexpr Real kDt = Real(1) / 60;
// Cloth.
constexpr Real kSphere = Real(0.3), kHeight = Real(0.6);
// 1 cm, or less than half a cell: a thickness as wide as the cells would have self-collision
// push apart a flat cloth's own neighbours.
Real clothThickness(int cells) { return std::min(Real(0.01), Real(0.4) / Real(cells)); }
constexpr Real kClothMass = Real(0.5);
// Hair.
constexpr int kStrands = 1000, kSegments = 32;
constexpr Real kHead = Real(0.1), kCap = Real(1.3), kHairLength = Real(0.25);
constexpr Real kHairMass = Real(0.02), kHairThickness = Real(0.002);

struct Result {
  double msPerStep = 0;
  double strain = 0;       // largest stretch-spring strain at the end
  double penetration = 0;  // deepest distance below the obstacle's surface (m), over all steps
  double speed = 0;        // fastest vertex at the end (m/s)
  double newton = 0;       // Inertia: Newton iterations per step
  double iterations = 0;   // Inertia: PCG iterations per step
  int converged = 0;       // Inertia: steps whose solve met the tolerance
};

// One scene: its model, settings, obstacle radius, and which vertices are roots (not measured).
struct Scene {
  MassSpringModel model;
  DeformableSettings settings;
  Real obstacle = 0;
  std::size_t rootEvery = 0;  // hair: every (segments + 1)-th vertex is a pinned root
};

Scene clothScene(int cells, bool selfCollision, double tolerance) {
  return {cloth({.pose = {Vec3(0, kHeight, 0), Quat::Identity()},
                 .size = {1, 1},
                 .resolution = {cells, cells},
                 .mass = kClothMass,
                 .stiffness = {.stretch = 5000, .shear = 500, .bend = 5},
                 .damping = Real(0.01)}),
          {.thickness = clothThickness(cells),
           .friction = Real(0.3),
           .solverTolerance = tolerance,
           .selfCollision = selfCollision},
          kSphere,
          0};
}

MassSpringModel hairModel() {
  return hair({.radius = kHead,
               .capAngle = kCap,
               .strands = kStrands,
               .segments = kSegments,
               .length = kHairLength,
               .mass = kHairMass,
               .stiffness = {.stretch = 2000, .bend = Real(0.5)},
               .damping = Real(0.001)});
}

Scene hairScene(double tolerance) {
  return {hairModel(),
          {.thickness = kHairThickness, .friction = Real(0.2), .solverTolerance = tolerance},
          kHead,
          std::size_t(kSegments + 1)};
}

double below(const Vec3& x, Real radius) {
  return std::max(0.0, double(radius) - double(x.norm()));
}

Result runInertia(const Scene& scene, ThreadPool* pool = nullptr,
                  std::vector<Real>* end = nullptr) {
  Deformable d(scene.settings, scene.model);
  d.addField({GravityField{}});
  d.addObstacle({Collider(Sphere{scene.obstacle}), Transform{}});
  const auto measured = [&](std::size_t i) { return !scene.rootEvery || i % scene.rootEvery; };
  Result r;
  double seconds = 0;
  long iterations = 0, newton = 0;
  for (int s = 0; s < kSteps; ++s) {
    const auto t0 = Clock::now();
    d.step(kDt, pool);
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    iterations += d.lastSolve().iterations;
    newton += d.lastSolve().newtonIterations;
    r.converged += d.lastSolve().converged;
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      if (measured(i))
        r.penetration = std::max(r.penetration, below(d.position(i), scene.obstacle));
  }
  r.msPerStep = 1e3 * seconds / kSteps;
  r.iterations = double(iterations) / kSteps;
  r.newton = double(newton) / kSteps;
  for (const Spring& sp : d.springs())
    if (sp.kind == SpringKind::Stretch)
      r.strain = std::max(r.strain,
                          double((d.position(sp.a) - d.position(sp.b)).norm() / sp.restLength - 1));
  for (std::size_t i = 0; i < d.vertexCount(); ++i)
    r.speed = std::max(r.speed, double(d.velocity(i).norm()));
  if (end)
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      for (const Vec3& value : {d.position(i), d.velocity(i)})
        end->insert(end->end(), value.data(), value.data() + 3);
  return r;
}

#ifdef INERTIA_BENCH_BULLET
// Bullet's soft-rigid world with a static sphere of `radius`; `make` makes the soft bodies.
// Their stretch links are those no longer at rest than `stretchLength` (m) (diagonal and
// bending links are longer); with `skipRoots`, node 0 of each is a root (not measured).
Result runBullet(Real radius,
                 const std::function<std::vector<btSoftBody*>(btSoftBodyWorldInfo&)>& make,
                 Real stretchLength, bool skipRoots) {
  btSoftBodyRigidBodyCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, btScalar(-9.81), 0));
  btSoftBodyWorldInfo& info = world.getWorldInfo();
  info.m_gravity = world.getGravity();
  info.m_sparsesdf.Initialize();
  btSphereShape sphere(radius);
  btRigidBody ball(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &sphere));
  world.addRigidBody(&ball);
  const std::vector<btSoftBody*> bodies = make(info);
  for (btSoftBody* b : bodies) world.addSoftBody(b);

  Result r;
  double seconds = 0;
  for (int s = 0; s < kSteps; ++s) {
    const auto t0 = Clock::now();
    world.stepSimulation(kDt, 1, kDt);
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    for (btSoftBody* b : bodies)
      for (int i = skipRoots ? 1 : 0; i < b->m_nodes.size(); ++i) {
        const btVector3& x = b->m_nodes[i].m_x;
        r.penetration = std::max(r.penetration, below(Vec3(x.x(), x.y(), x.z()), radius));
      }
  }
  r.msPerStep = 1e3 * seconds / kSteps;
  for (btSoftBody* b : bodies) {
    for (int k = 0; k < b->m_links.size(); ++k) {
      const btSoftBody::Link& l = b->m_links[k];
      if (l.m_rl > btScalar(1.01) * stretchLength) continue;
      r.strain = std::max(r.strain, double((l.m_n[0]->m_x - l.m_n[1]->m_x).length() / l.m_rl - 1));
    }
    for (int i = 0; i < b->m_nodes.size(); ++i)
      r.speed = std::max(r.speed, double(b->m_nodes[i].m_v.length()));
    world.removeSoftBody(b);
    delete b;
  }
  world.removeRigidBody(&ball);
  return r;
}

Result runBulletCloth(int cells) {
  return runBullet(
      kSphere,
      [&](btSoftBodyWorldInfo& info) {
        const btScalar h = kHeight;
        btSoftBody* cloth = btSoftBodyHelpers::CreatePatch(
            info, btVector3(-0.5, h, -0.5), btVector3(0.5, h, -0.5), btVector3(-0.5, h, 0.5),
            btVector3(0.5, h, 0.5), cells + 1, cells + 1, 0, true);
        cloth->m_materials[0]->m_kLST = 1;
        cloth->generateBendingConstraints(2, cloth->m_materials[0]);
        cloth->m_cfg.piterations = 10;
        cloth->m_cfg.kDF = btScalar(0.3);
        cloth->setTotalMass(kClothMass);
        cloth->getCollisionShape()->setMargin(clothThickness(cells));
        return std::vector<btSoftBody*>{cloth};
      },
      Real(1) / Real(cells), false);
}

// One CreateRope per strand of hairModel(), root to tip, the root fixed (mass 0).
Result runBulletHair() {
  const MassSpringModel m = hairModel();
  const std::size_t perStrand = std::size_t(kSegments + 1);
  return runBullet(
      kHead,
      [&](btSoftBodyWorldInfo& info) {
        std::vector<btSoftBody*> strands;
        for (std::size_t root = 0; root < m.vertexCount(); root += perStrand) {
          const Vec3 a = m.positions[root], b = m.positions[root + perStrand - 1];
          btSoftBody* strand = btSoftBodyHelpers::CreateRope(
              info, btVector3(a.x(), a.y(), a.z()), btVector3(b.x(), b.y(), b.z()),
              kSegments - 1, 1);
          strand->m_materials[0]->m_kLST = 1;
          strand->generateBendingConstraints(2, strand->m_materials[0]);
          strand->m_cfg.piterations = 10;
          strand->m_cfg.kDF = btScalar(0.2);
          strand->setTotalMass(kHairMass / kStrands);
          strand->setMass(0, 0);
          strand->getCollisionShape()->setMargin(kHairThickness);
          strands.push_back(strand);
        }
        return strands;
      },
      kHairLength / kSegments, true);
}
#endif

void header() {
  std::printf(
      "| engine | ms/step | max strain | deepest in obstacle (m) | max speed at end (m/s) | "
      "Newton / PCG iterations per step, steps converged |\n|---|---|---|---|---|---|\n");
}

void row(const std::string& name, const Result& r, bool iterations) {
  std::printf("| %s | %.2f | %.3f | %.4f | %.3f |", name.c_str(), r.msPerStep, r.strain,
              r.penetration, r.speed);
  if (iterations)
    std::printf(" %.1f / %.0f, %d of %d |\n", r.newton, r.iterations, r.converged, kSteps);
  else
    std::printf(" - |\n");
  std::fflush(stdout);  // a row as soon as it is measured: a run takes up to an hour
}

// The scene at tolerance 1e-6 on 2 threads and on every core: rows, and whether the final
// bytes equal the single thread's.
void threadRows(const Scene& scene) {
  std::vector<Real> serial;
  runInertia(scene, nullptr, &serial);
  std::vector<int> counts = {2};
  if (int(std::thread::hardware_concurrency()) > 2)
    counts.push_back(int(std::thread::hardware_concurrency()));
  for (int threads : counts) {
    ThreadPool pool(threads);
    std::vector<Real> end;
    const Result r = runInertia(scene, &pool, &end);
    const bool same = end.size() == serial.size() &&
                      std::memcmp(end.data(), serial.data(), end.size() * sizeof(Real)) == 0;
    row("Inertia implicit Euler, tolerance 1e-6, " + std::to_string(threads) + " threads (" +
            (same ? "same bytes" : "BYTES DIFFER") + ")",
        r, true);
  }
}

void clothTable(int cells) {
  const int n = (cells + 1) * (cells + 1);
  std::printf("\nCloth %d x %d (%d vertices) dropped on a sphere, %d steps of 1/60 s, one thread "
              "unless said.\n\n",
              cells, cells, n, kSteps);
  header();
  const Result plain = runInertia(clothScene(cells, false, 1e-6));
  row("Inertia implicit Euler, tolerance 1e-6", plain, true);
  const Result loose = runInertia(clothScene(cells, false, 1e-3));
  row("Inertia implicit Euler, tolerance 1e-3", loose, true);
  const Result self = runInertia(clothScene(cells, true, 1e-6));
  row("Inertia implicit Euler, 1e-6, + self-collision", self, true);
  threadRows(clothScene(cells, false, 1e-6));
#ifdef INERTIA_BENCH_BULLET
  const Result bullet = runBulletCloth(cells);
  row("Bullet btSoftBody (10 position iterations)", bullet, false);
  std::printf(
      "\nInertia / Bullet time: %.2f at tolerance 1e-6, %.2f at 1e-3, %.2f with self-collision\n",
      plain.msPerStep / bullet.msPerStep, loose.msPerStep / bullet.msPerStep,
      self.msPerStep / bullet.msPerStep);
#endif
}

void hairTable() {
  std::printf("\nHair: %d strands of %d segments (%d vertices) on a head, %d steps of 1/60 s, "
              "one thread unless said.\n\n",
              kStrands, kSegments, kStrands * (kSegments + 1), kSteps);
  header();
  const Result plain = runInertia(hairScene(1e-6));
  row("Inertia implicit Euler, tolerance 1e-6", plain, true);
  const Result loose = runInertia(hairScene(1e-3));
  row("Inertia implicit Euler, tolerance 1e-3", loose, true);
  threadRows(hairScene(1e-6));
#ifdef INERTIA_BENCH_BULLET
  const Result bullet = runBulletHair();
  row("Bullet btSoftBody ropes (10 position iterations)", bullet, false);
  std::printf("\nInertia / Bullet time: %.2f at tolerance 1e-6, %.2f at 1e-3\n",
              plain.msPerStep / bullet.msPerStep, loose.msPerStep / bullet.msPerStep);
#endif
}

}  // namespace

// bench_deformables [CELLS] [SCENES]: the cloth's cells per side (100 unless given,
// 1..1000), and which tables: cloth, hair or all (the default).
int main(int argc, char** argv) {
  const int cells = argc > 1 ? std::atoi(argv[1]) : 100;
  if (cells < 1 || cells > 1000) {
    std::fprintf(stderr, "bench_deformables: CELLS must be in 1..1000 (got '%s')\n", argv[1]);
    return 2;
  }
  const std::string scenes = argc > 2 ? argv[2] : "all";
  if (scenes != "cloth" && scenes != "hair" && scenes != "all") {
    std::fprintf(stderr, "bench_deformables: SCENES must be cloth, hair or all (got '%s')\n",
                 argv[2]);
    return 2;
  }
#ifndef INERTIA_BENCH_BULLET
  std::printf("Bullet not found at configure time: no btSoftBody comparison.\n");
#endif
  if (scenes != "hair") clothTable(cells);
  if (scenes != "cloth") hairTable();
  return 0;
}
