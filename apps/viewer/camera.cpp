#include "camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inertia/geometry/bounds.h"

namespace inertia::viewer {

Eigen::Matrix4f viewMatrix(const CameraView& c) {
  const Eigen::Vector3f f = (c.target - c.position).normalized();
  Eigen::Vector3f up = Eigen::Vector3f::UnitY();
  if (std::abs(f.dot(up)) > 0.999f) up = Eigen::Vector3f::UnitZ();
  const Eigen::Vector3f s = f.cross(up).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(c.position);
  m(1, 3) = -u.dot(c.position);
  m(2, 3) = f.dot(c.position);
  return m;
}

Eigen::Matrix4f projectionMatrix(const CameraView& c, float aspect) {
  const float t = std::tan(c.fovY * std::numbers::pi_v<float> / 360.0f);
  const float n = c.nearPlane, f = c.farPlane;
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = 1.0f / (aspect * t);
  m(1, 1) = 1.0f / t;
  m(2, 2) = -(f + n) / (f - n);
  m(2, 3) = -2.0f * f * n / (f - n);
  m(3, 2) = -1.0f;
  return m;
}

Aabb sceneBounds(const World& world) {
  const RigidBodySystem& rb = world.rigidBodies();
  Aabb box = Aabb::empty();
  std::vector<Plane> planes;
  auto add = [&](const Shape& shape, const Transform& pose) {
    if (const Plane* p = shape.getIf<Plane>()) {
      const Vec3 n = pose.rotate(p->normal);
      planes.push_back({n, p->offset + n.dot(pose.p)});
    } else {
      box.merge(worldBounds(shape, pose));
    }
  };
  for (BodyId body : rb.bodies()) {
    for (ShapeId shape : rb.shapes(body)) add(rb.collider(shape).shape(), rb.shapeTransform(shape));
  }
  for (ParticleSystemId id : world.particleSystems()) {
    for (const Obstacle& o : world.particleSystem(id).obstacles()) add(o.collider.shape(), o.pose);
    const ParticlePool& pool = world.particleSystem(id).pool();
    for (std::size_t i = 0; i < pool.size(); ++i) box.extend(pool.position(i));
  }
  for (DeformableId id : world.deformables()) {
    const Deformable& d = world.deformable(id);
    for (std::size_t i = 0; i < d.vertexCount(); ++i) box.extend(d.position(i));
  }
  if (!box.isValid()) {
    if (planes.empty()) return box;
    box = Aabb::fromCenterHalfExtents(Vec3::Zero(), Vec3::Zero());
  }
  const Vec3 c = box.center();
  for (const Plane& p : planes) box.extend(c - (p.normal.dot(c) - p.offset) * p.normal);
  return box;
}

CameraView frameBounds(const Aabb& bounds, float fovY, float aspect) {
  Aabb b = bounds.isValid() ? bounds : Aabb::fromCenterHalfExtents(Vec3::Zero(), Vec3::Constant(5));
  const Eigen::Vector3f center = b.center().cast<float>();
  const float radius = std::max(0.5f, float(b.halfExtents().norm()));
  const float halfV = fovY * std::numbers::pi_v<float> / 360.0f;
  const float halfH = std::atan(std::tan(halfV) * aspect);
  const float distance = radius / std::sin(std::min(halfV, halfH));
  CameraView c;
  c.fovY = fovY;
  c.target = center;
  // From the front (+z) and 25 degrees above the horizon.
  c.position = center + distance * Eigen::Vector3f(0, 0.4226f, 0.9063f);
  fitClipPlanes(c, b);
  return c;
}

void fitClipPlanes(CameraView& c, const Aabb& bounds) {
  if (!bounds.isValid()) return;
  const float d = (bounds.center().cast<float>() - c.position).norm();
  const float radius = float(bounds.halfExtents().norm());
  c.farPlane = std::max(100.0f, 4 * (d + radius));
  c.nearPlane = std::clamp(0.02f * std::max(0.0f, d - radius), 0.01f, 1.0f);
}

Aabb framingBounds(const World& world, const io::Scene& scene) {
  Aabb b = sceneBounds(world);
  for (const io::ParticleSystemDesc& ps : scene.particleSystems) {
    for (const EmitterSettings& e : ps.emitters) b.extend(e.pose.p);
  }
  if (b.isValid() && (b.upper - b.lower).maxCoeff() < Real(2)) b = b.inflated(Real(1));
  return b;
}

CameraView sceneCamera(const io::Scene& scene, const World& world, float aspect) {
  if (!scene.camera) return frameBounds(framingBounds(world, scene), 45, aspect);
  CameraView camera;
  camera.position = scene.camera->position.cast<float>();
  camera.target = scene.camera->target.cast<float>();
  camera.fovY = float(scene.camera->fov);
  fitClipPlanes(camera, framingBounds(world, scene));
  return camera;
}

}  // namespace inertia::viewer
