// Picking, the mouse spring and shooting balls (interaction.h).
#include "interaction.h"

#include <numbers>

namespace inertia::viewer {

std::optional<MouseSpring> pickBody(const World& world, const Ray& ray) {
  const std::optional<WorldRayHit> hit = world.castRay(ray);
  if (!hit || world.rigidBodies().type(hit->body) != BodyType::Dynamic) return std::nullopt;
  MouseSpring spring;
  spring.body = hit->body;
  spring.localAnchor = world.transform(hit->body).applyInverse(hit->hit.point);
  spring.target = hit->hit.point;
  spring.distance = (hit->hit.point - ray.origin).norm();
  return spring;
}

Vec3 springTarget(const MouseSpring& spring, const Ray& ray) {
  const Real length = ray.direction.norm();
  if (!(length > 0)) return spring.target;
  return ray.origin + (spring.distance / length) * ray.direction;
}

Vec3 springForce(const World& world, const MouseSpring& spring) {
  const RigidBodySystem& rb = world.rigidBodies();
  const Real m = rb.mass(spring.body);
  const Real omega = 2 * std::numbers::pi_v<Real> * spring.frequency;
  const Vec3 anchor = rb.transform(spring.body).apply(spring.localAnchor);
  const Vec3 v = rb.linearVelocity(spring.body) +
                 rb.angularVelocity(spring.body).cross(anchor - rb.centerOfMass(spring.body));
  Vec3 force =
      m * omega * omega * (spring.target - anchor) - 2 * m * spring.dampingRatio * omega * v;
  const Real limit = m * spring.maxAcceleration;
  if (force.norm() > limit) force *= limit / force.norm();
  return force;
}

void applySpring(World& world, const MouseSpring& spring) {
  if (!world.isValid(spring.body)) return;
  RigidBodySystem& rb = world.rigidBodies();
  rb.applyForce(spring.body, springForce(world, spring),
                rb.transform(spring.body).apply(spring.localAnchor));
  // Held bodies would otherwise spin about the anchor for a long time.
  rb.applyTorque(spring.body, -spring.angularDamping *
                                  (rb.inertiaWorld(spring.body) * rb.angularVelocity(spring.body)));
}

BodyId shootBall(World& world, const Ray& ray, const BallSettings& ball) {
  const Vec3 direction = ray.direction.normalized();
  const BodyId id = world.createBody({.position = ray.origin,
                                      .linearVelocity = ball.speed * direction,
                                      .bullet = true,
                                      .name = "ball"});
  world.addShape(id, Sphere{ball.radius},
                 Material{.density = ball.density, .restitution = Real(0.3)});
  return id;
}

}  // namespace inertia::viewer
