// `inertia render`: draws a scene offscreen (EGL, no display needed) into a PNG, a numbered
// PNG sequence, an MP4 or a GIF.
#pragma once

#include <optional>
#include <string>

namespace inertia::app {

struct RenderOptions {
  std::string scene{};
  std::string out{};                 ///< .png, frame_%04d.png, .mp4 or .gif
  std::optional<double> duration{};  ///< Seconds of video (default 10).
  std::optional<double> time{};      ///< A single PNG's time (s), default: the duration.
  std::string size = "1280x720";     ///< WxH pixels.
  double fps = 30;                   ///< Frames per second of sequences and videos.
  std::optional<int> threads{};      ///< Overrides the scene's world.threads.
  int samples = 4;                   ///< Multisampling (1: none).
  bool quiet = false;
};

int renderScene(const RenderOptions& options);

/// Parses an image size "WIDTHxHEIGHT" (1..8192 pixels each); false when malformed.
bool parseSize(const std::string& text, int& width, int& height);

}  // namespace inertia::app
