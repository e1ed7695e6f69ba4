// The orbit camera and pixel rays: round trips through CameraView, orbit keeps the distance,
// pan moves the target in the view plane, and the ray through a projected point passes
// through it.
#include "orbit_camera.h"

#include <gtest/gtest.h>

namespace inertia::viewer {
namespace {

CameraView sample() {
  CameraView v;
  v.position = {3, 4, 12};
  v.target = {1, 1, 0};
  v.fovY = 50;
  return v;
}

TEST(OrbitCamera, FromViewRoundTrips) {
  const CameraView v = sample();
  const CameraView back = OrbitCamera::fromView(v).view();
  EXPECT_TRUE(back.position.isApprox(v.position, 1e-5f));
  EXPECT_TRUE(back.target.isApprox(v.target));
  EXPECT_EQ(back.fovY, v.fovY);
}

TEST(OrbitCamera, OrbitKeepsTargetAndDistanceAndClampsPitch) {
  OrbitCamera o = OrbitCamera::fromView(sample());
  const float d = o.distance;
  o.orbit(120, -40);
  const CameraView v = o.view();
  EXPECT_NEAR((v.position - v.target).norm(), d, 1e-4f);
  EXPECT_TRUE(v.target.isApprox(sample().target));
  o.orbit(0, 1e6f);  // far past straight down
  EXPECT_LT(o.pitch, 1.5708f);
  EXPECT_TRUE(o.view().position.allFinite());
}

TEST(OrbitCamera, ZoomAndPan) {
  OrbitCamera o = OrbitCamera::fromView(sample());
  const float d = o.distance;
  o.zoom(1);
  EXPECT_NEAR(o.distance, 0.9f * d, 1e-4f);
  o.zoom(-1);
  EXPECT_NEAR(o.distance, d, 1e-4f);
  // Dragging right by a full viewport height moves the target left by the visible height at
  // the target's depth, in the view plane (perpendicular to the view direction).
  const CameraView before = o.view();
  o.pan(600, 0, 600);
  const Eigen::Vector3f moved = o.target - before.target;
  const float visible = 2 * d * std::tan(before.fovY * 3.14159265f / 360);
  EXPECT_NEAR(moved.norm(), visible, 1e-3f * visible);
  EXPECT_NEAR(moved.dot((before.target - before.position).normalized()), 0, 1e-4f);
  const Eigen::Vector3f right = viewMatrix(before).block<1, 3>(0, 0).transpose();
  EXPECT_LT(moved.dot(right), 0);
}

TEST(PixelRay, PassesThroughWhatThePixelShows) {
  const CameraView v = sample();
  const int w = 640, h = 360;
  const Eigen::Matrix4f m = projectionMatrix(v, float(w) / h) * viewMatrix(v);
  const Eigen::Vector3f point(2, 0.5f, -1);
  const Eigen::Vector4f clip = m * point.homogeneous();
  const double x = (clip.x() / clip.w() + 1) / 2 * w, y = (1 - clip.y() / clip.w()) / 2 * h;
  const Ray ray = pixelRay(v, x, y, w, h, 100);
  EXPECT_NEAR(ray.direction.norm(), 100, 1e-3);
  EXPECT_TRUE(ray.origin.isApprox(v.position.cast<Real>()));
  const Vec3 d = ray.direction.normalized();
  const Vec3 toPoint = point.cast<Real>() - ray.origin;
  EXPECT_LT((toPoint - toPoint.dot(d) * d).norm(), 1e-3);  // distance of the point to the ray
  // The centre pixel looks at the target.
  const Ray centre = pixelRay(v, w / 2.0, h / 2.0, w, h, 1);
  EXPECT_TRUE(centre.direction.isApprox((v.target - v.position).normalized().cast<Real>(), 1e-5f));
}

}  // namespace
}  // namespace inertia::viewer
