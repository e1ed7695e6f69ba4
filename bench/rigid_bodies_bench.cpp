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
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>
#ifdef INERTIA_BENCH_ODE
#include <ode/ode.h>
#endif

#include "inertia/world/builders.h"
#include "inertia/world/world.h"
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

btVector3 bt(const Vec3& v) { return {btScalar(v.x()), btScalar(v.y()), btScalar(v.z())}; }

Result runBullet(const Scene& scene) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadPhase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadPhase, &solver, &config);
  world.setGravity(btVector3(0, btScalar(-9.81), 0));

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<btRigidBody*> dynamic;
  auto add = [&](const BodyDesc& d) {
    if (d.shapes.size() != 1) std::abort();  // the scenes here have one shape, at the origin
    const ShapeDesc& s = d.shapes[0];
    double volume = 0;
    if (const Plane* p = s.shape.getIf<Plane>()) {
      shapes.push_back(std::make_unique<btStaticPlaneShape>(bt(p->normal), btScalar(p->offset)));
    } else if (const Box* b = s.shape.getIf<Box>()) {
      // btBoxShape keeps its collision margin (0.04 m) inside the given half extents.
      shapes.push_back(std::make_unique<btBoxShape>(bt(b->halfExtents)));
      volume = 8.0 * double(b->halfExtents.prod());
    } else if (const Sphere* sp = s.shape.getIf<Sphere>()) {
      shapes.push_back(std::make_unique<btSphereShape>(btScalar(sp->radius)));
      volume = 4.0 / 3.0 * std::numbers::pi * std::pow(double(sp->radius), 3);
    } else {
      std::abort();
    }
    const bool isStatic = d.settings.type == BodyType::Static;
    const btScalar mass = isStatic ? 0 : btScalar(double(s.material.density) * volume);
    btVector3 inertia(0, 0, 0);
    if (!isStatic) shapes.back()->calculateLocalInertia(mass, inertia);
    const Quat& q = d.settings.orientation;
    motions.push_back(std::make_unique<btDefaultMotionState>(btTransform(
        btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())),
        bt(d.settings.position))));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motions.back().get(), shapes.back().get(),
                                                  inertia);
    // Bullet multiplies the two bodies' coefficients; sqrt on each gives the geometric mean,
    // Inertia's default rule (0.6 between any two of these materials).
    info.m_friction = btScalar(std::sqrt(double(s.material.friction)));
    info.m_restitution = btScalar(s.material.restitution);
    bodies.push_back(std::make_unique<btRigidBody>(info));
    if (!isStatic) {
      bodies.back()->setActivationState(DISABLE_DEACTIVATION);
      dynamic.push_back(bodies.back().get());
    }
    world.addRigidBody(bodies.back().get());
  };
  for (const BodyDesc& d : scene.statics) add(d);
  for (const BodyDesc& d : scene.dynamics) add(d);

  double total = 0;
  for (int i = 0; i < kSteps; ++i) {
    const auto t0 = Clock::now();
    world.stepSimulation(btScalar(kDt), 0);  // maxSubSteps 0: exactly one step of kDt
    total += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  Result r;
  r.msPerStep = 1e3 * total / kSteps;
  std::vector<Vec3> final;
  for (const btRigidBody* b : dynamic) {
    const btVector3& p = b->getCenterOfMassPosition();
    final.emplace_back(Real(p.x()), Real(p.y()), Real(p.z()));
    const btVector3 v = b->getLinearVelocity(), w = b->getAngularVelocity();
    const btVector3 iw = b->getInvInertiaTensorWorld().inverse() * w;
    r.kineticEnergy +=
        0.5 * double(1 / b->getInvMass()) * double(v.length2()) + 0.5 * double(w.dot(iw));
  }
  checkPositions(scene, final, r);
  for (auto& b : bodies) world.removeRigidBody(b.get());
  return r;
}

#ifdef INERTIA_BENCH_ODE
// ODE: a hash space, contacts from dCollide (at most 4 per pair, as the other engines'
// manifolds) as contact joints with friction mu = 0.6 scaled by the normal force
// (dContactApprox1, ODE's Coulomb approximation), and no bounce; the world's default ERP 0.2 and
// CFM; dWorldQuickStep with its default 20 iterations; auto-disable off (its default).
struct OdeWorld {
  dWorldID world = dWorldCreate();
  dSpaceID space = dHashSpaceCreate(nullptr);
  dJointGroupID contacts = dJointGroupCreate(0);
  ~OdeWorld() {
    dJointGroupDestroy(contacts);
    dSpaceDestroy(space);
    dWorldDestroy(world);
  }
};

void odeNear(void* data, dGeomID g1, dGeomID g2) {
  OdeWorld& w = *static_cast<OdeWorld*>(data);
  const dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
  if (b1 == nullptr && b2 == nullptr) return;  // two static geoms
  constexpr int kMax = 4;
  dContact contact[kMax] = {};
  const int n = dCollide(g1, g2, kMax, &contact[0].geom, sizeof(dContact));
  for (int i = 0; i < n; ++i) {
    contact[i].surface.mode = dContactApprox1;
    contact[i].surface.mu = double(kFriction);
    const dJointID j = dJointCreateContact(w.world, w.contacts, &contact[i]);
    dJointAttach(j, b1, b2);
  }
}

Result runOde(const Scene& scene) {
  OdeWorld w;
  dWorldSetGravity(w.world, 0, -9.81, 0);
  dWorldSetAutoDisableFlag(w.world, 0);
  std::vector<dBodyID> dynamic;
  for (const std::vector<BodyDesc>* list : {&scene.statics, &scene.dynamics}) {
    for (const BodyDesc& d : *list) {
      if (d.shapes.size() != 1) std::abort();  // one shape, at the origin
      const ShapeDesc& s = d.shapes[0];
      const bool isStatic = d.settings.type == BodyType::Static;
      dGeomID geom = nullptr;
      dMass mass;
      const double density = double(s.material.density);
      if (const Plane* p = s.shape.getIf<Plane>()) {
        geom = dCreatePlane(w.space, p->normal.x(), p->normal.y(), p->normal.z(), p->offset);
      } else if (const Box* b = s.shape.getIf<Box>()) {
        const Vec3 size = 2 * b->halfExtents;  // ODE takes full side lengths
        geom = dCreateBox(w.space, size.x(), size.y(), size.z());
        dMassSetBox(&mass, density, size.x(), size.y(), size.z());
      } else if (const Sphere* sp = s.shape.getIf<Sphere>()) {
        geom = dCreateSphere(w.space, sp->radius);
        dMassSetSphere(&mass, density, sp->radius);
      } else {
        std::abort();
      }
      const Vec3& x = d.settings.position;
      const Quat& q = d.settings.orientation;
      const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};  // ODE: w first
      if (isStatic) {
        if (s.shape.getIf<Plane>() == nullptr) {
          dGeomSetPosition(geom, x.x(), x.y(), x.z());
          dGeomSetQuaternion(geom, dq);
        }
        continue;
      }
      const dBodyID body = dBodyCreate(w.world);
      dBodySetMass(body, &mass);
      dBodySetPosition(body, x.x(), x.y(), x.z());
      dBodySetQuaternion(body, dq);
      dGeomSetBody(geom, body);
      dynamic.push_back(body);
    }
  }

  double total = 0;
  for (int i = 0; i < kSteps; ++i) {
    const auto t0 = Clock::now();
    dSpaceCollide(w.space, &w, odeNear);
    dWorldQuickStep(w.world, double(kDt));
    dJointGroupEmpty(w.contacts);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  Result r;
  r.msPerStep = 1e3 * total / kSteps;
  std::vector<Vec3> final;
  for (const dBodyID b : dynamic) {
    const dReal* p = dBodyGetPosition(b);
    final.emplace_back(Real(p[0]), Real(p[1]), Real(p[2]));
    dMass m;
    dBodyGetMass(b, &m);
    const dReal* v = dBodyGetLinearVel(b);
    const dReal* wv = dBodyGetAngularVel(b);
    // The rotational energy in the body's frame: w_b = R^T w, R and I row-major 3 x 4.
    const dReal* R = dBodyGetRotation(b);
    double wb[3], e = 0;
    for (int k = 0; k < 3; ++k) wb[k] = R[k] * wv[0] + R[4 + k] * wv[1] + R[8 + k] * wv[2];
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) e += wb[k] * m.I[4 * k + l] * wb[l];
    r.kineticEnergy += 0.5 * m.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 0.5 * e;
  }
  checkPositions(scene, final, r);
  return r;
}
#endif

// Inertia's mean ms per step in each phase, "-" for the peers.
std::string phaseSplit(const Result& r) {
  if (!r.hasPhases) return "-";
  const double ms = 1e3 / kSteps;
  char split[96];
  std::snprintf(split, sizeof split, "%.2f / %.2f / %.2f / %.2f", ms * r.phases.broadPhase,
                ms * r.phases.narrowPhase, ms * r.phases.solver, ms * r.phases.integration);
  return split;
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
// Inertia's thread counts (default: 1, 2 and all cores; 1 is always run).
int main(int argc, char** argv) {
  const std::vector<int> counts = bench::threadCounts(argc, argv);
  std::vector<std::string> only(argv + 1, argv + argc);
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
    printThreadTable(scene, counts, configs);
    for (const ThreadRuns& c : configs) differentBits += checkSameBits(scene, counts, c) ? 0 : 1;
  }
  std::printf(
      "\nms/step: mean wall-clock time of the %d steps. Inertia's phase split from "
      "World::phaseTimes(); its speed-up is its ms/step on 1 thread over that on the count "
      "(WorldSettings::threads, the size of its TBB arena). Bullet: btDiscreteDynamicsWorld, "
      "btDbvtBroadphase, btSequentialImpulseConstraintSolver (defaults: 10 iterations, split "
      "impulse, warm starting 0.85), stepSimulation(1/60, 0), DISABLE_DEACTIVATION.%s Pyramid "
      "max disp.: the largest final displacement of a box from its start; it stands when <= "
      "0.25 m.\n",
      kSteps,
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
