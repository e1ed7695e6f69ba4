// The interactive viewer's window, input, drawing and ImGui panel (viewer_app.h).
#include "viewer_app.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <vector>

#include "debug_draw.h"
#include "frame_writer.h"
#include "gl.h"
#include "inertia/core/error.h"
#include "interaction.h"
#include "offscreen.h"
#include "orbit_camera.h"
#include "playback.h"
#include "renderer.h"
#include "samples.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "backends/imgui_impl_glfw.h"
#include "backends/imgui_impl_opengl3.h"

namespace inertia::viewer {

namespace {

constexpr int kOk = 0, kInternalError = 1, kBadInput = 2;
constexpr double kFixedFrame = 1.0 / 60;  // real seconds per frame with --frames
constexpr float kRayLength = 1000;        // m: picking and shooting reach

// The message of GLFW's last error (glfwInit or window creation).
std::string glfwMessage;
void onGlfwError(int code, const char* description) {
  glfwMessage = description ? description : ("GLFW error " + std::to_string(code));
}

// Colours of a scene's shapes, in the order instantiate() creates bodies and shapes.
ShapeColors shapeColors(const io::Scene& scene) {
  ShapeColors colors;
  for (const BodyDesc& body : scene.bodies) {
    std::vector<std::optional<Vec3>>& list = colors.emplace_back();
    for (const ShapeDesc& shape : body.shapes) list.push_back(shape.color);
  }
  return colors;
}

// Per-step averages of the world's phase times over about half a second.
struct PhaseMeter {
  PhaseTimes start{};
  std::int64_t startSteps = 0;
  double elapsed = 0;
  PhaseTimes perStep{};  // ms per step
  double fps = 0;
  int frames = 0;

  void reset(const World& world) {
    start = world.phaseTimes();
    startSteps = world.stepCount();
    elapsed = 0;
    frames = 0;
  }
  void update(const World& world, double realSeconds) {
    elapsed += realSeconds;
    ++frames;
    if (elapsed < 0.5) return;
    const PhaseTimes now = world.phaseTimes();
    const double steps = double(std::max<std::int64_t>(1, world.stepCount() - startSteps));
    perStep = {1e3 * (now.broadPhase - start.broadPhase) / steps,
               1e3 * (now.narrowPhase - start.narrowPhase) / steps,
               1e3 * (now.solver - start.solver) / steps,
               1e3 * (now.integration - start.integration) / steps,
               1e3 * (now.particles - start.particles) / steps};
    fps = double(frames) / elapsed;
    reset(world);
  }
};

class App {
 public:
  App(GLFWwindow* window, const ViewerOptions& options, std::vector<Sample> samples)
      : window_(window),
        options_(options),
        samples_(std::move(samples)),
        showPanel_(options.panel) {}

  // Loads sample `index`; on failure keeps the current one and shows why. False on failure.
  bool load(std::size_t index) {
    try {
      io::Scene scene = samples_[index].build();
      if (options_.threads) scene.world.threads = *options_.threads;
      auto playback = std::make_unique<Playback>(std::move(scene));
      playback_ = std::move(playback);
      current_ = index;
      afterLoad(true);
      error_.clear();
      return true;
    } catch (const std::exception& e) {
      error_ = samples_[index].name + ": " + e.what();
      return false;
    }
  }

  const std::string& error() const { return error_; }

  // One frame: input, simulation, drawing into the back buffer.
  void frame(double realSeconds) {
    // What the panel asked for last frame (it replaces the world, which the panel was reading).
    if (deferred_) {
      deferred_();
      deferred_ = nullptr;
    }
    handleMouse();
    playback_->frame(realSeconds);
    meter_.update(playback_->world(), realSeconds);

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (showPanel_) panel();
    ImGui::Render();

    glfwGetFramebufferSize(window_, &width_, &height_);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width_, height_);
    CameraView camera = orbit_.view();
    fitClipPlanes(camera, bounds_);
    renderer_.style().sleepingColor =
        showSleeping_ ? std::optional(Eigen::Vector3f(0.45f, 0.45f, 0.62f)) : std::nullopt;
    const std::vector<Transform> poses = playback_->drawPoses();
    renderer_.draw(playback_->world(), camera, width_, height_, poses);

    lines_.clear();
    buildDebugLines(playback_->world(), flags_, scale_, lines_);
    if (spring_ && playback_->world().isValid(spring_->body)) {
      const Vec3 anchor = playback_->world().transform(spring_->body).apply(spring_->localAnchor);
      lines_.add(anchor, spring_->target, Eigen::Vector3f(1, 1, 1));
    }
    const float aspect = float(width_) / float(std::max(1, height_));
    lineRenderer_.draw(lines_, projectionMatrix(camera, aspect) * viewMatrix(camera));
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }

  // The back buffer as RGB rows from the top.
  std::vector<std::uint8_t> readFrame() const {
    std::vector<std::uint8_t> bottomUp(3 * std::size_t(width_) * std::size_t(height_));
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, bottomUp.data());
    std::vector<std::uint8_t> rgb(bottomUp.size());
    const std::size_t row = 3 * std::size_t(width_);
    for (int y = 0; y < height_; ++y)
      std::copy_n(&bottomUp[std::size_t(height_ - 1 - y) * row], row, &rgb[std::size_t(y) * row]);
    return rgb;
  }
  void writeScreenshot(const std::string& file) {
    writePng(file, width_, height_, readFrame());
    message_ = "wrote " + file;
  }
  bool screenshotRequested() {
    const bool r = screenshotRequested_;
    screenshotRequested_ = false;
    return r;
  }

  // GLFW callbacks (installed before ImGui's, which call them first, then do their own work).
  void onKey(int key, int action) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    switch (key) {
      case GLFW_KEY_SPACE:
        playback_->paused = !playback_->paused;
        break;
      case GLFW_KEY_S:
      case GLFW_KEY_RIGHT:
        playback_->paused = true;
        playback_->singleStep();
        break;
      case GLFW_KEY_R:
        restart();
        break;
      case GLFW_KEY_B:
        shoot();
        break;
      case GLFW_KEY_M:
        slowMotion_ = !slowMotion_;
        playback_->timeScale = slowMotion_ ? 0.25 : 1.0;
        break;
      case GLFW_KEY_C:
        resetCamera();
        break;
      case GLFW_KEY_TAB:
        showPanel_ = !showPanel_;
        break;
      case GLFW_KEY_F12:
        screenshotRequested_ = true;
        break;
      case GLFW_KEY_ESCAPE:
        glfwSetWindowShouldClose(window_, GLFW_TRUE);
        break;
      default:
        break;
    }
  }
  void onMouseButton(int button, int action, int mods) {
    if (action == GLFW_RELEASE) {
      if (button == GLFW_MOUSE_BUTTON_LEFT) {
        spring_.reset();
        orbiting_ = false;
      }
      if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE) panning_ = false;
      return;
    }
    if (ImGui::GetIO().WantCaptureMouse) return;
    glfwGetCursorPos(window_, &mouseX_, &mouseY_);
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
      // Shift-click shoots; a click on a dynamic body grabs it; elsewhere it orbits.
      if (mods & GLFW_MOD_SHIFT) {
        shoot();
        return;
      }
      spring_ = pickBody(playback_->world(), mouseRay());
      orbiting_ = !spring_;
    } else {
      panning_ = true;
    }
  }
  void onScroll(double dy) {
    if (!ImGui::GetIO().WantCaptureMouse) orbit_.zoom(float(dy));
  }

 private:
  // Ray through the cursor (window coordinates scaled to the framebuffer).
  Ray mouseRay() const {
    int w = 0, h = 0;
    glfwGetWindowSize(window_, &w, &h);
    CameraView camera = orbit_.view();
    return pixelRay(camera, mouseX_, mouseY_, std::max(1, w), std::max(1, h), kRayLength);
  }

  void handleMouse() {
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const double dx = x - mouseX_, dy = y - mouseY_;
    mouseX_ = x;
    mouseY_ = y;
    int w = 0, h = 0;
    glfwGetWindowSize(window_, &w, &h);
    if (orbiting_) orbit_.orbit(float(dx), float(dy));
    if (panning_) orbit_.pan(float(dx), float(dy), h);
    if (spring_) {
      if (!playback_->world().isValid(spring_->body)) {
        spring_.reset();
      } else {
        spring_->target = springTarget(*spring_, mouseRay());
      }
    }
  }

  void afterLoad(bool resetView) {
    World& world = playback_->world();
    renderer_.setShapeColors(shapeColors(playback_->scene()));
    bounds_ = framingBounds(world, playback_->scene());
    scale_ = bounds_.isValid() ? std::clamp(Real(0.05) * (bounds_.upper - bounds_.lower).norm(),
                                            Real(0.05), Real(2))
                               : Real(0.5);
    if (resetView) resetCamera();
    edit_ = playback_->scene().world;
    spring_.reset();
    playback_->beforeStep = [this](World& w) {
      if (spring_) applySpring(w, *spring_);
      if (samples_[current_].control) samples_[current_].control(w);
    };
    meter_.reset(world);
  }

  void resetCamera() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    orbit_ = OrbitCamera::fromView(
        sceneCamera(playback_->scene(), playback_->world(), float(w) / float(std::max(1, h))));
  }

  void restart() {
    const bool paused = playback_->paused;
    const double scale = playback_->timeScale;
    playback_->restart();
    playback_->paused = paused;
    playback_->timeScale = scale;
    afterLoad(false);
  }

  void shoot() {
    const CameraView camera = orbit_.view();
    const Eigen::Vector3f forward = (camera.target - camera.position).normalized();
    Ray ray{.origin = camera.position.cast<Real>(), .direction = forward.cast<Real>()};
    // From the cursor when it is over the scene, else straight ahead.
    if (!ImGui::GetIO().WantCaptureMouse) ray = mouseRay();
    ball_.radius = std::max(Real(0.05), Real(0.5) * scale_);
    shootBall(playback_->world(), ray, ball_);
  }

  void applySettings() {
    try {
      playback_->applySettings(edit_);
      meter_.reset(playback_->world());
      error_.clear();
    } catch (const InvalidArgument& e) {
      error_ = e.what();
      edit_ = playback_->scene().world;
    }
  }

  void panel() {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("Inertia");
    ImGui::PushItemWidth(-140);  // room for the labels
    const World& world = playback_->world();

    if (ImGui::CollapsingHeader("Samples", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::BeginChild("samples", ImVec2(0, 170), true);
      for (const std::string& group : sampleGroups(samples_)) {
        if (!ImGui::TreeNodeEx(group.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) continue;
        for (std::size_t i = 0; i < samples_.size(); ++i) {
          if (samples_[i].group != group) continue;
          ImGui::PushID(int(i));
          if (ImGui::Selectable(samples_[i].name.c_str(), i == current_))
            deferred_ = [this, i] { load(i); };
          ImGui::PopID();
        }
        ImGui::TreePop();
      }
      ImGui::EndChild();
    }
    if (!error_.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error_.c_str());

    if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) {
      if (ImGui::Button(playback_->paused ? "Play" : "Pause"))
        playback_->paused = !playback_->paused;
      ImGui::SameLine();
      if (ImGui::Button("Step")) {
        playback_->paused = true;
        playback_->singleStep();
      }
      ImGui::SameLine();
      if (ImGui::Button("Restart")) deferred_ = [this] { restart(); };
      ImGui::SameLine();
      if (ImGui::Button("Shoot ball")) shoot();
      float scale = float(playback_->timeScale);
      if (ImGui::SliderFloat("time scale", &scale, 0.05f, 2.0f, "%.2f",
                             ImGuiSliderFlags_Logarithmic))
        playback_->timeScale = std::max(0.01, double(scale));
      float speed = float(ball_.speed);
      if (ImGui::SliderFloat("ball speed (m/s)", &speed, 1, 100, "%.0f")) ball_.speed = Real(speed);
      ImGui::Text("t = %.3f s, step %lld, %.0f fps", world.time(), (long long)world.stepCount(),
                  meter_.fps);
    }

    if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) {
      std::int64_t particles = 0;
      for (ParticleSystemId id : world.particleSystems())
        particles += world.particleSystem(id).stats().alive;
      int awake = 0;
      for (BodyId b : world.rigidBodies().bodies())
        awake += world.rigidBodies().type(b) == BodyType::Dynamic && world.rigidBodies().isAwake(b);
      ImGui::Text("bodies %d (%d awake), contacts %d", world.bodyCount(), awake,
                  world.contactCount());
      ImGui::Text("particles %lld in %zu systems", (long long)particles,
                  world.particleSystems().size());
      const PhaseTimes& p = meter_.perStep;
      ImGui::Text("ms per step:");
      ImGui::Text("  broad phase  %7.3f", p.broadPhase);
      ImGui::Text("  narrow phase %7.3f", p.narrowPhase);
      ImGui::Text("  solver       %7.3f", p.solver);
      ImGui::Text("  integration  %7.3f", p.integration);
      ImGui::Text("  particles    %7.3f", p.particles);
    }

    if (ImGui::CollapsingHeader("World settings")) {
      ImGui::TextWrapped(
          "Changes make a new world with these settings; bodies keep their state, "
          "particle systems start again.");
      bool changed = false;
      Eigen::Vector3f g = edit_.gravity.cast<float>();
      // Edits go to edit_ as they happen (the widgets keep no value of their own) and are
      // applied when the widget lets go (drag, or double-click and type).
      if (ImGui::DragFloat3("gravity (m/s^2)", g.data(), 0.05f, -100, 100, "%.2f"))
        edit_.gravity = g.cast<Real>();
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      float hz = float(1 / edit_.dt);
      if (ImGui::SliderFloat("step rate (Hz)", &hz, 10, 480, "%.0f"))
        edit_.dt = Real(1 / double(hz));
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::SliderInt("substeps", &edit_.substeps, 1, 64);
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      int solver = int(edit_.solver.type);
      const char* solvers[] = {"soft_step", "pgs", "lcp_dantzig", "lcp_lemke"};
      if (ImGui::Combo("solver", &solver, solvers, 4)) {
        edit_.solver.type = SolverType(solver);
        changed = true;
      }
      ImGui::SliderInt("iterations", &edit_.solver.iterations, 1, 100);
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::SliderInt("relax iterations", &edit_.solver.relaxIterations, 0, 50);
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      int method = int(edit_.integrator);
      std::array<const char*, ode::kMethodNames.size()> methods{};
      for (std::size_t i = 0; i < methods.size(); ++i) methods[i] = ode::kMethodNames[i].data();
      if (ImGui::Combo("integrator", &method, methods.data(), int(methods.size()))) {
        edit_.integrator = ode::kMethods[std::size_t(method)];
        changed = true;
      }
      changed |= ImGui::Checkbox("sleeping", &edit_.sleeping);
      float hertz = float(edit_.contact.hertz);
      if (ImGui::SliderFloat("contact hertz", &hertz, 5, 240, "%.0f"))
        edit_.contact.hertz = Real(hertz);
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      float jointHertz = float(edit_.solver.jointHertz);
      if (ImGui::SliderFloat("joint hertz", &jointHertz, 5, 480, "%.0f"))
        edit_.solver.jointHertz = Real(jointHertz);
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::SliderInt("threads (0: all)", &edit_.threads, 0, 64);
      changed |= ImGui::IsItemDeactivatedAfterEdit();
      if (changed) deferred_ = [this] { applySettings(); };
    }

    if (ImGui::CollapsingHeader("Debug draw", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::Checkbox("joints", &flags_.joints);
      ImGui::Checkbox("contacts", &flags_.contacts);
      ImGui::SameLine();
      ImGui::Checkbox("speculative", &flags_.speculative);
      ImGui::Checkbox("AABBs (shape bounds)", &flags_.aabbs);
      ImGui::Checkbox("velocities", &flags_.velocities);
      ImGui::SameLine();
      ImGui::Checkbox("centres of mass", &flags_.centersOfMass);
      ImGui::Checkbox("broad-phase tree", &flags_.broadPhaseTree);
      ImGui::Checkbox("mesh BVH", &flags_.meshBvh);
      if (flags_.meshBvh) ImGui::SliderInt("BVH depth", &flags_.bvhDepth, 0, 12);
      ImGui::Checkbox("sleeping bodies in blue-grey", &showSleeping_);
    }
    if (ImGui::CollapsingHeader("Help")) {
      ImGui::TextWrapped(
          "Left drag: grab a body (spring) or orbit. Right/middle drag: pan. Wheel: zoom. "
          "Shift+click or B: shoot a ball. Space: play/pause. S: step. M: slow motion. "
          "R: restart. C: reset camera. Tab: hide this panel. F12: screenshot. Esc: quit.");
      if (!options_.screenshot.empty() && ImGui::Button("Screenshot")) screenshotRequested_ = true;
    }
    if (!message_.empty()) ImGui::TextUnformatted(message_.c_str());
    ImGui::PopItemWidth();
    ImGui::End();
  }

  GLFWwindow* window_;
  const ViewerOptions& options_;
  std::vector<Sample> samples_;
  std::size_t current_ = 0;
  std::unique_ptr<Playback> playback_{};
  Renderer renderer_{};
  LineRenderer lineRenderer_{};
  DebugLines lines_{};
  DebugDrawFlags flags_{};
  bool showPanel_ = true;
  bool showSleeping_ = false;
  bool slowMotion_ = false;
  OrbitCamera orbit_{};
  Aabb bounds_{};
  Real scale_ = Real(0.5);
  std::optional<MouseSpring> spring_{};
  BallSettings ball_{};
  WorldSettings edit_{};
  PhaseMeter meter_{};
  double mouseX_ = 0, mouseY_ = 0;
  bool orbiting_ = false, panning_ = false;
  bool screenshotRequested_ = false;
  int width_ = 1, height_ = 1;
  std::string error_{}, message_{};
  std::function<void()> deferred_{};
};

App* appOf(GLFWwindow* window) { return static_cast<App*>(glfwGetWindowUserPointer(window)); }

// Owns GLFW, the window and ImGui, released in reverse order whatever happens.
struct Session {
  GLFWwindow* window = nullptr;
  bool glfw = false, imgui = false, imguiGlfw = false, imguiGl = false;
  ~Session() {
    if (imguiGl) ImGui_ImplOpenGL3_Shutdown();
    if (imguiGlfw) ImGui_ImplGlfw_Shutdown();
    if (imgui) ImGui::DestroyContext();
    if (window) glfwDestroyWindow(window);
    if (glfw) glfwTerminate();
  }
};

// Out of line: messages built by concatenation (GCC 12's false -Warray-bounds when inlined).
[[gnu::noinline]] int fail(int code, const std::string& message) {
  std::fprintf(stderr, "inertia: view: %s\n", message.c_str());
  return code;
}

}  // namespace

std::string displayProblem() {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((x11 && *x11) || (wayland && *wayland)) return {};
  return "no display: neither DISPLAY nor WAYLAND_DISPLAY is set, and the viewer needs a "
         "window (use `inertia render` to draw offscreen, or run under xvfb-run)";
}

int runViewer(const ViewerOptions& options) {
  // The sample list and the first sample are checked before any window: bad input is reported
  // the same way with or without a display.
  std::vector<Sample> samples = allSamples(options.scenesDir);
  std::size_t first = 0;
  if (options.scene) {
    std::optional<std::size_t> found = findSample(samples, *options.scene);
    if (!found) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(*options.scene, ec))
        return fail(kBadInput, *options.scene + ": no such scene file or sample");
      const std::filesystem::path file = *options.scene;
      samples.insert(samples.begin(), Sample{"Scenes", file.stem().string(),
                                             [file] { return io::loadScene(file); }, file});
      found = 0;
    }
    first = *found;
  }
  if (samples.empty()) return fail(kBadInput, "no samples");
  try {
    io::Scene scene = samples[first].build();
    (void)io::instantiate(scene);
  } catch (const io::SceneError& e) {
    return fail(kBadInput, e.what());
  } catch (const InvalidArgument& e) {
    return fail(kBadInput, samples[first].name + ": " + e.what());
  }

  if (std::string problem = displayProblem(); !problem.empty()) return fail(kBadInput, problem);
  Session session;
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    return fail(kBadInput, "cannot open the display (" + glfwMessage +
                               "); use `inertia render` to draw offscreen");
  session.glfw = true;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  session.window = glfwCreateWindow(options.width, options.height, "Inertia", nullptr, nullptr);
  if (!session.window) {
    glfwWindowHint(GLFW_SAMPLES, 0);
    session.window = glfwCreateWindow(options.width, options.height, "Inertia", nullptr, nullptr);
  }
  if (!session.window)
    return fail(kBadInput, "cannot open an OpenGL 3.3 core window (" + glfwMessage + ")");
  glfwMakeContextCurrent(session.window);
  glfwSwapInterval(options.frames > 0 ? 0 : 1);

  try {
    App app(session.window, options, std::move(samples));
    if (!app.load(first)) return fail(kBadInput, app.error());
    glfwSetWindowUserPointer(session.window, &app);
    glfwSetKeyCallback(session.window, [](GLFWwindow* w, int key, int, int action, int) {
      appOf(w)->onKey(key, action);
    });
    glfwSetMouseButtonCallback(session.window, [](GLFWwindow* w, int button, int action, int mods) {
      appOf(w)->onMouseButton(button, action, mods);
    });
    glfwSetScrollCallback(session.window,
                          [](GLFWwindow* w, double, double dy) { appOf(w)->onScroll(dy); });

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    session.imgui = true;
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    // Installs ImGui's callbacks, which chain to the ones above.
    session.imguiGlfw = ImGui_ImplGlfw_InitForOpenGL(session.window, true);
    session.imguiGl = ImGui_ImplOpenGL3_Init("#version 330 core");
    if (!session.imguiGlfw || !session.imguiGl)
      return fail(kInternalError, "Dear ImGui could not start");

    double last = glfwGetTime();
    for (std::int64_t n = 1; !glfwWindowShouldClose(session.window); ++n) {
      glfwPollEvents();
      const double now = glfwGetTime();
      // A stalled frame (a breakpoint, a dragged window) must not become a huge time step.
      const double realSeconds = options.frames > 0 ? kFixedFrame : std::min(now - last, 0.25);
      last = now;
      app.frame(realSeconds);
      const bool lastFrame = options.frames > 0 && n >= options.frames;
      if ((lastFrame || app.screenshotRequested()) && !options.screenshot.empty())
        app.writeScreenshot(options.screenshot);
      glfwSwapBuffers(session.window);
      if (lastFrame) break;
    }
    glfwSetWindowUserPointer(session.window, nullptr);
  } catch (const OutputError& e) {
    return fail(kBadInput, std::string("--screenshot: ") + e.what());
  } catch (const GlError& e) {
    return fail(kInternalError, e.what());
  }
  return kOk;
}

}  // namespace inertia::viewer
