// Bounds of shapes: tight world boxes from the rotated support function (h(e_i) = max e_i . x).
#include "inertia/geometry/bounds.h"

#include <cmath>
#include <limits>
#include <type_traits>

#include "inertia/geometry/shapes.h"

namespace inertia {
namespace {

Aabb everything() { return {Vec3::Constant(-kInfinity), Vec3::Constant(kInfinity)}; }

bool allFiniteBox(const Aabb& box) { return box.lower.allFinite() && box.upper.allFinite(); }

}  // namespace

Aabb transformAabb(const Aabb& box, const Transform& xf) {
  if (!box.isValid()) return Aabb::empty();
  // |R| h is NaN for infinite h (0 * inf); an unbounded box stays unbounded.
  if (!allFiniteBox(box)) return everything();
  const Mat3 r = xf.q.toRotationMatrix();
  return Aabb::fromCenterHalfExtents(xf.apply(box.center()), r.cwiseAbs() * box.halfExtents());
}

// The half-space n.x <= d is bounded only along an axis it is exactly aligned with.
Aabb worldBounds(const Plane& plane, const Transform& xf) {
  const Vec3 n = xf.rotate(plane.normal);
  const Real d = plane.offset + n.dot(xf.p);
  Aabb out = everything();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    if (n[j] != 0 || n[k] != 0 || n[i] == 0) continue;
    if (n[i] > 0)
      out.upper[i] = d / n[i];
    else
      out.lower[i] = d / n[i];
  }
  return out;
}

Aabb worldBounds(const Sphere& sphere, const Transform& xf) {
  return Aabb::fromCenterHalfExtents(xf.p, Vec3::Constant(sphere.radius));
}

// The segment's extent along world axis i is halfHeight |u_i| (u the world axis), plus r.
Aabb worldBounds(const Capsule& capsule, const Transform& xf) {
  const Vec3 u = xf.rotate(Vec3::UnitY());
  return Aabb::fromCenterHalfExtents(
      xf.p, capsule.halfHeight * u.cwiseAbs() + Vec3::Constant(capsule.radius));
}

// Arvo's |R| h: the support of a box along world axis i is sum_j |R_ij| h_j.
Aabb worldBounds(const Box& box, const Transform& xf) {
  const Mat3 r = xf.q.toRotationMatrix();
  return Aabb::fromCenterHalfExtents(xf.p, r.cwiseAbs() * box.halfExtents);
}

// Support of a disc of radius r with unit normal u along e_i is r sqrt(1 - u_i^2); the two cap
// discs are at +-halfHeight u, so the extent is halfHeight |u_i| + r sqrt(1 - u_i^2).
Aabb worldBounds(const Cylinder& cylinder, const Transform& xf) {
  const Vec3 u = xf.rotate(Vec3::UnitY());
  Vec3 e;
  for (int i = 0; i < 3; ++i)
    e[i] = cylinder.halfHeight * std::abs(u[i]) +
           cylinder.radius * std::sqrt(std::max(Real(0), Real(1) - u[i] * u[i]));
  return Aabb::fromCenterHalfExtents(xf.p, e);
}

// Exact: the box of the transformed vertices.
Aabb worldBounds(const ConvexHull& hull, const Transform& xf) {
  const Mat3 r = xf.q.toRotationMatrix();
  Aabb out;
  for (const Vec3& v : hull.vertices()) out.extend(r * v);
  out.lower += xf.p;
  out.upper += xf.p;
  return out;
}

Aabb worldBounds(const TriangleMesh& mesh, const Transform& xf) {
  return transformAabb(mesh.bounds(), xf);
}

Aabb worldBounds(const HeightField& field, const Transform& xf) {
  const Aabb local{Vec3(0, field.minHeight(), 0),
                   Vec3(Real(field.cols() - 1) * field.spacing(), field.maxHeight(),
                        Real(field.rows() - 1) * field.spacing())};
  return transformAabb(local, xf);
}

Aabb worldBounds(const Compound& compound, const Transform& xf) {
  Aabb out;
  for (const CompoundChild& child : compound.children())
    out.merge(worldBounds(child.shape, xf * child.transform));
  return out;
}

Aabb worldBounds(const Shape& shape, const Transform& xf) {
  return shape.visit([&](const auto& s) { return worldBounds(s, xf); });
}

Aabb localBounds(const Shape& shape) { return worldBounds(shape, Transform::identity()); }

}  // namespace inertia
