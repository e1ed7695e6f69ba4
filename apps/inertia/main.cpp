// The inertia command: runs and checks scene files (DESIGN.md section 5).
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "run_command.h"

namespace {

// A finite number > 0. CLI11's PositiveNumber lets NaN through (NaN <= 0 is false).
const CLI::Validator kFinitePositive(
    [](std::string& s) -> std::string {
      try {
        std::size_t used = 0;
        double x = std::stod(s, &used);
        if (used != s.size() || !std::isfinite(x) || !(x > 0))
          return "must be a finite number > 0, got " + s;
      } catch (const std::exception&) {
        return "must be a finite number > 0, got " + s;
      }
      return {};
    },
    "POSITIVE");

}  // namespace

int main(int argc, char** argv) {
  using namespace inertia::app;
  CLI::App app{"Inertia: run and check physics scene files"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "inertia 0.1.0");

  RunOptions run;
  CLI::App* runCmd = app.add_subcommand("run", "Simulate a scene file");
  runCmd->add_option("scene", run.scene, "Scene file (JSON)")->required();
  auto* duration = runCmd->add_option("--duration", run.duration, "Simulated time (s), default 10")
                       ->check(kFinitePositive);
  runCmd->add_option("--steps", run.steps, "Number of fixed steps")
      ->check(CLI::Range(std::int64_t(1), std::int64_t(1) << 40))
      ->excludes(duration);
  runCmd->add_option("--dt", run.dt, "Fixed time step (s), overrides the scene's world.dt")
      ->check(kFinitePositive);
  runCmd->add_option("--threads", run.threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 1024));
  runCmd->add_option("--record", run.record, "Write body states as CSV");
  runCmd->add_option("--record-every", run.recordEvery, "Record every K-th step")
      ->check(CLI::Range(std::int64_t(1), std::int64_t(1) << 40));
  runCmd->add_option("--record-particles", run.recordParticles, "Write particle states as CSV");
  runCmd->add_option("--stats", run.stats, "Write a JSON summary");
  runCmd->add_flag("--quiet,-q", run.quiet, "Print nothing but errors");

  std::string validateFile;
  CLI::App* validateCmd = app.add_subcommand("validate", "Check a scene file and report errors");
  validateCmd->add_option("scene", validateFile, "Scene file (JSON)")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kBadInput;
  }

  try {
    if (runCmd->parsed()) return runScene(run);
    if (validateCmd->parsed()) return validateScene(validateFile);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "inertia: internal error: %s\n", e.what());
    return kInternalError;
  }
  return kInternalError;
}
