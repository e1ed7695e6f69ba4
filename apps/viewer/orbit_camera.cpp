// Orbit, pan and zoom of the viewer's camera, and rays through pixels (orbit_camera.h).
#include "orbit_camera.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace inertia::viewer {

namespace {
constexpr float kMaxPitch = 1.55f;          // just short of straight up or down
constexpr float kRadiansPerPixel = 0.006f;  // orbit speed
}  // namespace

OrbitCamera OrbitCamera::fromView(const CameraView& view) {
  OrbitCamera o;
  o.target = view.target;
  o.fovY = view.fovY;
  const Eigen::Vector3f d = view.position - view.target;
  o.distance = std::max(d.norm(), 1e-3f);
  o.pitch =
      std::clamp(std::asin(std::clamp(d.y() / o.distance, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
  o.yaw = std::atan2(d.x(), d.z());
  return o;
}

CameraView OrbitCamera::view() const {
  CameraView v;
  const Eigen::Vector3f offset(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                               std::cos(pitch) * std::cos(yaw));
  v.position = target + distance * offset;
  v.target = target;
  v.fovY = fovY;
  return v;
}

void OrbitCamera::orbit(float dxPixels, float dyPixels) {
  yaw -= kRadiansPerPixel * dxPixels;
  pitch = std::clamp(pitch + kRadiansPerPixel * dyPixels, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(float dxPixels, float dyPixels, int viewportHeight) {
  // Metres per pixel at the target's depth.
  const float scale = 2 * distance * std::tan(fovY * std::numbers::pi_v<float> / 360) /
                      float(std::max(1, viewportHeight));
  const Eigen::Matrix3f rotation = viewMatrix(view()).block<3, 3>(0, 0).transpose();
  const Eigen::Vector3f right = rotation.col(0), up = rotation.col(1);
  target += scale * (-dxPixels * right + dyPixels * up);
}

void OrbitCamera::zoom(float wheel) {
  distance = std::clamp(distance * std::pow(0.9f, wheel), 0.05f, 5000.0f);
}

Ray pixelRay(const CameraView& camera, double x, double y, int width, int height, float length) {
  const float aspect = float(width) / float(std::max(1, height));
  const float tanHalf = std::tan(camera.fovY * std::numbers::pi_v<float> / 360);
  const float ndcX = float(2 * x / std::max(1, width) - 1);
  const float ndcY = float(1 - 2 * y / std::max(1, height));
  // Camera axes are the rows of the view matrix's rotation (the camera looks down -z).
  const Eigen::Matrix3f toWorld = viewMatrix(camera).block<3, 3>(0, 0).transpose();
  const Eigen::Vector3f d =
      (toWorld * Eigen::Vector3f(ndcX * tanHalf * aspect, ndcY * tanHalf, -1)).normalized();
  return {.origin = camera.position.cast<Real>(),
          .direction = (length * d).cast<Real>(),
          .maxFraction = 1};
}

}  // namespace inertia::viewer
