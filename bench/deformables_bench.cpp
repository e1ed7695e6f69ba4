// Cloth: a 1 m square of 40 x 40 cells (1,681 vertices; structural, shear and bend springs of
// 5,000, 500 and 5 N/m, 0.5 kg, damping 0.01 N s/m) released flat 0.6 m above a static sphere
// of radius 0.3 m, stepped 120 times at 1/60 s with Inertia's implicit Euler (Newton on the
// incremental potential, modified PCG, tolerance 1e-6 and 1e-3), with and without
// self-collision, and,
// when Bullet was found at configure time, with Bullet's btSoftBody in the same run: the same
// grid from btSoftBodyHelpers::CreatePatch with its shear diagonals and bending constraints
// (distance 2), the same mass, margin 0.01 m, linear stiffness 1, 10 position iterations, in a
// btSoftRigidDynamicsWorld. Reported beside the time per step: how far the cloth ends up
// stretched (the largest structural strain, (l - L) / L), how deep a vertex went into the
// sphere (distance below its surface, over all steps) and the fastest vertex at the end
// (jitter at rest).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
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

constexpr int kCells = 40;
constexpr int kSteps = 120;
constexpr Real kDt = Real(1) / 60;
constexpr Real kRadius = Real(0.3), kHeight = Real(0.6), kThickness = Real(0.01);
constexpr Real kMass = Real(0.5);

struct Result {
  double msPerStep = 0;
  double strain = 0;       // largest structural strain at the end
  double penetration = 0;  // deepest distance below the sphere's surface (m), over all steps
  double speed = 0;        // fastest vertex at the end (m/s)
  double newton = 0;       // Inertia: Newton iterations per step
  double extra = 0;        // Inertia: PCG iterations per step
};

double below(const Vec3& x) { return std::max(0.0, double(kRadius) - double(x.norm())); }

Result runInertia(bool selfCollision, double tolerance, ThreadPool* pool = nullptr,
                  std::vector<Real>* end = nullptr) {
  MassSpringModel m = cloth({.pose = {Vec3(0, kHeight, 0), Quat::Identity()},
                             .size = {1, 1},
                             .resolution = {kCells, kCells},
                             .mass = kMass,
                             .stiffness = {.stretch = 5000, .shear = 500, .bend = 5},
                             .damping = Real(0.01)});
  Deformable d({.thickness = kThickness,
                .friction = Real(0.3),
                .solverTolerance = tolerance,
                .selfCollision = selfCollision},
               m);
  d.addField({GravityField{}});
  d.addObstacle({Collider(Sphere{kRadius}), Transform{}});
  Result r;
  double seconds = 0;
  long iterations = 0, newton = 0;
  for (int s = 0; s < kSteps; ++s) {
    const auto t0 = Clock::now();
    d.step(kDt, pool);
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    iterations += d.lastSolve().iterations;
    newton += d.lastSolve().newtonIterations;
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      r.penetration = std::max(r.penetration, below(d.position(i)));
  }
  r.msPerStep = 1e3 * seconds / kSteps;
  r.extra = double(iterations) / kSteps;
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
Result runBullet() {
  btSoftBodyRigidBodyCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, btScalar(-9.81), 0));
  btSoftBodyWorldInfo& info = world.getWorldInfo();
  info.m_gravity = world.getGravity();
  info.m_sparsesdf.Initialize();

  btSphereShape sphere(kRadius);
  btRigidBody ball(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &sphere));
  world.addRigidBody(&ball);

  const btScalar h = kHeight;
  btSoftBody* cloth = btSoftBodyHelpers::CreatePatch(
      info, btVector3(-0.5, h, -0.5), btVector3(0.5, h, -0.5), btVector3(-0.5, h, 0.5),
      btVector3(0.5, h, 0.5), kCells + 1, kCells + 1, 0, true);
  const int structural = cloth->m_links.size();  // CreatePatch's links before bending ones
  cloth->m_materials[0]->m_kLST = 1;
  cloth->generateBendingConstraints(2, cloth->m_materials[0]);
  cloth->m_cfg.piterations = 10;
  cloth->m_cfg.kDF = btScalar(0.3);
  cloth->setTotalMass(kMass);
  cloth->getCollisionShape()->setMargin(kThickness);
  world.addSoftBody(cloth);

  Result r;
  double seconds = 0;
  for (int s = 0; s < kSteps; ++s) {
    const auto t0 = Clock::now();
    world.stepSimulation(kDt, 1, kDt);
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    for (int i = 0; i < cloth->m_nodes.size(); ++i) {
      const btVector3& x = cloth->m_nodes[i].m_x;
      r.penetration = std::max(r.penetration, below(Vec3(x.x(), x.y(), x.z())));
    }
  }
  r.msPerStep = 1e3 * seconds / kSteps;
  for (int k = 0; k < structural; ++k) {
    const btSoftBody::Link& l = cloth->m_links[k];
    // CreatePatch's structural links join grid neighbours (its diagonals are longer).
    if (l.m_rl > btScalar(1.0 / kCells) * btScalar(1.01)) continue;
    r.strain = std::max(r.strain, double((l.m_n[0]->m_x - l.m_n[1]->m_x).length() / l.m_rl - 1));
  }
  for (int i = 0; i < cloth->m_nodes.size(); ++i)
    r.speed = std::max(r.speed, double(cloth->m_nodes[i].m_v.length()));
  world.removeSoftBody(cloth);
  delete cloth;
  world.removeRigidBody(&ball);
  return r;
}
#endif

void row(const char* name, const Result& r, bool iterations) {
  std::printf("| %s | %.2f | %.3f | %.4f | %.3f |", name, r.msPerStep, r.strain, r.penetration,
              r.speed);
  if (iterations)
    std::printf(" %.1f / %.0f |\n", r.newton, r.extra);
  else
    std::printf(" - |\n");
}

}  // namespace

int main() {
  std::printf(
      "Cloth 40 x 40 (1,681 vertices) dropped on a sphere, %d steps of 1/60 s, one thread unless "
      "said.\n\n",
      kSteps);
  std::printf(
      "| engine | ms/step | max strain | deepest in sphere (m) | max speed at end (m/s) | Newton / "
      "PCG iterations per step |\n|---|---|---|---|---|---|\n");
  const Result plain = runInertia(false, 1e-6);
  row("Inertia implicit Euler, tolerance 1e-6", plain, true);
  const Result loose = runInertia(false, 1e-3);
  row("Inertia implicit Euler, tolerance 1e-3", loose, true);
  const Result self = runInertia(true, 1e-6);
  row("Inertia implicit Euler, 1e-6, + self-collision", self, true);
  // The same run on 2 threads and on every core: the time, and whether the bytes agree.
  std::vector<Real> serialEnd;
  runInertia(false, 1e-6, nullptr, &serialEnd);
  std::vector<int> counts = {2};
  if (int(std::thread::hardware_concurrency()) > 2)
    counts.push_back(int(std::thread::hardware_concurrency()));
  std::vector<std::pair<int, bool>> identical;
  for (int threads : counts) {
    ThreadPool pool(threads);
    std::vector<Real> end;
    const Result r = runInertia(false, 1e-6, &pool, &end);
    char name[96];
    std::snprintf(name, sizeof name, "Inertia implicit Euler, tolerance 1e-6, %d threads", threads);
    row(name, r, true);
    identical.push_back({threads, end == serialEnd});
  }
#ifdef INERTIA_BENCH_BULLET
  const Result bullet = runBullet();
  row("Bullet btSoftBody (10 position iterations)", bullet, false);
  std::printf(
      "\nInertia / Bullet time: %.2f at tolerance 1e-6, %.2f at 1e-3, %.2f with self-collision\n",
      plain.msPerStep / bullet.msPerStep, loose.msPerStep / bullet.msPerStep,
      self.msPerStep / bullet.msPerStep);
#else
  std::printf("\nBullet not found at configure time: no btSoftBody comparison.\n");
#endif
  for (const auto& [threads, same] : identical)
    std::printf("%d threads: final state %s the single thread's, byte for byte\n", threads,
                same ? "equals" : "DIFFERS FROM");
  return 0;
}
