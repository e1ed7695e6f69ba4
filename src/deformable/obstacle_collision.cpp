// The collision stage of a deformable's step: every free vertex against the static obstacles
// (swept from where the step started, as particles are, so fast vertices do not tunnel), then
// pushed out to `thickness` from every obstacle, static or moving. Contacts are inelastic with
// Coulomb friction (the particles' impact model with restitution 0); against a dynamic body
// the impulse is shared by the vertex's and the body's masses and reported for the body.
#include <algorithm>
#include <limits>
#include <optional>

#include "deformable/scratch.h"
#include "inertia/collision/queries.h"
#include "particles/impact.h"

namespace inertia {

namespace {

// Left between a vertex and a surface beyond the thickness, so that a vertex resting on a
// surface is not found inside it again by rounding.
Real skin(Real thickness) { return Real(1e-3) * thickness; }

// The obstacle index of a vertex held against a static obstacle (not one of the moving ones).
constexpr std::size_t kStaticObstacle = std::numeric_limits<std::size_t>::max();

struct Contact {
  Vec3 point, normal;
  Real fraction;
  std::ptrdiff_t moving = -1;  // index of the moving obstacle hit, -1 for a static one
};

// The first obstacle the vertex's path start -> end enters. A moving obstacle is swept in its
// own frame at the step's end (its pose): the start is carried by the body's motion over the
// step, start + h (v + w x (start - c)), to first order, so the segment is the vertex's motion
// relative to the body and a fast body cannot pass over a vertex (nor a vertex through it).
std::optional<Contact> firstHit(std::span<const Obstacle> obstacles,
                                std::span<const MovingObstacle> moving,
                                std::span<const Aabb> bounds, const Vec3& start, const Vec3& end,
                                Real thickness, Real h) {
  std::optional<Contact> first;
  const auto test = [&](const Collider& collider, const Transform& pose, const Aabb& box,
                        const Vec3& from, std::ptrdiff_t index) {
    const Aabb swept = Aabb{from.cwiseMin(end), from.cwiseMax(end)}.inflated(thickness);
    if (!box.overlaps(swept)) return;
    const Real maxFraction = first ? first->fraction : Real(1);
    const auto hit = castRay(collider, pose, Ray{from, end - from, maxFraction});
    if (hit && (!first || hit->fraction < first->fraction))
      first = Contact{hit->point, hit->normal, hit->fraction, index};
  };
  for (std::size_t k = 0; k < obstacles.size(); ++k)
    test(obstacles[k].collider, obstacles[k].pose, bounds[k], start, -1);
  for (std::size_t k = 0; k < moving.size(); ++k) {
    const MovingObstacle& o = moving[k];
    // The body's centre at the step's start is h v behind where it is now.
    const Vec3 from =
        start +
        h * (o.linearVelocity + o.angularVelocity.cross(start - (o.center - h * o.linearVelocity)));
    test(*o.collider, o.pose, bounds[obstacles.size() + k], from, std::ptrdiff_t(k));
  }
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

// An inelastic contact with Coulomb friction between a vertex of inverse mass wv and a body
// (inverse mass and world inverse inertia about its centre), at the vertex x with normal n:
// the normal impulse stops the approach, jn = -v_n / w_n with w_n = wv + 1/M + (r x n)^T I^-1
// (r x n), and friction takes up to mu jn off the sliding (Mirtich and Canny's impulse, e = 0).
// The vertex gets J, the body -J (written to its velocities here, so later vertices see them).
// Returns the impulse on the body.
Vec3 twoWayImpulse(MovingObstacle& o, Real wv, Real friction, const Vec3& x, const Vec3& n,
                   Vec3& v) {
  const Vec3 r = x - o.center;
  const Vec3 relative = v - (o.linearVelocity + o.angularVelocity.cross(r));
  const Real vn = relative.dot(n);
  if (!(vn < 0)) return Vec3::Zero();
  const auto inverseMass = [&](const Vec3& d) {
    const Vec3 rd = r.cross(d);
    return wv + o.inverseMass + rd.dot(o.inverseInertia * rd);
  };
  const Real jn = -vn / inverseMass(n);
  Vec3 j = jn * n;
  const Vec3 vt = relative - vn * n;
  const Real vtNorm = vt.norm();
  if (vtNorm > 0) {
    const Vec3 t = vt / vtNorm;
    j -= std::min(vtNorm / inverseMass(t), friction * jn) * t;
  }
  v += wv * j;
  o.linearVelocity -= o.inverseMass * j;
  o.angularVelocity -= o.inverseInertia * r.cross(j);
  return -j;
}

}  // namespace

// The implicit step's resting contacts (Baraff and Witkin's constrained vertices): each free
// vertex within twice the thickness of a body's shape or a static obstacle, not approaching it
// faster than the thickness per step, is held in the solve to the surface's normal velocity
// there, plus what brings it back out to the thickness within the step. So the solve itself
// carries a resting body's weight: projected out only after the solve, its bottom vertices gave
// way in every solve, and a soft ball on the ground settled squashed (by an amount independent
// of its stiffness, with spring energy in proportion to it). Friction acts in the solve too
// (Coulomb's active set: a held vertex sticks to the surface, or slides with mu times its
// normal impulse), since collide() finds held vertices outside the thickness and has none to
// apply: without it an implicit cloth slid off a sphere and a rope down any slope. Faster
// approaches are impacts, handled in collide() (shared by the vertex's and a dynamic body's
// masses); the held impulses, friction included, go to dynamic bodies only.
void Deformable::holdBodyContacts(Real h) {
  auto& contacts = scratch_->contacts;
  contacts.clear();
  scratch_->contactObstacles.clear();
  const Real r = settings_.thickness;
  const std::span<const Aabb> bounds = scratch_->obstacleBounds;
  // True when the vertex at x (velocity v) rests on the shape: then it is held, to the surface's
  // normal velocity plus what recovers a vertex found inside the thickness.
  const auto hold = [&](std::size_t i, const Vec3& x, const Vec3& v, const Collider& collider,
                        const Transform& pose, const Aabb& box, const Vec3& surface,
                        std::size_t obstacle) {
    if (!box.inflated(2 * r).contains(x)) return false;
    const PointQuery q = queryPoint(collider, pose, x);
    if (!(q.distance < 2 * r)) return false;
    if ((v - surface).dot(q.normal) < -r / h) return false;  // approaching: the swept test's
    const Real recover = std::max(Real(0), r + skin(r) - q.distance) / h;
    contacts.push_back({.vertex = std::uint32_t(i),
                        .normal = q.normal.cast<double>(),
                        .normalVelocity = double(surface.dot(q.normal) + recover),
                        .surfaceVelocity = surface.cast<double>(),
                        .friction = double(settings_.friction)});
    scratch_->contactObstacles.push_back(obstacle);
    return true;
  };
  for (std::size_t i = 0; i < vertexCount(); ++i) {
    if (pinned_[i]) continue;
    const Vec3 x = Eigen::Map<const Vec3>(&x_[3 * i]);
    const Vec3 v = Eigen::Map<const Vec3>(&v_[3 * i]);
    bool held = false;  // one contact per vertex: bodies first, then static obstacles
    for (std::size_t k = 0; k < moving_.size() && !held; ++k) {
      const MovingObstacle& o = moving_[k];
      const Vec3 surface = o.linearVelocity + o.angularVelocity.cross(x - o.center);
      held = hold(i, x, v, *o.collider, o.pose, bounds[obstacles_.size() + k], surface, k);
    }
    for (std::size_t k = 0; k < obstacles_.size() && !held; ++k)
      held = hold(i, x, v, obstacles_[k].collider, obstacles_[k].pose, bounds[k], Vec3::Zero(),
                  kStaticObstacle);
  }
}

// The held contacts' impulses, reversed onto their bodies (and their velocities here).
void Deformable::pushHeldContacts() {
  const auto& contacts = scratch_->contacts;
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const std::size_t k = scratch_->contactObstacles[c];
    if (contacts[c].impulse.isZero(0) || k == kStaticObstacle || !(moving_[k].inverseMass > 0))
      continue;
    MovingObstacle& o = moving_[k];
    const Vec3 x = Eigen::Map<const Vec3>(&x_[3 * contacts[c].vertex]);
    const Vec3 j = -contacts[c].impulse.cast<Real>();
    o.linearVelocity += o.inverseMass * j;
    o.angularVelocity += o.inverseInertia * (x - o.center).cross(j);
    obstacleImpulses_.push_back({scratch_->contactObstacles[c], j, x});
  }
}

void Deformable::collide(Real h) {
  if (obstacles_.empty() && moving_.empty()) return;
  const Real r = settings_.thickness, mu = settings_.friction;
  const std::span<const Aabb> bounds = scratch_->obstacleBounds;
  for (std::size_t i = 0; i < vertexCount(); ++i) {
    if (pinned_[i]) continue;
    Eigen::Map<Vec3> xm(&x_[3 * i]), vm(&v_[3 * i]);
    Vec3 x = xm, v = vm;
    const Vec3 start = Eigen::Map<const Vec3>(&scratch_->start[3 * i]);
    if (const auto hit = firstHit(obstacles_, moving_, bounds, start, x, r, h)) {
      // Stop at the surface, moved out by the thickness; the rest of the step is lost.
      x = hit->point + hit->normal * (r + skin(r));
      if (hit->moving >= 0) {
        // Relative to the body's surface; shared with the body's mass when it is dynamic.
        const std::size_t k = std::size_t(hit->moving);
        const Vec3 j = twoWayImpulse(moving_[k], 1 / masses_[i], mu, x, hit->normal, v);
        if (moving_[k].inverseMass > 0 && !j.isZero(0)) obstacleImpulses_.push_back({k, j, x});
      } else {
        detail::respondToImpact(v, hit->normal, 0, mu, 0);
      }
    }
    for (std::size_t k = 0; k < obstacles_.size(); ++k)
      if (bounds[k].inflated(r).contains(x))
        pushOut(obstacles_[k].collider, obstacles_[k].pose, Vec3::Zero(), r, mu, x, v);
    for (std::size_t k = 0; k < moving_.size(); ++k) {
      const MovingObstacle& o = moving_[k];
      if (!bounds[obstacles_.size() + k].inflated(r).contains(x)) continue;
      if (o.inverseMass > 0) {
        // A dynamic body: pushed out the same way, the velocities exchanged two-way.
        MovingObstacle& body = moving_[k];
        const PointQuery q = queryPoint(*o.collider, o.pose, x);
        if (!(q.distance < r)) continue;
        x += q.normal * (r + skin(r) - q.distance);
        const Vec3 j = twoWayImpulse(body, 1 / masses_[i], mu, x, q.normal, v);
        if (!j.isZero(0)) obstacleImpulses_.push_back({k, j, x});
        continue;
      }
      const Vec3 surface = o.linearVelocity + o.angularVelocity.cross(x - o.center);
      pushOut(*o.collider, o.pose, surface, r, mu, x, v);
    }
    xm = x;
    vm = v;
  }
}

}  // namespace inertia
