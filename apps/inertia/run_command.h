// `inertia run` and `inertia validate`: options and entry points.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace inertia {
class World;
}
namespace inertia::io {
struct Scene;
}

namespace inertia::app {

/// Exit codes of the command (DESIGN.md section 5).
enum ExitCode : int { kOk = 0, kInternalError = 1, kBadInput = 2 };

struct RunOptions {
  std::string scene;
  std::optional<double> duration;     ///< Simulated seconds (default 10 when neither is given).
  std::optional<std::int64_t> steps;  ///< Number of fixed steps.
  std::optional<double> dt;           ///< Overrides the scene's world.dt (s).
  std::optional<int> threads;         ///< Overrides the scene's world.threads.
  std::string record;                 ///< Body CSV (DESIGN.md section 6).
  std::int64_t recordEvery = 1;       ///< Record every K-th step.
  std::string stats;                  ///< JSON summary.
  std::string recordParticles;        ///< Particle CSV (DESIGN.md section 6).
  std::string recordJoints;           ///< Joint CSV (DESIGN.md section 6).
  std::string recordDeformables;      ///< Deformable vertex CSV (DESIGN.md section 6).
  std::string energy;                 ///< Energy and momenta per step (CSV).
  bool quiet = false;                 ///< No summary or progress on the terminal.
};

int runScene(const RunOptions& options);

/// Loads a scene file into `scene`; on a SceneError prints it (file, JSON pointer, reason) and
/// returns false, for the commands to exit with kBadInput.
bool loadSceneReporting(const std::string& file, io::Scene& scene);
/// Builds the world of a loaded scene; on an invalid body or joint prints what is wrong (the
/// file, and the joint's JSON pointer) and returns null, for the commands to exit with kBadInput.
std::unique_ptr<World> instantiateReporting(const std::string& file, const io::Scene& scene);
int validateScene(const std::string& scene);

}  // namespace inertia::app
