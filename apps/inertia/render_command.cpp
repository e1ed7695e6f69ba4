#include "render_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <system_error>
#include <vector>

#include "camera.h"
#include "frame_writer.h"
#include "inertia/io/scene.h"
#include "offscreen.h"
#include "progress.h"
#include "renderer.h"
#include "run_command.h"
#include "samples.h"

namespace inertia::app {

namespace {

constexpr int kMaxSide = 8192;

// Whole steps nearest to time t (s).
std::int64_t stepsAt(double t, double dt) { return std::int64_t(std::llround(t / dt)); }

// Colours of the scene's shapes, in the order instantiate() creates bodies and shapes.
viewer::ShapeColors shapeColors(const io::Scene& scene) {
  viewer::ShapeColors colors;
  for (const BodyDesc& body : scene.bodies) {
    std::vector<std::optional<Vec3>>& list = colors.emplace_back();
    for (const ShapeDesc& shape : body.shapes) list.push_back(shape.color);
  }
  return colors;
}

// Out of line: messages built by concatenation (GCC 12's false -Warray-bounds when inlined).
[[gnu::noinline]] int badInput(const char* what, const std::string& message) {
  std::fprintf(stderr, "inertia: %s%s\n", what, message.c_str());
  return kBadInput;
}

}  // namespace

bool parseSize(const std::string& s, int& width, int& height) {
  int w = 0, h = 0, used = 0;
  if (std::sscanf(s.c_str(), "%dx%d%n", &w, &h, &used) != 2 || used != int(s.size())) return false;
  if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide) return false;
  width = w;
  height = h;
  return true;
}

int renderScene(const RenderOptions& o) {
  int width = 0, height = 0;
  if (!parseSize(o.size, width, height))
    return badInput("--size: ", "expected WIDTHxHEIGHT in pixels (1.." + std::to_string(kMaxSide) +
                                    " each, e.g. 1280x720), got \"" + o.size + "\"");
  viewer::OutputKind kind;
  try {
    kind = viewer::outputKind(o.out);
  } catch (const viewer::OutputError& e) {
    return badInput("--out: ", e.what());
  }
  const bool isVideo = kind == viewer::OutputKind::Mp4 || kind == viewer::OutputKind::Gif;
  if (kind == viewer::OutputKind::Mp4 && (width % 2 || height % 2))
    return badInput("--size: ", "MP4 (yuv420p) needs an even width and height, got " + o.size);
  if (isVideo && !viewer::findExecutable("ffmpeg"))
    return badInput("--out: ", o.out +
                                   ": writing video needs ffmpeg, which is not on PATH "
                                   "(install the ffmpeg package)");
  if (o.time && !(std::isfinite(*o.time) && *o.time >= 0))
    return badInput("--time: ", "must be a finite number >= 0");
  if (o.time && kind != viewer::OutputKind::Png)
    return badInput("--time: ", "only for a single .png; sequences and videos use --duration");

  io::Scene scene;
  std::function<void(World&)> control;  // a built-in sample's controller
  const std::vector<viewer::Sample> builtins = viewer::builtinSamples();
  const std::optional<std::size_t> builtin = viewer::findSample(builtins, o.scene);
  std::error_code ec;
  if (builtin && !std::filesystem::is_regular_file(o.scene, ec)) {
    scene = builtins[*builtin].build();
    control = builtins[*builtin].control;
  } else if (!loadSceneReporting(o.scene, scene)) {
    return kBadInput;
  }
  if (o.threads) scene.world.threads = *o.threads;
  std::unique_ptr<World> world = instantiateReporting(o.scene, scene);
  if (!world) return kBadInput;

  // Frame k shows the state after round(t_k / dt) whole fixed steps, t_k = k / fps (no
  // interpolation between steps): frame k is exactly what `inertia run --steps` reaches.
  const double dt = double(scene.world.dt);
  const double duration = o.duration.value_or(10.0);
  std::vector<double> times;
  if (kind == viewer::OutputKind::Png) {
    times.push_back(o.time.value_or(duration));
  } else {
    const double frames = std::max(1.0, std::round(duration * o.fps));
    if (frames > 1e6) return badInput("--duration: ", "more than a million frames");
    for (std::int64_t k = 0; k < std::int64_t(frames); ++k) times.push_back(double(k) / o.fps);
  }

  try {
    viewer::EglContext context;
    viewer::OffscreenTarget target(width, height, o.samples);
    viewer::Renderer renderer;
    renderer.setShapeColors(shapeColors(scene));
    const viewer::CameraView camera =
        viewer::sceneCamera(scene, *world, float(width) / float(height));

    std::unique_ptr<viewer::VideoEncoder> video;
    if (isVideo) video = std::make_unique<viewer::VideoEncoder>(o.out, kind, width, height, o.fps);

    Progress progress(!o.quiet, std::int64_t(times.size()), "frame");
    for (std::size_t k = 0; k < times.size(); ++k) {
      const std::int64_t steps = stepsAt(times[k], dt);
      while (world->stepCount() < steps) {
        if (control) control(*world);
        world->step(scene.world.dt);
      }
      target.bind();
      renderer.draw(*world, camera, width, height);
      const std::vector<std::uint8_t> rgb = target.readRgb();
      if (kind == viewer::OutputKind::Png)
        viewer::writePng(o.out, width, height, rgb);
      else if (kind == viewer::OutputKind::PngSequence)
        viewer::writePng(viewer::sequencePath(o.out, std::int64_t(k)), width, height, rgb);
      else
        video->write(rgb);
      progress.update(std::int64_t(k + 1));
    }
    progress.finish();
    if (video) video->finish();
    if (!o.quiet) {
      std::printf("%s: %zu frame%s of %dx%d to %s (%lld steps, %.4g s simulated)\n",
                  o.scene.c_str(), times.size(), times.size() == 1 ? "" : "s", width, height,
                  o.out.c_str(), (long long)world->stepCount(), world->time());
    }
  } catch (const viewer::OutputError& e) {
    std::fprintf(stderr, "inertia: --out: %s\n", e.what());
    return kBadInput;
  } catch (const viewer::GlError& e) {
    std::fprintf(stderr, "inertia: render: %s\n", e.what());
    return kInternalError;
  }
  return kOk;
}

}  // namespace inertia::app
