// Draws a World with OpenGL 3.3 core: bodies' shapes shaded by a directional light (planes as a
// large ground square with a grid), particles as point sprites, deformables as shaded two-sided
// surfaces (cloth, soft bodies) or tubes (ropes, hair). It draws into whatever
// framebuffer is bound in the current context: an offscreen target (inertia render) or a
// window (the interactive viewer), so it does not know how the context was made.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <vector>

#include "camera.h"
#include "gl.h"
#include "inertia/world/world.h"

namespace inertia::viewer {

/// Colours of shapes from a scene: colors[i][j] is shape j of the i-th body in
/// RigidBodySystem::bodies() order; a missing entry or nullopt takes the body's default colour.
using ShapeColors = std::vector<std::vector<std::optional<Vec3>>>;

/// The colour of a body without one: light grey for planes' and static bodies, else a
/// deterministic hue per body index (golden-ratio steps around the colour wheel).
Eigen::Vector3f defaultBodyColor(std::size_t bodyIndex, BodyType type);

/// Compiles and links a vertex and a fragment shader into a program in the current context;
/// throws GlError with the compiler's log.
GLuint linkProgram(const char* vertexSource, const char* fragmentSource);

struct RenderStyle {
  Eigen::Vector3f background = Eigen::Vector3f(0.66f, 0.74f, 0.83f);  ///< Sky and fog (rgb).
  /// Direction the light travels (world), normalised when drawn.
  Eigen::Vector3f lightDirection = Eigen::Vector3f(-0.35f, -1.0f, -0.45f);
  bool particles = true;  ///< Draw particle systems.
  /// Particles darken towards the end of their life (age / lifetime).
  bool colorOverLife = true;
  int segments = 32;  ///< Tessellation of round shapes.
  /// When set, sleeping dynamic bodies are drawn in this colour (the viewer's debug toggle).
  std::optional<Eigen::Vector3f> sleepingColor{};
};

/// Draws worlds: bodies, particles, and the obstacles of particle systems (in grey). Needs a
/// current OpenGL 3.3 core context for its whole life (GPU meshes of shapes are cached by ShapeId,
/// and dropped when their shape disappears).
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  RenderStyle& style() { return style_; }
  void setShapeColors(ShapeColors colors) { colors_ = std::move(colors); }

  /// Clears the bound framebuffer (a viewport of width x height pixels) and draws `world`.
  /// `bodyPoses`, when not empty, holds the pose of each body's origin in
  /// RigidBodySystem::bodies() order, drawn instead of the current one (the viewer passes poses
  /// interpolated between two physics steps); bodies past its end are drawn where they are.
  void draw(const World& world, const CameraView& camera, int width, int height,
            std::span<const Transform> bodyPoses = {});

 private:
  struct GpuMesh {
    GLuint vao = 0, vbo = 0, ibo = 0;
    GLsizei count = 0;
    bool used = false;
  };
  GpuMesh& meshFor(std::uint64_t key, const Shape& shape);
  void drawShape(std::uint64_t key, const Shape& shape, const Transform& pose,
                 const Eigen::Vector3f& color);
  void drawParticles(const World& world, const Eigen::Matrix4f& view, const Eigen::Matrix4f& proj,
                     float pointScale);
  void drawDeformables(const World& world);

  RenderStyle style_{};
  ShapeColors colors_{};
  GLuint meshProgram_ = 0, pointProgram_ = 0;
  GLuint pointVao_ = 0, pointVbo_ = 0;
  std::vector<float> pointData_{};
  std::map<std::uint64_t, GpuMesh> meshes_{};
  GpuMesh deformable_{};  // buffers refilled for each deformable every frame
  std::vector<float> deformableData_{};
};

}  // namespace inertia::viewer
