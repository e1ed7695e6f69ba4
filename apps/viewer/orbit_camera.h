// The interactive viewer's camera: orbit about a target, pan and zoom from mouse motion, and
// the ray through a pixel (for picking and shooting). No GL here.
#pragma once

#include <Eigen/Core>

#include "camera.h"
#include "inertia/collision/queries.h"

namespace inertia::viewer {

/// A camera on a sphere about `target`: yaw about world +y, pitch above the horizontal plane.
struct OrbitCamera {
  Eigen::Vector3f target = Eigen::Vector3f::Zero();  ///< m
  float yaw = 0;                                     ///< rad; 0 looks down -z (the eye on +z)
  float pitch = 0.3f;                                ///< rad, kept inside (-pi/2, pi/2)
  float distance = 15;                               ///< m, > 0
  float fovY = 45;                                   ///< degrees

  /// The orbit that sees what `view` sees (its eye, target and field of view).
  static OrbitCamera fromView(const CameraView& view);
  /// Eye, target and field of view (clip planes at their defaults).
  CameraView view() const;

  /// Turns by mouse motion in pixels (right drag: the scene turns with the mouse).
  void orbit(float dxPixels, float dyPixels);
  /// Moves the target in the view plane so that the scene follows the mouse, for a viewport
  /// `viewportHeight` pixels high.
  void pan(float dxPixels, float dyPixels, int viewportHeight);
  /// Moves the eye towards the target (wheel > 0) or away, by 10% per wheel notch.
  void zoom(float wheel);
};

/// The ray from the eye through pixel (x, y) (from the top-left corner of a width x height
/// viewport, pixel centres at .5): unit direction times `length` (m), maxFraction 1, so a hit's
/// fraction times `length` is its distance from the eye.
Ray pixelRay(const CameraView& camera, double x, double y, int width, int height, float length);

}  // namespace inertia::viewer
