// Drawing without a display: an OpenGL 3.3 core context from EGL (Mesa's surfaceless platform,
// software rasterised by llvmpipe when there is no GPU) and an offscreen framebuffer to draw
// into and read back. The renderer does not know which kind of context it draws in.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "gl.h"

namespace inertia::viewer {

/// An OpenGL context could not be made or a framebuffer is incomplete.
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A current OpenGL 3.3 core context with no window. Tries EGL_MESA_platform_surfaceless,
/// then the device platform, then the default display with a 1x1 pbuffer. Throws GlError.
class EglContext {
 public:
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// The GL_RENDERER string (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
  std::string renderer() const;
  /// Which EGL platform succeeded ("surfaceless", "device" or "default").
  const std::string& platform() const { return platform_; }

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  void* surface_ = nullptr;
  std::string platform_{};
};

/// An offscreen colour (RGBA8) and depth target of a fixed size, multisampled when
/// samples > 1 (resolved on read). Needs a current context; throws GlError when incomplete.
class OffscreenTarget {
 public:
  OffscreenTarget(int width, int height, int samples = 4);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  /// Binds the target for drawing and sets the viewport to its size.
  void bind() const;
  /// The image as RGB bytes, rows from the top (as image files store them), 3 * width * height.
  std::vector<std::uint8_t> readRgb() const;

 private:
  int width_ = 0, height_ = 0, samples_ = 0;
  GLuint drawFbo_ = 0, resolveFbo_ = 0;
  GLuint color_ = 0, depth_ = 0, resolveColor_ = 0;
};

}  // namespace inertia::viewer
