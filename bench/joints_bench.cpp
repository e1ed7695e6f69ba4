// Joints against Bullet 3 (btDiscreteDynamicsWorld, btSequentialImpulseConstraintSolver with its
// default 10 iterations) and, for the chains, ODE (dWorldQuickStep with its default 20
// iterations) in the same run, the peers on one thread, sleeping off in all, 600 steps of 1/60 s
// (--steps N for fewer). Inertia runs with its default settings (soft step, 4 substeps, 4
// iterations + 1 relax pass, joints at 120 Hz) at 1 thread beside them, and for the scenes
// without contacts also with Box2D v3's (1 iteration + 1 relax pass, joints at 60 Hz); then
// with its defaults at 2 threads and all cores (or the
// counts of --threads 1,2,16), with its speed-up over 1 thread and a check that every count ends
// with the same bits. The scenes come from the shared builders' Assembly descriptions and are
// built from the same description in every engine:
// - chain: 100 chains of 20 capsules (r 0.05 m, 0.5 m joint to joint) on ball joints, each
//   hanging from the world by its first link, released from horizontal (Bullet:
//   btPoint2PointConstraint; ODE: dBallJoint);
// - joint_grid: Box2D v3's joint_grid in 3D: 100 x 100 spheres (r 0.4 m, 1 m apart) in a
//   vertical plane, each joined to its right and lower neighbours by a ball joint (19,800), the
//   middle 7 of the top row pinned to the world by 7 more (Bullet: btPoint2PointConstraint);
//   as in Box2D's, a collision filter keeps the spheres from colliding (category 2, mask ~2);
// - ragdolls: 100 ragdolls (11 bodies, 10 joints each) dropped at assorted tilts and heights onto
//   a ground plane (Bullet: btConeTwistConstraint without limits for the ball joints, as
//   Inertia's ragdoll has none, btHingeConstraint with the same limits for the hinges).
// Density 1000 kg/m^3, friction 0.6, restitution 0, gravity -9.81 m/s^2; the joined bodies do not
// collide with each other, the others do. Reported: mean ms per step, the largest joint error
// over the run and at its end (the distance between a joint's two anchors, m), non-finite
// states and the final kinetic energy.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>
#include <variant>
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

int gSteps = 600;
constexpr Real kDt = Real(1.0 / 60);
constexpr Real kFriction = Real(0.6);

Material material() { return {.density = 1000, .friction = kFriction, .restitution = 0}; }

// How a peer makes Inertia's ball joints.
enum class BulletBall { PointToPoint, ConeTwist };

struct Scene {
  std::string name;
  Assembly assembly;
  bool ground = false;  // a static plane y = 0
  BulletBall ball = BulletBall::PointToPoint;
  bool ode = false;  // also run ODE
};

Scene chainScene() {
  Scene s{"chain", {}, false, BulletBall::PointToPoint, true};
  for (int i = 0; i < 100; ++i)
    append(s.assembly, chain({.links = 20,
                              .top = Vec3(0, 20, Real(i) - Real(49.5)),
                              .direction = Vec3::UnitX(),
                              .material = material(),
                              .name = "chain_" + std::to_string(i)}));
  return s;
}

// As in Box2D's sample, the spheres are in category 2 and collide with every category but 2:
// with nothing here. Only the joints act.
Scene jointGridScene() {
  Scene s{"joint_grid", jointGrid({.material = material()}), false, BulletBall::PointToPoint,
          false};
  for (BodyDesc& body : s.assembly.bodies)
    for (ShapeDesc& shape : body.shapes) shape.filter = {.category = 2, .mask = ~2u};
  return s;
}

Scene ragdollScene() {
  Scene s{"ragdolls", {}, true, BulletBall::ConeTwist, false};
  for (int i = 0; i < 100; ++i) {
    // Assorted tilts (0.2 to 1.4 rad about a horizontal axis turning with i) and drop heights
    // (pelvis 1.5 to 3 m), on a 10 x 10 grid 2.5 m apart.
    const Real turn = Real(i) * Real(2.4);
    const Vec3 axis(std::cos(turn), 0, std::sin(turn));
    const Quat tilt(Eigen::AngleAxis<Real>(Real(0.2) + Real(0.3) * Real(i % 5), axis));
    append(s.assembly, ragdoll({.position = Vec3(Real(2.5) * Real(i % 10 - 5),
                                                 Real(1.5) + Real(0.5) * Real(i % 4),
                                                 Real(2.5) * Real(i / 10 - 5)),
                                .orientation = tilt,
                                .material = material(),
                                .name = "ragdoll_" + std::to_string(i)}));
  }
  return s;
}

// What a run measured.
struct Result {
  double msPerStep = 0;
  double maxError = 0;    // m, the largest joint error over the run (after each step)
  double finalError = 0;  // m, the largest at the end
  int nonFinite = 0;
  double kineticEnergy = 0;  // J
  PhaseTimes phases{};       // Inertia only (s, summed over the steps)
  bool hasPhases = false;
  // Inertia only: every dynamic body's position, orientation (x, y, z, w), linear and angular
  // velocity, kStateSize Reals a body, which every thread count must reproduce bit for bit.
  std::vector<Real> finalState;
};

constexpr std::size_t kStateSize = 13;

int jointCount(const Scene& s) { return int(s.assembly.joints.size()); }

// The anchors (body frame) of the ball and hinge joints the peers build.
struct Anchors {
  Vec3 a, b;
};

Anchors anchorsOf(const AssemblyJoint& j) {
  if (const auto* ball = std::get_if<BallJointSettings>(&j.settings))
    return {ball->anchorA, ball->anchorB};
  if (const auto* hinge = std::get_if<HingeJointSettings>(&j.settings))
    return {hinge->anchorA, hinge->anchorB};
  std::fprintf(stderr, "joints bench: the peers take ball and hinge joints only\n");
  std::exit(1);
}

using bench::bt;
using bench::onlyShape;

// Box2D v3's solver settings: one iteration and one relax pass a substep, joints at 60 Hz
// (twice its 30 Hz contacts), damping ratio 2. Its joint_grid figure is for these.
SolverSettings box2dSolver() {
  return {.iterations = 1, .relaxIterations = 1, .jointHertz = 60, .jointDampingRatio = 2};
}

Result runInertia(const Scene& scene, int threads, const SolverSettings& solver = {}) {
  World world({.solver = solver, .threads = threads, .sleeping = false});
  if (scene.ground) {
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0}, material());
  }
  const AssemblyIds ids = addAssembly(world, scene.assembly);
  const RigidBodySystem& bodies = world.rigidBodies();
  Result r;
  auto worstError = [&] {
    double worst = 0;
    for (JointId j : ids.joints) worst = std::max(worst, double(bodies.jointError(j).position));
    return worst;
  };
  double total = 0;
  for (int i = 0; i < gSteps; ++i) {
    const auto t0 = Clock::now();
    world.step(kDt);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    r.maxError = std::max(r.maxError, worstError());
  }
  r.msPerStep = 1e3 * total / gSteps;
  r.phases = world.phaseTimes();
  r.hasPhases = true;
  r.finalError = worstError();
  for (BodyId id : ids.bodies) {
    if (bodies.type(id) != BodyType::Dynamic) continue;
    const Transform x = world.transform(id);
    const Vec3 v = world.linearVelocity(id), w = world.angularVelocity(id);
    if (!x.p.allFinite() || !v.allFinite() || !w.allFinite()) ++r.nonFinite;
    r.finalState.insert(r.finalState.end(), x.p.data(), x.p.data() + 3);
    r.finalState.insert(r.finalState.end(), x.q.coeffs().data(), x.q.coeffs().data() + 4);
    r.finalState.insert(r.finalState.end(), v.data(), v.data() + 3);
    r.finalState.insert(r.finalState.end(), w.data(), w.data() + 3);
  }
  r.kineticEnergy = double(bodies.kineticEnergy());
  return r;
}

Result runBullet(const Scene& scene) {
  bench::BulletWorld world;
  if (scene.ground)
    world.add(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, btTransform::getIdentity(),
              material());
  std::vector<btRigidBody*> rb;
  for (const BodyDesc& d : scene.assembly.bodies) rb.push_back(world.add(d));
  // Each joint's bodies (A null for the world, then its anchor is a world point) and anchors.
  struct Pin {
    btRigidBody* a;
    btRigidBody* b;
    btVector3 anchorA, anchorB;
  };
  std::vector<Pin> pins;
  for (const AssemblyJoint& j : scene.assembly.joints) {
    const Anchors an = anchorsOf(j);
    btRigidBody* a = j.bodyA < 0 ? nullptr : rb[std::size_t(j.bodyA)];
    btRigidBody* b = rb[std::size_t(j.bodyB)];
    pins.push_back({a, b, bt(an.a), bt(an.b)});
    bool collide = false;
    if (const auto* hinge = std::get_if<HingeJointSettings>(&j.settings)) {
      if (a == nullptr) std::exit(1);  // not in these scenes
      btVector3 axisA = bt(hinge->axisA), axisB = bt(hinge->axisB);
      auto h = std::make_unique<btHingeConstraint>(*a, *b, bt(an.a), bt(an.b), axisA, axisB);
      // Bullet's hinge angle is minus Inertia's (B's turn relative to A, right-hand rule about
      // the axis), so its limits are the negated, swapped bounds.
      if (hinge->limits)
        h->setLimit(btScalar(-hinge->limits->upper), btScalar(-hinge->limits->lower));
      collide = hinge->collideConnected;
      world.add(std::move(h), collide);
      continue;
    } else {
      const auto& ball = std::get<BallJointSettings>(j.settings);
      collide = ball.collideConnected;
      if (a == nullptr) {
        world.add(std::make_unique<btPoint2PointConstraint>(*b, bt(an.b)), collide);
      } else if (scene.ball == BulletBall::PointToPoint) {
        world.add(std::make_unique<btPoint2PointConstraint>(*a, *b, bt(an.a), bt(an.b)), collide);
      } else {
        // Frames that coincide now: A's axes, expressed in B's frame; the spans keep their
        // default (no cone or twist limit).
        const btQuaternion qa = a->getWorldTransform().getRotation();
        const btQuaternion qb = b->getWorldTransform().getRotation();
        const btTransform frameA(btQuaternion::getIdentity(), bt(an.a));
        const btTransform frameB(qb.inverse() * qa, bt(an.b));
        world.add(std::make_unique<btConeTwistConstraint>(*a, *b, frameA, frameB), collide);
      }
    }
  }
  auto worstError = [&] {
    double worst = 0;
    for (const Pin& p : pins) {
      const btVector3 wa = p.a == nullptr ? p.anchorA : p.a->getCenterOfMassTransform() * p.anchorA;
      const btVector3 wb = p.b->getCenterOfMassTransform() * p.anchorB;
      worst = std::max(worst, double((wa - wb).length()));
    }
    return worst;
  };

  Result r;
  double total = 0;
  for (int i = 0; i < gSteps; ++i) {
    const auto t0 = Clock::now();
    world.step(kDt);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    r.maxError = std::max(r.maxError, worstError());
  }
  r.msPerStep = 1e3 * total / gSteps;
  r.finalError = worstError();
  for (const btRigidBody* b : rb) {
    if (b->getInvMass() == 0) continue;
    const btVector3 v = b->getLinearVelocity(), w = b->getAngularVelocity();
    const btVector3& p = b->getCenterOfMassPosition();
    if (!std::isfinite(double(p.x() + p.y() + p.z() + v.length2() + w.length2()))) ++r.nonFinite;
    r.kineticEnergy += bench::BulletWorld::kineticEnergy(*b);
  }
  return r;
}

#ifdef INERTIA_BENCH_ODE
Result runOde(const Scene& scene) {
  bench::OdeWorld w{double(kFriction)};
  if (scene.ground) {
    BodyDesc ground;
    ground.settings.type = BodyType::Static;
    ground.shapes.push_back({.shape = Plane{Vec3::UnitY(), 0}, .material = material()});
    w.add(ground);
  }
  std::vector<dBodyID> bodies;
  for (const BodyDesc& d : scene.assembly.bodies) bodies.push_back(w.add(d));
  std::vector<dJointID> joints;
  for (const AssemblyJoint& j : scene.assembly.joints) {
    const auto* ball = std::get_if<BallJointSettings>(&j.settings);
    if (ball == nullptr) std::exit(1);  // balls only (the chains)
    const dBodyID b = bodies[std::size_t(j.bodyB)];
    const dJointID joint = dJointCreateBall(w.world, nullptr);
    dJointAttach(joint, j.bodyA < 0 ? nullptr : bodies[std::size_t(j.bodyA)], b);
    dVector3 anchor;  // B's anchor in the world, where the joint is made
    dBodyGetRelPointPos(b, ball->anchorB.x(), ball->anchorB.y(), ball->anchorB.z(), anchor);
    dJointSetBallAnchor(joint, anchor[0], anchor[1], anchor[2]);
    joints.push_back(joint);
  }
  auto worstError = [&] {
    double worst = 0;
    for (const dJointID j : joints) {
      dVector3 a, b;
      dJointGetBallAnchor(j, a);
      dJointGetBallAnchor2(j, b);
      worst = std::max(worst, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
    }
    return worst;
  };

  Result r;
  double total = 0;
  for (int i = 0; i < gSteps; ++i) {
    const auto t0 = Clock::now();
    w.step(kDt);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    r.maxError = std::max(r.maxError, worstError());
  }
  r.msPerStep = 1e3 * total / gSteps;
  r.finalError = worstError();
  for (const dBodyID b : bodies) {
    const dReal* v = dBodyGetLinearVel(b);
    const dReal* wv = dBodyGetAngularVel(b);
    if (!std::isfinite(v[0] + v[1] + v[2] + wv[0] + wv[1] + wv[2])) ++r.nonFinite;
    r.kineticEnergy += bench::OdeWorld::kineticEnergy(b);
  }
  return r;
}
#endif

int dynamicCount(const Scene& s) {
  int n = 0;
  for (const BodyDesc& d : s.assembly.bodies) n += d.settings.type == BodyType::Dynamic ? 1 : 0;
  return n;
}

std::string phaseSplit(const Result& r) {
  return bench::phaseSplit(r.hasPhases ? &r.phases : nullptr, gSteps);
}

void printTableHeader() {
  std::printf(
      "| scene | engine | bodies | joints | ms/step | Inertia broad / narrow / solver / integ. ms "
      "| max joint error m (run) | max joint error m (end) | non-finite | final KE J |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
}

void printRow(const Scene& scene, const char* engine, const Result& r) {
  std::printf("| %s | %s | %d | %d | %.2f | %s | %.3g | %.3g | %d | %.4g |\n", scene.name.c_str(),
              engine, dynamicCount(scene), jointCount(scene), r.msPerStep, phaseSplit(r).c_str(),
              r.maxError, r.finalError, r.nonFinite, r.kineticEnergy);
  std::fflush(stdout);
}

void printThreadTable(const Scene& scene, const std::vector<int>& counts,
                      const std::vector<Result>& runs) {
  std::printf(
      "\n| %s: Inertia | threads | ms/step | speed-up vs 1 thread | broad / narrow / solver / "
      "integ. ms | max joint error m |\n",
      scene.name.c_str());
  std::printf("|---|---|---|---|---|---|\n");
  for (std::size_t k = 0; k < counts.size(); ++k)
    std::printf("| defaults | %d | %.2f | %.2f | %s | %.3g |\n", counts[k], runs[k].msPerStep,
                runs[0].msPerStep / runs[k].msPerStep, phaseSplit(runs[k]).c_str(),
                runs[k].maxError);
}

// Compares every thread count's final state with 1 thread's, byte for byte; prints "same bits"
// or a loud line naming the first body that differs. Returns whether all were the same.
bool checkSameBits(const Scene& scene, const std::vector<int>& counts,
                   const std::vector<Result>& runs) {
  const std::vector<Real>& ref = runs[0].finalState;
  bool same = true;
  for (std::size_t k = 1; k < counts.size(); ++k) {
    const std::vector<Real>& s = runs[k].finalState;
    std::size_t differ = 0, first = 0;
    for (std::size_t i = 0; i < ref.size() / kStateSize; ++i) {
      if (std::memcmp(&ref[i * kStateSize], &s[i * kStateSize], kStateSize * sizeof(Real)) == 0)
        continue;
      if (differ++ == 0) first = i;
    }
    if (differ == 0) continue;
    same = false;
    const double dx = (Eigen::Map<const Vec3>(&s[first * kStateSize]) -
                       Eigen::Map<const Vec3>(&ref[first * kStateSize]))
                          .norm();
    std::printf(
        "*** DIFFERENT BITS *** %s: at %d threads %zu of %zu bodies end otherwise than at 1 "
        "thread (first: body %zu, position off by %.3g m)\n",
        scene.name.c_str(), counts[k], differ, ref.size() / kStateSize, first, dx);
  }
  if (same) {
    bench::BitHash hash;
    hash.add(std::span<const Real>(ref));
    std::printf(
        "%s: same bits at %s threads (final positions, orientations and velocities of the %zu "
        "bodies, FNV-1a %016llx)\n",
        scene.name.c_str(), bench::countList(counts).c_str(), ref.size() / kStateSize,
        static_cast<unsigned long long>(hash.value()));
  }
  std::fflush(stdout);
  return same;
}

}  // namespace

// Arguments, all optional: scene names to run (default: chain, joint_grid, ragdolls); --threads
// 1,2,16 to choose Inertia's thread counts (default: 1, 2 and all cores; 1 is always run);
// --steps N (default 600).
int main(int argc, char** argv) {
  const std::vector<int> counts = bench::threadCounts(argc, argv);
  gSteps = bench::countOption(argc, argv, "--steps", 1'000'000, gSteps);
  const std::vector<std::string> only =
      bench::sceneNames(argc, argv, "bench_joints", {"chain", "joint_grid", "ragdolls"});
#ifdef INERTIA_BENCH_ODE
  dInitODE2(0);
#endif
  const WorldSettings defaults;
  std::printf(
      "joints: %d steps of 1/60 s, peers on 1 thread, Inertia (soft_step, %d substeps, %d it. + "
      "%d relax) on 1 thread beside them, then on %s threads below each scene (%d cores), "
      "sleeping off, Real = %s, Bullet btScalar = %s\n",
      gSteps, defaults.substeps, defaults.solver.iterations, defaults.solver.relaxIterations,
      bench::countList(counts).c_str(), bench::allCores(), sizeof(Real) == 4 ? "float" : "double",
      sizeof(btScalar) == 4 ? "float" : "double");
  int differentBits = 0;
  using Make = Scene (*)();
  for (Make make : {Make(chainScene), Make(jointGridScene), Make(ragdollScene)}) {
    const Scene scene = make();
    if (!only.empty() && std::find(only.begin(), only.end(), scene.name) == only.end()) continue;
    std::printf("\n");
    printTableHeader();
    std::vector<Result> runs;
    runs.push_back(runInertia(scene, 1));
    printRow(scene, "Inertia (defaults)", runs[0]);
    if (!scene.ground)
      printRow(scene, "Inertia (Box2D's solver: 1 it. + 1 relax, joints 60 Hz)",
               runInertia(scene, 1, box2dSolver()));
    printRow(scene,
             scene.ball == BulletBall::ConeTwist ? "Bullet SI (10 it.; cone-twist, hinge)"
                                                 : "Bullet SI (10 it.; point-to-point)",
             runBullet(scene));
#ifdef INERTIA_BENCH_ODE
    if (scene.ode) printRow(scene, "ODE QuickStep (20 it.; dBallJoint)", runOde(scene));
#endif
    for (std::size_t k = 1; k < counts.size(); ++k) runs.push_back(runInertia(scene, counts[k]));
    printThreadTable(scene, counts, runs);
    differentBits += checkSameBits(scene, counts, runs) ? 0 : 1;
  }
  std::printf(
      "\nms/step: mean wall-clock time of the %d steps (the joint errors are measured after each "
      "step, outside the timing); Inertia's phase split from World::phaseTimes() (joints are "
      "solved in the solver phase). Joint error: the distance between a joint's two anchors, the "
      "largest over the joints, after each step over the run and after the last. Bullet: "
      "btDiscreteDynamicsWorld, btDbvtBroadphase, btSequentialImpulseConstraintSolver (defaults: "
      "10 iterations, split impulse, warm starting 0.85), stepSimulation(1/60, 0), "
      "DISABLE_DEACTIVATION, hinge limits with its default softness 0.9, bias 0.3, relaxation "
      "1.%s\n",
      gSteps,
#ifdef INERTIA_BENCH_ODE
      " ODE (double): dHashSpace, up to 4 contacts a pair, dContactApprox1 with mu 0.6, "
      "default ERP 0.2 and CFM, dWorldQuickStep (default 20 iterations), auto-disable off."
#else
      " ODE not built (libode-dev not found)."
#endif
  );
  if (differentBits > 0)
    std::printf(
        "\n*** DIFFERENT BITS *** in %d scenes: Inertia's result depends on the thread count "
        "(DESIGN.md section 7 says it must not)\n",
        differentBits);
#ifdef INERTIA_BENCH_ODE
  dCloseODE();
#endif
  return 0;
}
