// Debug drawing for the viewer: coloured line segments showing contact points and normals,
// joints, shape bounding boxes, velocities and centres of mass. Building the lines needs no GL (testable
// headless); LineRenderer draws them with a minimal OpenGL 3.3 line program.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "gl.h"
#include "inertia/world/world.h"

namespace inertia::viewer {

/// What to draw.
struct DebugDrawFlags {
  bool contacts = false;       ///< Touching contact points (red) and normals (yellow).
  bool speculative = false;    ///< Speculative contact points too (grey), with `contacts`.
  bool aabbs = false;          ///< Shape bounds: awake bodies cyan, sleeping ones dark blue.
  bool velocities = false;     ///< Linear velocity (green, 0.1 s of motion), angular (magenta).
  bool centersOfMass = false;  ///< Axes cross at each dynamic body's centre of mass.
  /// Joints: each body's centre to its anchor (white), the anchors (crosses), the joint's axis
  /// (cyan), a hinge's limits (orange); a broken or disabled joint's anchors in red.
  bool joints = true;
  /// The broad phase's dynamic tree: fat leaf boxes (grey) and inner nodes, warmer the
  /// higher they sit.
  bool broadPhaseTree = false;
  /// The bounding-volume hierarchies of triangle-mesh shapes, posed with their shapes, down to
  /// `bvhDepth` levels below the root (warmer nearer the root).
  bool meshBvh = false;
  int bvhDepth = 4;
};

/// Line segments with a colour per vertex: 6 floats per vertex (x y z r g b), 2 vertices a line.
struct DebugLines {
  std::vector<float> vertices{};

  void add(const Vec3& a, const Vec3& b, const Eigen::Vector3f& color);
  std::size_t lineCount() const { return vertices.size() / 12; }
  void clear() { vertices.clear(); }
};

/// Appends the lines `flags` asks for, from the world's state after its last step. `scale` (m)
/// sizes normals (one scale) and crosses (a quarter).
void buildDebugLines(const World& world, const DebugDrawFlags& flags, Real scale, DebugLines& out);

/// Draws DebugLines in the current OpenGL 3.3 core context, depth-tested against what is
/// already drawn. Needs the context for its whole life.
class LineRenderer {
 public:
  LineRenderer();
  ~LineRenderer();
  LineRenderer(const LineRenderer&) = delete;
  LineRenderer& operator=(const LineRenderer&) = delete;

  /// `viewProj`: projection times view (camera.h).
  void draw(const DebugLines& lines, const Eigen::Matrix4f& viewProj);

 private:
  GLuint program_ = 0, vao_ = 0, vbo_ = 0;
};

}  // namespace inertia::viewer
