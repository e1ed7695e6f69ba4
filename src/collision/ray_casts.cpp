// Ray casts for every shape type, computed in the shape's local frame (fractions are invariant
// under rigid transforms). Analytic for the primitives, face-plane clipping for hulls,
// Moller-Trumbore through the BVH for meshes and along a 2D DDA for height fields.
// A solid entered at s = 0 (origin on the surface, moving in) is a hit at s = 0; an origin
// strictly inside a solid is no hit. Inputs are assumed finite (not checked: hot path).
#include <algorithm>
#include <cmath>
#include <limits>

#include "inertia/collision/mesh_bvh.h"
#include "inertia/collision/queries.h"
#include "inertia/collision/triangle.h"
#include "local_queries.h"

namespace inertia {

namespace {

using detail::LocalHit;
using detail::normalizedOr;
using Hit = std::optional<LocalHit>;

// Entry s of a ray into the ball |x| <= r from an origin outside it (c >= 0), or -1.
// Hearn and Baker's discriminant b^2 - a c = a (r^2 - |o - (b / a) d|^2) and the root c / q
// avoid the cancellation of the textbook formula for distant origins (Haines et al.,
// "Precision improvements for ray/sphere intersection", Ray Tracing Gems, 2019).
Real sphereEntry(const Vec3& o, const Vec3& d, Real r) {
  const Real a = d.squaredNorm(), b = o.dot(d);
  const Real len = o.norm();
  const Real c = (len - r) * (len + r);
  if (c < 0 || b >= 0) return Real(-1);  // inside, or moving away / tangent at the origin
  const Real disc = r * r - (o - (b / a) * d).squaredNorm();
  if (disc < 0) return Real(-1);
  const Real q = -b + std::sqrt(a * disc);  // > 0
  return c / q;
}

Hit cast(const Plane& plane, const Vec3& o, const Vec3& d, Real maxFraction) {
  const Real dist = plane.normal.dot(o) - plane.offset, rate = plane.normal.dot(d);
  if (dist < 0 || !(rate < 0)) return std::nullopt;
  if (dist > -rate * maxFraction) return std::nullopt;
  return LocalHit{std::min(dist / -rate, maxFraction), plane.normal};
}

Hit cast(const Sphere& sphere, const Vec3& o, const Vec3& d, Real maxFraction) {
  const Real t = sphereEntry(o, d, sphere.radius);
  if (t < 0 || t > maxFraction) return std::nullopt;
  const Vec3 x = o + t * d;
  return LocalHit{t, normalizedOr(x, normalizedOr(-d, Vec3::UnitY()))};
}

// The capsule is the union of two balls and a finite cylinder; from an origin outside all
// three, the first entry into the union is the earliest entry into one of them, and the
// cylinder's flat caps lie inside the balls, so only its side needs testing.
Hit cast(const Capsule& capsule, const Vec3& o, const Vec3& d, Real maxFraction) {
  const Real r = capsule.radius, h = capsule.halfHeight;
  const Vec3 axisPoint(0, std::clamp(o.y(), -h, h), 0);
  if ((o - axisPoint).squaredNorm() < r * r) return std::nullopt;  // starts inside
  Real best = kInfinity;
  Vec3 normal = Vec3::UnitY();
  const Real a = d.x() * d.x() + d.z() * d.z();
  if (a > 0) {
    const Real b = o.x() * d.x() + o.z() * d.z();
    const Real len = std::sqrt(o.x() * o.x() + o.z() * o.z());
    const Real c = (len - r) * (len + r);
    if (c >= 0 && b < 0) {
      const Real lx = o.x() - (b / a) * d.x(), lz = o.z() - (b / a) * d.z();
      const Real disc = r * r - (lx * lx + lz * lz);
      if (disc >= 0) {
        const Real t = c / (-b + std::sqrt(a * disc));
        const Vec3 x = o + t * d;
        if (std::abs(x.y()) <= h) {
          best = t;
          normal = normalizedOr(Vec3(x.x(), 0, x.z()), Vec3::UnitX());
        }
      }
    }
  }
  for (const Real cy : {h, -h}) {
    const Vec3 c(0, cy, 0);
    const Real t = sphereEntry(o - c, d, r);
    if (t >= 0 && t < best) {
      best = t;
      normal = normalizedOr(o + t * d - c, Vec3(0, cy > 0 ? 1 : -1, 0));
    }
  }
  if (best > maxFraction) return std::nullopt;
  return LocalHit{best, normal};
}

// Kay-Kajiya slabs. Divisions (not multiplications by 1/d) so that a zero gap over a tiny
// direction component gives 0, never 0 * inf.
Hit cast(const Box& box, const Vec3& o, const Vec3& d, Real maxFraction) {
  Real enter = -kInfinity, exit = kInfinity;
  int axis = -1;
  for (int i = 0; i < 3; ++i) {
    const Real h = box.halfExtents[i];
    if (d[i] == 0) {
      if (std::abs(o[i]) > h) return std::nullopt;
      continue;
    }
    const Real t1 = (-h - o[i]) / d[i], t2 = (h - o[i]) / d[i];
    const Real tNear = std::min(t1, t2), tFar = std::max(t1, t2);
    if (tNear > enter) {
      enter = tNear;
      axis = i;
    }
    exit = std::min(exit, tFar);
  }
  if (axis < 0 || enter > exit || enter < 0 || enter > maxFraction) return std::nullopt;
  Vec3 n = Vec3::Zero();
  n[axis] = d[axis] > 0 ? Real(-1) : Real(1);
  return LocalHit{enter, n};
}

// The slab |y| <= h intersected with the infinite cylinder x^2 + z^2 <= r^2.
Hit cast(const Cylinder& cyl, const Vec3& o, const Vec3& d, Real maxFraction) {
  const Real r = cyl.radius, h = cyl.halfHeight;
  Real enter = -kInfinity, exit = kInfinity;
  bool capEntry = false;
  if (d.y() == 0) {
    if (std::abs(o.y()) > h) return std::nullopt;
  } else {
    const Real t1 = (-h - o.y()) / d.y(), t2 = (h - o.y()) / d.y();
    enter = std::min(t1, t2);
    exit = std::max(t1, t2);
    capEntry = true;
  }
  const Real a = d.x() * d.x() + d.z() * d.z();
  const Real len = std::sqrt(o.x() * o.x() + o.z() * o.z());
  const Real c = (len - r) * (len + r);
  if (a == 0) {
    if (c > 0) return std::nullopt;
  } else {
    const Real b = o.x() * d.x() + o.z() * d.z();
    const Real lx = o.x() - (b / a) * d.x(), lz = o.z() - (b / a) * d.z();
    const Real disc = r * r - (lx * lx + lz * lz);
    if (disc < 0) return std::nullopt;
    // Stable roots of a t^2 + 2 b t + c: q = -(b + sign(b) sqrt(a disc)), t = q / a and c / q.
    const Real q = -(b + std::copysign(std::sqrt(a * disc), b));
    Real t0 = q / a, t1 = q != 0 ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > enter) {
      enter = t0;
      capEntry = false;
    }
    exit = std::min(exit, t1);
  }
  if (enter > exit || enter < 0 || enter > maxFraction) return std::nullopt;
  if (capEntry) return LocalHit{enter, Vec3(0, d.y() > 0 ? Real(-1) : Real(1), 0)};
  const Vec3 x = o + enter * d;
  return LocalHit{enter, normalizedOr(Vec3(x.x(), 0, x.z()), Vec3::UnitX())};
}

// Cyrus-Beck clipping of the line against every face plane; the entry face gives the normal.
Hit cast(const ConvexHull& hull, const Vec3& o, const Vec3& d, Real maxFraction) {
  Real enter = -kInfinity, exit = kInfinity;
  std::size_t enterFace = 0;
  bool entered = false;
  const auto& faces = hull.faces();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Real dist = faces[f].normal.dot(o) - faces[f].offset;
    const Real rate = faces[f].normal.dot(d);
    if (rate == 0) {
      if (dist > 0) return std::nullopt;
      continue;
    }
    const Real t = -dist / rate;
    if (rate < 0) {
      if (t > enter) {
        enter = t;
        enterFace = f;
        entered = true;
      }
    } else {
      exit = std::min(exit, t);
    }
    if (enter > exit) return std::nullopt;
  }
  if (!entered || enter < 0 || enter > maxFraction) return std::nullopt;
  return LocalHit{enter, faces[enterFace].normal};
}

Hit cast(const MeshBvh& bvh, const Vec3& o, const Vec3& d, Real maxFraction) {
  const auto hit = bvh.castRay(o, d, maxFraction);
  if (!hit) return std::nullopt;
  return LocalHit{hit->fraction, hit->normal};
}

// A 2D DDA (Amanatides and Woo 1987) over the cells the ray's xz projection crosses, inside
// the field's bounding box; each cell's two triangles are tested, and the walk stops once the
// best hit lies before the current cell's exit.
Hit cast(const HeightField& field, const Vec3& o, const Vec3& d, Real maxFraction) {
  const Real s = field.spacing();
  const std::size_t cols = field.cols() - 1, rows = field.rows() - 1;  // cell counts
  const Vec3 lo(0, field.minHeight(), 0);
  const Vec3 hi(Real(cols) * s, field.maxHeight(), Real(rows) * s);
  // Clip to the box grown by a few ulps (a flat field has a box of zero height).
  const Real scale = std::max({hi.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff(), s});
  const Real pad = 16 * std::numeric_limits<Real>::epsilon() * scale;
  Real t0 = 0, t1 = maxFraction;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (o[i] < lo[i] - pad || o[i] > hi[i] + pad) return std::nullopt;
      continue;
    }
    Real a = (lo[i] - pad - o[i]) / d[i], b = (hi[i] + pad - o[i]) / d[i];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return std::nullopt;
  }
  const auto cellOf = [s](Real x, std::size_t cells) -> std::size_t {
    const Real f = std::floor(x / s);
    return f <= 0 ? 0 : f >= Real(cells - 1) ? cells - 1 : std::size_t(f);
  };
  const Vec3 start = o + t0 * d;
  std::size_t j = cellOf(start.x(), cols), i = cellOf(start.z(), rows);
  // s at which the ray crosses the next cell boundary along x (column) or z (row).
  const auto nextCrossing = [&](int axis, std::size_t cell) -> Real {
    if (d[axis] == 0) return kInfinity;
    const Real boundary = Real(cell + (d[axis] > 0 ? 1 : 0)) * s;
    return (boundary - o[axis]) / d[axis];
  };
  Real best = maxFraction;
  bool found = false;
  Vec3 normal = Vec3::UnitY();
  for (std::size_t steps = 0; steps <= rows + cols + 2; ++steps) {
    for (const auto& t : field.cellTriangles(i, j)) {
      const Real hit = intersectRayTriangle(o, d, best, t[0], t[1], t[2]);
      if (hit >= 0 && (!found || hit < best)) {
        best = hit;
        found = true;
        normal = normalizedOr((t[1] - t[0]).cross(t[2] - t[0]), Vec3::UnitY());
      }
    }
    const Real tx = nextCrossing(0, j), tz = nextCrossing(2, i);
    const Real cellExit = std::min(tx, tz);
    if ((found && best <= cellExit) || cellExit > t1) break;
    if (tx < tz) {
      if (d.x() > 0 ? j + 1 >= cols : j == 0) break;
      j = d.x() > 0 ? j + 1 : j - 1;
    } else {
      if (d.z() > 0 ? i + 1 >= rows : i == 0) break;
      i = d.z() > 0 ? i + 1 : i - 1;
    }
  }
  if (!found) return std::nullopt;
  if (normal.dot(d) > 0) normal = -normal;
  return LocalHit{best, normal};
}

// Nearest child hit; none when the origin is strictly inside a solid child (primitives,
// hulls, planes, nested compounds; mesh and height-field children are surfaces for rays).
bool insideSolid(const Collider& collider, const Vec3& p) {
  switch (collider.type()) {
    case ShapeType::Mesh:
    case ShapeType::HeightField:
      return false;
    case ShapeType::Compound: {
      const auto& children = collider.children();
      const auto& xfs = collider.shape().getIf<Compound>()->children();
      for (std::size_t k = 0; k < children.size(); ++k)
        if (insideSolid(children[k], xfs[k].transform.applyInverse(p))) return true;
      return false;
    }
    default:
      return detail::queryPointLocal(collider, p).distance < 0;
  }
}

Hit cast(const Collider& collider, const Compound& compound, const Vec3& o, const Vec3& d,
         Real maxFraction) {
  if (insideSolid(collider, o)) return std::nullopt;
  Hit best;
  Real limit = maxFraction;
  const auto& children = collider.children();
  for (std::size_t k = 0; k < children.size(); ++k) {
    const Transform& xf = compound.children()[k].transform;
    const Hit h =
        detail::castRayLocal(children[k], xf.applyInverse(o), xf.q.conjugate() * d, limit);
    if (h && (!best || h->fraction < best->fraction)) {
      best = LocalHit{h->fraction, xf.rotate(h->normal)};
      limit = h->fraction;
    }
  }
  return best;
}

Hit castShape(const Collider& collider, const Vec3& o, const Vec3& d, Real maxFraction) {
  const Shape& shape = collider.shape();
  switch (shape.type()) {
    case ShapeType::Plane:
      return cast(*shape.getIf<Plane>(), o, d, maxFraction);
    case ShapeType::Sphere:
      return cast(*shape.getIf<Sphere>(), o, d, maxFraction);
    case ShapeType::Capsule:
      return cast(*shape.getIf<Capsule>(), o, d, maxFraction);
    case ShapeType::Box:
      return cast(*shape.getIf<Box>(), o, d, maxFraction);
    case ShapeType::Cylinder:
      return cast(*shape.getIf<Cylinder>(), o, d, maxFraction);
    case ShapeType::Hull:
      return cast(*shape.getIf<ConvexHull>(), o, d, maxFraction);
    case ShapeType::Mesh:
      return cast(*collider.meshBvh(), o, d, maxFraction);
    case ShapeType::HeightField:
      return cast(*shape.getIf<HeightField>(), o, d, maxFraction);
    case ShapeType::Compound:
      return cast(collider, *shape.getIf<Compound>(), o, d, maxFraction);
  }
  return std::nullopt;
}

}  // namespace

namespace detail {

// A ray whose squares overflow Real (an origin or a direction past about 1e19 m in float) makes
// the casts' roots NaN, which their range tests let through: such a ray reports no hit rather
// than a NaN one (the world fuzz target's: a deformable's vertex swept against a body thrown to
// 1e22 m/s).
std::optional<LocalHit> castRayLocal(const Collider& collider, const Vec3& o, const Vec3& d,
                                     Real maxFraction) {
  const Hit hit = castShape(collider, o, d, maxFraction);
  if (hit && !(hit->fraction >= 0 && hit->fraction <= maxFraction)) return std::nullopt;
  return hit;
}

}  // namespace detail

std::optional<RayHit> castRay(const Collider& collider, const Transform& pose, const Ray& ray) {
  if (ray.direction.squaredNorm() == 0 || !(ray.maxFraction >= 0)) return std::nullopt;
  const auto hit = detail::castRayLocal(collider, pose.applyInverse(ray.origin),
                                        pose.q.conjugate() * ray.direction, ray.maxFraction);
  if (!hit) return std::nullopt;
  const Real s = hit->fraction + Real(0);  // turns a -0 from the slab tests into +0
  return RayHit{s, ray.origin + s * ray.direction, pose.rotate(hit->normal)};
}

}  // namespace inertia
