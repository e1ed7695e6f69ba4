// Where the renderer looks from: view and projection matrices, and a default camera that
// frames a world's bodies and particles.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"
#include "inertia/io/scene.h"
#include "inertia/world/world.h"

namespace inertia::viewer {

/// A perspective camera (world coordinates, y up).
struct CameraView {
  Eigen::Vector3f position = Eigen::Vector3f(0, 5, 15);  ///< Eye (m).
  Eigen::Vector3f target = Eigen::Vector3f::Zero();      ///< Point looked at (m).
  float fovY = 45;                                       ///< Vertical field of view (degrees).
  float nearPlane = 0.05f;                               ///< m
  float farPlane = 500;                                  ///< m
};

/// Right-handed look-at view matrix (OpenGL convention: the camera looks down -z). The up
/// vector is world +y, or +z when the view is vertical.
Eigen::Matrix4f viewMatrix(const CameraView& camera);
/// OpenGL perspective projection for `aspect` = width / height.
Eigen::Matrix4f projectionMatrix(const CameraView& camera, float aspect);

/// Bounds of what is worth seeing: every shape of every body and particle obstacle except
/// planes, the live particles and the deformables' vertices. Empty when there is nothing
/// finite. Each plane adds the point of the plane nearest the centre of the rest, so the ground
/// stays in view.
Aabb sceneBounds(const World& world);

/// A camera in front of (+z) and above `bounds`, looking at their centre, far enough for their
/// bounding sphere to fit both the vertical and the horizontal field of view; clip planes
/// follow the distance. An empty `bounds` is taken as a 10 m box at the origin.
CameraView frameBounds(const Aabb& bounds, float fovY, float aspect);

/// Near and far planes fitted to a camera's distance to `bounds` (kept when bounds are empty).
void fitClipPlanes(CameraView& camera, const Aabb& bounds);

/// Bounds for framing a scene: sceneBounds(world) and each particle emitter's position
/// (particles may not exist yet at time 0), grown by 1 m when smaller than 2 m.
Aabb framingBounds(const World& world, const io::Scene& scene);

/// The camera a scene starts with: its "camera" when given (clip planes fitted), else one
/// framing its bounds (frameBounds with a 45-degree field of view).
CameraView sceneCamera(const io::Scene& scene, const World& world, float aspect);

}  // namespace inertia::viewer
