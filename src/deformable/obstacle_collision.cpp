// The collision stage of a deformable's step: every free vertex against the static obstacles
// (swept from where the step started, as particles are, so fast vertices do not tunnel), then
// pushed out to `thickness` from every obstacle, static or moving. Contacts are inelastic with
// Coulomb friction (the particles' impact model with restitution 0).
#include <optional>

#include "deformable/scratch.h"
#include "inertia/collision/queries.h"
#include "particles/impact.h"

namespace inertia {

namespace {

// Left between a vertex and a surface beyond the thickness, so that a vertex resting on a
// surface is not found inside it again by rounding.
Real skin(Real thickness) { return Real(1e-3) * thickness; }

struct Contact {
  Vec3 point, normal;
  Real fraction;
};

// The first obstacle at rest (a static one, or a moving one whose velocity is zero) the
// segment start -> end enters.
std::optional<Contact> firstHit(std::span<const Obstacle> obstacles,
                                std::span<const MovingObstacle> moving,
                                std::span<const Aabb> bounds, const Vec3& start, const Vec3& end,
                                Real thickness) {
  const Aabb swept = Aabb{start.cwiseMin(end), start.cwiseMax(end)}.inflated(thickness);
  std::optional<Contact> first;
  const auto test = [&](const Collider& collider, const Transform& pose, const Aabb& box) {
    if (!box.overlaps(swept)) return;
    const Real maxFraction = first ? first->fraction : Real(1);
    const auto hit = castRay(collider, pose, Ray{start, end - start, maxFraction});
    if (hit && (!first || hit->fraction < first->fraction))
      first = Contact{hit->point, hit->normal, hit->fraction};
  };
  for (std::size_t k = 0; k < obstacles.size(); ++k)
    test(obstacles[k].collider, obstacles[k].pose, bounds[k]);
  for (std::size_t k = 0; k < moving.size(); ++k)
    if (moving[k].linearVelocity.isZero(0) && moving[k].angularVelocity.isZero(0))
      test(*moving[k].collider, moving[k].pose, bounds[obstacles.size() + k]);
  return first;
}

// Pushes x out to the thickness from one shape; answers with the velocity relative to the
// surface `surface` (zero for static shapes). True when it touched.
bool pushOut(const Collider& collider, const Transform& pose, const Vec3& surfaceVelocity,
             Real thickness, Real friction, Vec3& x, Vec3& v) {
  const PointQuery q = queryPoint(collider, pose, x);
  if (!(q.distance < thickness)) return false;
  x += q.normal * (thickness + skin(thickness) - q.distance);
  Vec3 relative = v - surfaceVelocity;
  detail::respondToImpact(relative, q.normal, 0, friction, 0);
  v = relative + surfaceVelocity;
  return true;
}

}  // namespace

void Deformable::collide() {
  if (obstacles_.empty() && moving_.empty()) return;
  const Real r = settings_.thickness, mu = settings_.friction;
  const std::span<const Aabb> bounds = scratch_->obstacleBounds;
  for (std::size_t i = 0; i < vertexCount(); ++i) {
    if (pinned_[i]) continue;
    Eigen::Map<Vec3> xm(&x_[3 * i]), vm(&v_[3 * i]);
    Vec3 x = xm, v = vm;
    const Vec3 start = Eigen::Map<const Vec3>(&scratch_->start[3 * i]);
    if (const auto hit = firstHit(obstacles_, moving_, bounds, start, x, r)) {
      // Stop at the surface, moved out by the thickness; the rest of the step is lost.
      x = hit->point + hit->normal * (r + skin(r));
      detail::respondToImpact(v, hit->normal, 0, mu, 0);
    }
    for (std::size_t k = 0; k < obstacles_.size(); ++k)
      if (bounds[k].inflated(r).contains(x))
        pushOut(obstacles_[k].collider, obstacles_[k].pose, Vec3::Zero(), r, mu, x, v);
    for (std::size_t k = 0; k < moving_.size(); ++k) {
      const MovingObstacle& o = moving_[k];
      if (!bounds[obstacles_.size() + k].inflated(r).contains(x)) continue;
      const Vec3 surface = o.linearVelocity + o.angularVelocity.cross(x - o.center);
      pushOut(*o.collider, o.pose, surface, r, mu, x, v);
    }
    xm = x;
    vm = v;
  }
}

}  // namespace inertia
