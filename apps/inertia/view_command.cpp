// `inertia view`: options checked, scenes folder found, then the viewer (view_command.h).
#include "view_command.h"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>

#include "frame_writer.h"
#include "render_command.h"
#include "run_command.h"
#include "samples.h"
#include "viewer_app.h"

namespace inertia::app {

namespace {

// This executable's path (Linux), or empty.
std::filesystem::path executablePath() {
  std::array<char, 4096> buffer{};
  const ssize_t n = readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
  return n > 0 ? std::filesystem::path(std::string(buffer.data(), std::size_t(n)))
               : std::filesystem::path();
}

// Out of line: messages built by concatenation (GCC 12's false -Warray-bounds when inlined).
[[gnu::noinline]] int badInput(const std::string& message) {
  std::fprintf(stderr, "inertia: view: %s\n", message.c_str());
  return kBadInput;
}

}  // namespace

int viewScene(const ViewOptions& o) {
  viewer::ViewerOptions v;
  if (!parseSize(o.size, v.width, v.height))
    return badInput("--size: expected WIDTHxHEIGHT in pixels (e.g. 1280x720), got \"" + o.size +
                    "\"");
  if (!o.screenshot.empty()) {
    try {
      if (viewer::outputKind(o.screenshot) != viewer::OutputKind::Png)
        return badInput("--screenshot: " + o.screenshot + ": must be a .png file");
    } catch (const viewer::OutputError& e) {
      return badInput(std::string("--screenshot: ") + e.what());
    }
  }
  std::optional<std::filesystem::path> explicitDir;
  if (o.scenesDir) explicitDir = *o.scenesDir;
  v.scenesDir = viewer::findScenesDir(explicitDir, executablePath(), INERTIA_SOURCE_DIR);
  if (o.scenesDir && !v.scenesDir) return badInput("--scenes: " + *o.scenesDir + ": not a folder");
  v.scene = o.scene;
  v.frames = o.frames;
  v.screenshot = o.screenshot;
  v.threads = o.threads;
  v.panel = !o.noPanel;
  return viewer::runViewer(v);
}

}  // namespace inertia::app
