#include "offscreen.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstring>

namespace inertia::viewer {

namespace {

[[noreturn]] void fail(const char* what) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "%s (EGL error 0x%04x)", what, unsigned(eglGetError()));
  throw GlError(buffer);
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// Tries to initialise a display; returns EGL_NO_DISPLAY on failure.
EGLDisplay initialise(EGLDisplay d) {
  if (d == EGL_NO_DISPLAY) return d;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(d, &major, &minor)) return EGL_NO_DISPLAY;
  return d;
}

}  // namespace

EglContext::EglContext() {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  EGLDisplay display = EGL_NO_DISPLAY;
  bool needsSurface = false;
  if (getPlatformDisplay && hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
    display =
        initialise(getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    if (display != EGL_NO_DISPLAY) platform_ = "surfaceless";
  }
  if (display == EGL_NO_DISPLAY && getPlatformDisplay &&
      hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
    auto queryDevices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT device = nullptr;
    EGLint count = 0;
    if (queryDevices && queryDevices(1, &device, &count) && count > 0) {
      display = initialise(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, device, nullptr));
      if (display != EGL_NO_DISPLAY) platform_ = "device";
    }
  }
  if (display == EGL_NO_DISPLAY) {
    display = initialise(eglGetDisplay(EGL_DEFAULT_DISPLAY));
    if (display == EGL_NO_DISPLAY) fail("no EGL display (is libegl-mesa0 installed?)");
    platform_ = "default";
    needsSurface = true;
  }
  display_ = display;

  if (!eglBindAPI(EGL_OPENGL_API)) fail("EGL cannot bind the OpenGL API");
  const EGLint configAttributes[] = {EGL_SURFACE_TYPE,
                                     EGL_PBUFFER_BIT,
                                     EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (!eglChooseConfig(display, configAttributes, &config, 1, &configs) || configs == 0) {
    if (needsSurface) fail("no EGL config with a pbuffer and OpenGL");
    config = EGL_NO_CONFIG_KHR;  // surfaceless contexts need none (EGL_KHR_no_config_context)
  }
  const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      3,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
  if (context == EGL_NO_CONTEXT) {
    eglTerminate(display);
    fail("cannot create an OpenGL 3.3 core context");
  }
  context_ = context;
  EGLSurface surface = EGL_NO_SURFACE;
  if (needsSurface) {
    const EGLint pbufferAttributes[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
    surface = eglCreatePbufferSurface(display, config, pbufferAttributes);
    surface_ = surface;
  }
  if (!eglMakeCurrent(display, surface, surface, context)) {
    eglDestroyContext(display, context);
    eglTerminate(display);
    fail("cannot make the OpenGL context current");
  }
}

EglContext::~EglContext() {
  EGLDisplay display = display_;
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (surface_) eglDestroySurface(display, surface_);
  eglDestroyContext(display, context_);
  eglTerminate(display);
  eglReleaseThread();
}

std::string EglContext::renderer() const {
  const GLubyte* s = glGetString(GL_RENDERER);
  return s ? reinterpret_cast<const char*>(s) : "";
}

OffscreenTarget::OffscreenTarget(int width, int height, int samples)
    : width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw GlError("offscreen target size must be positive");
  GLint maxSamples = 1, maxSize = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
  if (width > maxSize || height > maxSize)
    throw GlError("offscreen target larger than GL_MAX_RENDERBUFFER_SIZE (" +
                  std::to_string(maxSize) + ")");
  samples_ = std::clamp(samples, 1, std::max(1, int(maxSamples)));

  auto makeTarget = [&](GLuint& fbo, GLuint& color, GLuint* depth, int s) {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    if (s > 1)
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_RGBA8, width, height);
    else
      glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    if (depth) {
      glGenRenderbuffers(1, depth);
      glBindRenderbuffer(GL_RENDERBUFFER, *depth);
      if (s > 1)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_DEPTH_COMPONENT24, width, height);
      else
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth);
    }
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw GlError("offscreen framebuffer incomplete");
  };
  makeTarget(drawFbo_, color_, &depth_, samples_);
  if (samples_ > 1) makeTarget(resolveFbo_, resolveColor_, nullptr, 1);
  glBindFramebuffer(GL_FRAMEBUFFER, drawFbo_);
}

OffscreenTarget::~OffscreenTarget() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const GLuint fbos[] = {drawFbo_, resolveFbo_};
  const GLuint rbs[] = {color_, depth_, resolveColor_};
  glDeleteFramebuffers(2, fbos);
  glDeleteRenderbuffers(3, rbs);
}

void OffscreenTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, drawFbo_);
  glViewport(0, 0, width_, height_);
}

std::vector<std::uint8_t> OffscreenTarget::readRgb() const {
  GLuint source = drawFbo_;
  if (samples_ > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, drawFbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFbo_);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    source = resolveFbo_;
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  const std::size_t row = 3 * std::size_t(width_);
  std::vector<std::uint8_t> bottomUp(row * std::size_t(height_));
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, bottomUp.data());
  glBindFramebuffer(GL_FRAMEBUFFER, drawFbo_);
  // OpenGL's rows start at the bottom; images start at the top.
  std::vector<std::uint8_t> topDown(bottomUp.size());
  for (int y = 0; y < height_; ++y)
    std::copy_n(bottomUp.data() + row * std::size_t(height_ - 1 - y), row,
                topDown.data() + row * std::size_t(y));
  return topDown;
}

}  // namespace inertia::viewer
