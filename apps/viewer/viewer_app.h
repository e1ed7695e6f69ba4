// The interactive viewer (`inertia view`): a GLFW window with an OpenGL 3.3 core context, the
// shared Renderer, debug lines and a Dear ImGui panel over the sample browser, Playback, the
// orbit camera and mouse interaction.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace inertia::viewer {

struct ViewerOptions {
  /// A scene file, or the name of a sample, to open first; the first sample when empty.
  std::optional<std::string> scene{};
  /// The folder of scene files listed in the browser (none when empty).
  std::optional<std::filesystem::path> scenesDir{};
  int width = 1280, height = 720;  ///< Window size (screen coordinates).
  /// When > 0: draw this many frames, each taken as 1/60 s of real time (so a run is
  /// reproducible), then exit.
  std::int64_t frames = 0;
  /// A PNG of the window's last frame with `frames`, otherwise written by F12 or the panel.
  std::string screenshot{};
  std::optional<int> threads{};  ///< Overrides the scenes' world.threads.
  bool panel = true;             ///< Show the panel at start (Tab toggles it).
};

/// Why no window can be opened, judged from the environment: empty when DISPLAY or
/// WAYLAND_DISPLAY is set.
std::string displayProblem();

/// Runs the viewer until its window closes (or `frames` frames). Returns the inertia command's
/// exit codes: 0 done, 2 bad input or no usable display (the message says which), 1 an
/// internal failure. Messages go to stderr.
int runViewer(const ViewerOptions& options);

}  // namespace inertia::viewer
