// The inertia command: runs and checks scene files (DESIGN.md section 5).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include "render_command.h"
#include "run_command.h"
#include "view_command.h"

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
  CLI::App app{"Inertia: run, check, render and view physics scene files"};
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
  runCmd->add_option("--record-joints", run.recordJoints,
                     "Write joint forces, torques, errors and breaks as CSV");
  runCmd->add_option("--record-deformables", run.recordDeformables,
                     "Write deformables' vertex states as CSV");
  runCmd->add_option("--stats", run.stats, "Write a JSON summary");
  runCmd->add_option("--energy", run.energy,
                     "Write kinetic, potential, total energy and momenta per step as CSV");
  runCmd->add_flag("--quiet,-q", run.quiet, "Print nothing but errors");

  RenderOptions render;
  CLI::App* renderCmd = app.add_subcommand("render", "Draw a scene offscreen to PNG, MP4 or GIF");
  renderCmd
      ->add_option("scene", render.scene,
                   "Scene file (JSON), or a built-in sample's name (as the viewer lists them)")
      ->required();
  renderCmd
      ->add_option(
          "--out,-o", render.out,
          "Output: FILE.png (one frame), FRAME_%04d.png (a sequence), FILE.mp4 or FILE.gif")
      ->required();
  renderCmd->add_option("--duration", render.duration, "Simulated seconds of video, default 10")
      ->check(kFinitePositive);
  renderCmd->add_option("--time", render.time, "Time (s) of a single PNG, default the duration")
      ->check(CLI::NonNegativeNumber);
  renderCmd->add_option("--size", render.size, "Image size WIDTHxHEIGHT, default 1280x720");
  renderCmd->add_option("--fps", render.fps, "Frames per second, default 30")
      ->check(kFinitePositive);
  renderCmd->add_option("--threads", render.threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 1024));
  renderCmd->add_option("--samples", render.samples, "Multisamples per pixel (1: none), default 4")
      ->check(CLI::Range(1, 16));
  renderCmd->add_flag("--quiet,-q", render.quiet, "Print nothing but errors");

  ViewOptions view;
  CLI::App* viewCmd = app.add_subcommand(
      "view",
      "Interactive viewer: a sample browser over scenes/ and built-in samples (needs a display; "
      "exits with 2 without one)");
  viewCmd->add_option("scene", view.scene, "Scene file (JSON) or sample name to open first");
  viewCmd->add_option("--scenes", view.scenesDir,
                      "Folder of scene files to list (default: scenes/ found near the executable)");
  viewCmd->add_option("--size", view.size, "Window size WIDTHxHEIGHT, default 1280x720");
  viewCmd->add_option("--frames", view.frames, "Run N frames (1/60 s each) and exit")
      ->check(CLI::Range(std::int64_t(1), std::int64_t(1) << 40));
  viewCmd->add_option("--screenshot", view.screenshot,
                      "Write the last frame as PNG (with --frames; otherwise on F12)");
  viewCmd->add_option("--threads", view.threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 1024));
  viewCmd->add_flag("--no-panel", view.noPanel, "Start with the panel hidden (Tab toggles it)");

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
    if (renderCmd->parsed()) return renderScene(render);
    if (viewCmd->parsed()) return viewScene(view);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "inertia: internal error: %s\n", e.what());
    return kInternalError;
  }
  return kInternalError;
}
