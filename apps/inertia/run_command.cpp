#include "run_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "energy_log.h"
#include "inertia/core/error.h"
#include "inertia/io/recording.h"
#include "inertia/io/scene.h"
#include "progress.h"

namespace inertia::app {

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }


nlohmann::json particleStats(const World& world) {
  nlohmann::json list = nlohmann::json::array();
  for (ParticleSystemId id : world.particleSystems()) {
    const ParticleSystem& ps = world.particleSystem(id);
    const ParticleStats s = ps.stats();
    list.push_back({{"name", ps.name()},
                    {"alive", s.alive},
                    {"emitted", s.emitted},
                    {"died", s.died},
                    {"dropped", s.dropped}});
  }
  return list;
}

int brokenJoints(const World& world) {
  const RigidBodySystem& rb = world.rigidBodies();
  int broken = 0;
  for (JointId id : rb.joints()) broken += rb.isJointBroken(id) ? 1 : 0;
  return broken;
}

// A joint's name in recordings and messages: its name, or its index when unnamed.
std::string jointLabel(const RigidBodySystem& rb, JointId id, std::size_t index) {
  const std::string_view name = rb.jointName(id);
  return name.empty() ? std::to_string(index) : std::string(name);
}

// A joint that broke during the run, for the summary.
struct Break {
  double time;
  std::string joint;
  Vec3 force, torque;
};

// Per deformable: vertices, springs, and springs broken so far.
nlohmann::json deformableStats(const World& world) {
  nlohmann::json list = nlohmann::json::array();
  for (DeformableId id : world.deformables()) {
    const Deformable& d = world.deformable(id);
    list.push_back({{"name", d.name()},
                    {"vertices", d.vertexCount()},
                    {"springs", d.springs().size()},
                    {"broken_springs", d.brokenCount()}});
  }
  return list;
}

// A spring of a deformable that tore during the run, for the summary.
struct Tear {
  double time;
  std::string deformable;
  std::size_t spring;
  Real strain;
};

nlohmann::json statsJson(const World& world, double wallTime) {
  const PhaseTimes& p = world.phaseTimes();
  return {
      {"steps", world.stepCount()},
      {"sim_time", world.time()},
      {"wall_time", wallTime},
      {"bodies", world.bodyCount()},
      {"contacts", world.contactCount()},
      {"joints", world.rigidBodies().jointCount()},
      {"broken_joints", brokenJoints(world)},
      {"phases",
       {{"broad_phase", p.broadPhase},
        {"narrow_phase", p.narrowPhase},
        {"solver", p.solver},
        {"integration", p.integration},
        {"particles", p.particles},
        {"deformables", p.deformables}}},
      {"particle_systems", particleStats(world)},
      {"deformables", deformableStats(world)},
  };
}

}  // namespace

bool loadSceneReporting(const std::string& file, io::Scene& scene) {
  try {
    scene = io::loadScene(file);
    return true;
  } catch (const io::SceneError& e) {
    std::fprintf(stderr, "inertia: %s\n", e.what());
    return false;
  }
}

std::unique_ptr<World> instantiateReporting(const std::string& file, const io::Scene& scene) {
  try {
    return io::instantiate(scene);
  } catch (const io::SceneError& e) {
    std::fprintf(stderr, "inertia: %s\n", e.what());
  } catch (const InvalidArgument& e) {
    std::fprintf(stderr, "inertia: %s: %s\n", file.c_str(), e.what());
  }
  return nullptr;
}

int runScene(const RunOptions& o) {
  io::Scene scene;
  if (!loadSceneReporting(o.scene, scene)) return kBadInput;
  if (o.dt) scene.world.dt = Real(*o.dt);
  if (o.threads) scene.world.threads = *o.threads;
  if (!(std::isfinite(scene.world.dt) && scene.world.dt > 0)) {
    // A --dt too small for Real (float underflow to 0) is bad input too.
    std::fprintf(stderr, "inertia: --dt: %g is not representable as a positive step\n", *o.dt);
    return kBadInput;
  }

  std::int64_t steps = 0;
  if (o.steps) {
    steps = *o.steps;
  } else {
    double duration = o.duration.value_or(10.0);
    // Whole steps covering the duration; a ratio within 1e-4 of an integer is that integer, so
    // float's rounding of dt (1 s at dt 0.01 is 100.0000002 steps) does not add a step.
    double ratio = duration / double(scene.world.dt);
    double n = std::fabs(ratio - std::round(ratio)) < 1e-4 ? std::round(ratio) : std::ceil(ratio);
    if (!(n <= double(std::int64_t(1) << 40))) {
      std::fprintf(stderr, "inertia: --duration: %g s at dt %g s is too many steps\n", duration,
                   double(scene.world.dt));
      return kBadInput;
    }
    steps = std::max<std::int64_t>(1, std::int64_t(n));
  }

  std::unique_ptr<World> world = instantiateReporting(o.scene, scene);
  if (!world) return kBadInput;

  std::unique_ptr<io::BodyRecorder> recorder;
  std::unique_ptr<io::ParticleRecorder> particleRecorder;
  try {
    if (!o.record.empty()) recorder = std::make_unique<io::BodyRecorder>(o.record);
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "inertia: --record: %s\n", e.what());
    return kBadInput;
  }
  try {
    if (!o.recordParticles.empty())
      particleRecorder = std::make_unique<io::ParticleRecorder>(o.recordParticles);
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "inertia: --record-particles: %s\n", e.what());
    return kBadInput;
  }
  std::unique_ptr<io::JointRecorder> jointRecorder;
  try {
    if (!o.recordJoints.empty())
      jointRecorder = std::make_unique<io::JointRecorder>(o.recordJoints);
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "inertia: --record-joints: %s\n", e.what());
    return kBadInput;
  }
  std::unique_ptr<io::DeformableRecorder> deformableRecorder;
  try {
    if (!o.recordDeformables.empty())
      deformableRecorder = std::make_unique<io::DeformableRecorder>(o.recordDeformables);
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "inertia: --record-deformables: %s\n", e.what());
    return kBadInput;
  }
  std::unique_ptr<EnergyLog> energyLog;
  try {
    if (!o.energy.empty()) energyLog = std::make_unique<EnergyLog>(o.energy);
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "inertia: --energy: %s\n", e.what());
    return kBadInput;
  }
  std::vector<Real> gravityScale;  // per body, in creation order (as bodies() lists them)
  for (const BodyDesc& d : scene.bodies) gravityScale.push_back(d.settings.gravityScale);
  const std::vector<BodyId> bodyIds = world->rigidBodies().bodies();
  const std::vector<JointId> jointIds = world->rigidBodies().joints();
  std::vector<std::string> jointLabels;
  for (std::size_t i = 0; i < jointIds.size(); ++i)
    jointLabels.push_back(jointLabel(world->rigidBodies(), jointIds[i], i));
  auto record = [&] {
    if (recorder) {
      const RigidBodySystem& rb = world->rigidBodies();
      for (std::size_t i = 0; i < bodyIds.size(); ++i) {
        const BodyId id = bodyIds[i];
        const std::string index = std::to_string(i);
        const std::string_view name = rb.name(id).empty() ? std::string_view(index) : rb.name(id);
        recorder->write(Real(world->time()), name, rb.transform(id), rb.linearVelocity(id),
                        rb.angularVelocity(id));
      }
    }
    if (jointRecorder) {
      const RigidBodySystem& rb = world->rigidBodies();
      for (std::size_t i = 0; i < jointIds.size(); ++i) {
        const JointId id = jointIds[i];
        jointRecorder->write(Real(world->time()), jointLabels[i], rb.isJointBroken(id),
                             rb.jointForce(id), rb.jointTorque(id), rb.jointError(id));
      }
    }
    if (deformableRecorder)
      for (DeformableId id : world->deformables())
        deformableRecorder->write(Real(world->time()), world->deformable(id));
    if (!particleRecorder) return;
    for (ParticleSystemId id : world->particleSystems()) {
      const ParticleSystem& ps = world->particleSystem(id);
      particleRecorder->write(Real(world->time()), ps.name(), ps.pool());
    }
  };
  std::vector<Break> breaks;  // reported once each, in the summary
  std::vector<Tear> tears;    // likewise

  Progress progress(!o.quiet, steps, "step");
  double wall = 0;
  record();  // the initial state at time 0
  if (energyLog) energyLog->write(measureEnergy(*world, gravityScale));
  for (std::int64_t i = 0; i < steps; ++i) {
    auto t0 = Clock::now();
    world->step(scene.world.dt);
    wall += seconds(Clock::now() - t0);
    for (const JointEvent& e : world->rigidBodies().jointEvents()) {
      const auto at = std::find(jointIds.begin(), jointIds.end(), e.joint);
      const std::string label = at == jointIds.end()
                                    ? std::to_string(e.joint.index)
                                    : jointLabels[std::size_t(at - jointIds.begin())];
      breaks.push_back({world->time(), label, e.force, e.torque});
    }
    for (DeformableId id : world->deformables()) {
      const Deformable& d = world->deformable(id);
      for (const TearEvent& e : d.tearEvents())
        tears.push_back({e.time, d.name(), e.spring, e.strain});
    }
    if ((i + 1) % o.recordEvery == 0) record();
    if (energyLog) energyLog->write(measureEnergy(*world, gravityScale));
    progress.update(i + 1);
  }
  progress.finish();
  if (recorder) recorder->close();
  if (particleRecorder) particleRecorder->close();
  if (jointRecorder) jointRecorder->close();
  if (deformableRecorder) deformableRecorder->close();
  if (energyLog) energyLog->close();

  if (!o.stats.empty()) {
    std::ofstream out(o.stats);
    if (!out) {
      std::fprintf(stderr, "inertia: --stats: %s: cannot be opened for writing\n", o.stats.c_str());
      return kBadInput;
    }
    out << statsJson(*world, wall).dump(2) << '\n';
  }
  if (!o.quiet) {
    std::printf("%s: %lld steps, %.4g s simulated in %.4g s of stepping; %d bodies, %d contacts\n",
                o.scene.c_str(), (long long)world->stepCount(), world->time(), wall,
                world->bodyCount(), world->contactCount());
    if (!jointIds.empty())
      std::printf("  %zu joints, %d broken\n", jointIds.size(), brokenJoints(*world));
    for (const Break& b : breaks)
      std::printf("  joint \"%s\" broke at %.4g s (force %.4g N, torque %.4g N m)\n",
                  b.joint.c_str(), b.time, double(b.force.norm()), double(b.torque.norm()));
    for (ParticleSystemId id : world->particleSystems()) {
      const ParticleSystem& ps = world->particleSystem(id);
      const ParticleStats s = ps.stats();
      std::printf("  particles \"%s\": %lld alive, %lld emitted, %lld died\n", ps.name().c_str(),
                  (long long)s.alive, (long long)s.emitted, (long long)s.died);
    }
    for (const Tear& t : tears)
      std::printf("  deformable \"%s\": spring %zu tore at %.4g s (strain %.4g)\n",
                  t.deformable.c_str(), t.spring, t.time, double(t.strain));
  }
  return kOk;
}

int validateScene(const std::string& file) {
  try {
    // Loading checks what the file says; instantiating, what only the library knows (the
    // joints' settings against the bodies' poses, shapes' mass properties).
    io::Scene scene = io::loadScene(file);
    io::instantiate(scene);
    const WorldSettings& w = scene.world;
    std::printf("%s: ok (%zu bodies, %zu joints; dt %g s, %d substeps, solver %s, integrator %s)\n",
                file.c_str(), scene.bodies.size(), scene.joints.size(), double(w.dt), w.substeps,
                std::string(solverName(w.solver.type)).c_str(),
                std::string(ode::methodName(w.integrator)).c_str());
    return kOk;
  } catch (const io::SceneError& e) {
    std::fprintf(stderr, "inertia: %s\n", e.what());
  } catch (const InvalidArgument& e) {
    std::fprintf(stderr, "inertia: %s: %s\n", file.c_str(), e.what());
  }
  return kBadInput;
}

}  // namespace inertia::app
