// Shared helpers for the collision tests: random poses, meshes, and double-precision oracles.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "inertia/collision/contact.h"
#include "inertia/collision/queries.h"
#include "inertia/core/types.h"
#include "inertia/geometry/geometry.h"
#include "../draws.h"

namespace inertia::test {

using Vec3d = Eigen::Vector3d;
/// Machine epsilon of Real: float-build tolerances scale with it.
constexpr double kEps = std::numeric_limits<Real>::epsilon();

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
inline Transform randomPose(std::mt19937_64& rng, double spread = 2) {
  return {randomVec(rng, -spread, spread), randomRotation(rng)};
}
/// The hull of n random points in a box of half size `size` stretched by 0.3..1 per axis.
inline ConvexHull randomHull(std::mt19937_64& rng, int n, double size) {
  std::vector<Vec3> pts;
  const Vec3 stretch = randomVec(rng, 0.3, 1.0);
  for (int i = 0; i < n; ++i)
    pts.push_back(Real(size) * randomVec(rng, -1, 1).cwiseProduct(stretch));
  return ConvexHull(pts);
}
/// A random box: centre in [-extent, extent]^3, half extents in [0.05, maxHalf].
inline Aabb randomAabb(std::mt19937& rng, Real extent, Real maxHalf) {
  std::uniform_real_distribution<Real> c(-extent, extent), h(Real(0.05), maxHalf);
  // GCC evaluated the second argument first.
  const Vec3 half = draw3<Vec3>([&] { return h(rng); });
  return Aabb::fromCenterHalfExtents(draw3<Vec3>([&] { return c(rng); }), half);
}
/// The eight corners of the box of half extents h, centred on the origin.
inline std::vector<Vec3> boxCorners(const Vec3& h) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  return v;
}
/// The pose at (x, y, z) turned by q.
inline Transform at(double x, double y, double z, const Quat& q = Quat::Identity()) {
  return {Vec3(Real(x), Real(y), Real(z)), q};
}
/// The rotation by `angle` (rad) about `axis` (normalised here).
inline Quat axisAngle(double angle, const Vec3& axis) {
  return Quat(Eigen::AngleAxis<Real>(Real(angle), axis.normalized()));
}
/// Every manifold collide() makes for the pair, with speculative distance `spec`.
inline std::vector<ContactManifold> collideAll(const Collider& a, const Transform& pa,
                                               const Collider& b, const Transform& pb,
                                               Real spec = 0) {
  std::vector<ContactManifold> out;
  collide(a, pa, b, pb, ContactSettings{.speculativeDistance = spec}, out);
  return out;
}
/// Contact points and separations: coordinates of a few metres pass through a handful of
/// transforms (each a few ulps) and the clipping interpolation: 200 ulps of a 4 m coordinate,
/// ~1e-4 m in float, ~2e-13 m in double.
constexpr double kContactTol = 200 * kEps * 4;

inline Vec3d toD(const Vec3& v) { return v.cast<double>(); }
/// World -> local in double, from the (Real) pose.
inline Vec3d toLocal(const Transform& pose, const Vec3& x) {
  return pose.q.cast<double>().conjugate() * (toD(x) - toD(pose.p));
}
inline Vec3d rotateD(const Transform& pose, const Vec3d& v) { return pose.q.cast<double>() * v; }

/// A signed distance and its gradient (unit outward direction), double precision.
struct Sdf {
  double distance;
  Vec3d gradient;
};

// Exact signed distances of the primitives in their local frames (Quilez' formulas), written
// independently of the library, in double.
inline Sdf sdf(const Sphere& s, const Vec3d& p) {
  const double n = p.norm();
  return {n - s.radius, n > 0 ? Vec3d(p / n) : Vec3d::UnitY()};
}
inline Sdf sdf(const Capsule& c, const Vec3d& p) {
  const double h = c.halfHeight;
  const Vec3d q(0, std::clamp(p.y(), -h, h), 0);
  const double n = (p - q).norm();
  return {n - c.radius, n > 0 ? Vec3d((p - q) / n) : Vec3d::UnitX()};
}
inline Sdf sdf(const Box& b, const Vec3d& p) {
  const Vec3d h = toD(b.halfExtents);
  const Vec3d e = p.cwiseAbs() - h;
  const Vec3d sign(p.x() >= 0 ? 1 : -1, p.y() >= 0 ? 1 : -1, p.z() >= 0 ? 1 : -1);
  const Vec3d out = e.cwiseMax(0.0);
  if (out.squaredNorm() > 0) {
    const double n = out.norm();
    return {n, out.cwiseProduct(sign) / n};
  }
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (e[i] > e[axis]) axis = i;
  Vec3d g = Vec3d::Zero();
  g[axis] = sign[axis];
  return {e[axis], g};
}
inline Sdf sdf(const Cylinder& c, const Vec3d& p) {
  const double rho = std::hypot(p.x(), p.z());
  const Vec3d u = rho > 0 ? Vec3d(p.x() / rho, 0, p.z() / rho) : Vec3d::UnitX();
  const double er = rho - c.radius, ey = std::abs(p.y()) - c.halfHeight;
  const Vec3d up(0, p.y() >= 0 ? 1 : -1, 0);
  if (er > 0 || ey > 0) {
    const double a = std::max(er, 0.0), b = std::max(ey, 0.0);
    const double n = std::hypot(a, b);
    return {n, (a * u + b * up) / n};
  }
  return er > ey ? Sdf{er, u} : Sdf{ey, up};
}

/// The first entry of the ray into the solid by sphere tracing the exact SDF in double
/// (Hart 1996): -1 for a miss, -2 when the origin is inside, -3 when tracing did not settle
/// (grazing rays creep along the surface; such rays are skipped by the callers).
template <class S>
double traceRay(const S& shape, const Vec3d& o, const Vec3d& d, double maxFraction) {
  const double len = d.norm();
  double t = 0;
  if (sdf(shape, o).distance < 0) return -2;
  for (int it = 0; it < 100000; ++it) {
    const double dist = sdf(shape, o + t * d).distance;
    if (dist < 1e-13) return t;
    t += dist / len;
    if (t > maxFraction) return -1;
  }
  return -3;
}

/// The closed mesh of a box: 8 corners, 12 triangles, counter-clockwise from outside.
inline TriangleMesh boxMesh(const Vec3& h) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Each face as a quad (a, b, c, d) counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  std::vector<Triangle> t;
  for (const auto& q : quads) {
    t.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    t.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return TriangleMesh(std::move(v), std::move(t));
}

/// A closed UV sphere of radius r (outward normals): a closed mesh that is not convex-trivial.
inline TriangleMesh sphereMesh(double r, int stacks, int slices, double wobble = 0,
                               std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3> v;
  v.emplace_back(0, Real(r), 0);
  for (int i = 1; i < stacks; ++i) {
    const double th = M_PI * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double ph = 2 * M_PI * j / slices;
      const double rr = r * (1 + wobble * uniform(rng, -1, 1));
      v.emplace_back(Real(rr * std::sin(th) * std::cos(ph)), Real(rr * std::cos(th)),
                     Real(rr * std::sin(th) * std::sin(ph)));
    }
  }
  v.emplace_back(0, Real(-r), 0);
  const auto idx = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * slices + (j % slices)); };
  const std::uint32_t bottom = std::uint32_t(v.size() - 1);
  std::vector<Triangle> t;
  for (int j = 0; j < slices; ++j) t.push_back({0, idx(1, j + 1), idx(1, j)});
  for (int i = 1; i < stacks - 1; ++i)
    for (int j = 0; j < slices; ++j) {
      t.push_back({idx(i, j), idx(i, j + 1), idx(i + 1, j + 1)});
      t.push_back({idx(i, j), idx(i + 1, j + 1), idx(i + 1, j)});
    }
  for (int j = 0; j < slices; ++j)
    t.push_back({idx(stacks - 1, j), idx(stacks - 1, j + 1), bottom});
  return TriangleMesh(std::move(v), std::move(t));
}

/// A random soup of n triangles of size ~`size` in the cube [-extent, extent]^3 (open mesh).
inline TriangleMesh randomSoup(std::mt19937_64& rng, int n, double extent, double size) {
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  for (int k = 0; k < n; ++k) {
    const Vec3 c = randomVec(rng, -extent, extent);
    for (int i = 0; i < 3; ++i) v.push_back(c + randomVec(rng, -size, size));
    const std::uint32_t b = std::uint32_t(3 * k);
    t.push_back({b, b + 1, b + 2});
  }
  return TriangleMesh(std::move(v), std::move(t));
}

/// Closest points of the segments p0p1 and q0q1 (Ericson 5.1.9, clamped), in double: the
/// squared distance. A segment may be a point.
inline double segmentDistance2(const Vec3d& p0, const Vec3d& p1, const Vec3d& q0,
                               const Vec3d& q1) {
  const Vec3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 1e-300 && e <= 1e-300) return r.squaredNorm();
  if (a <= 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), den = a * e - b * b;
      s = den > 0 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0)
        t = 0, s = std::clamp(-c / a, 0.0, 1.0);
      else if (t > 1)
        t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  return (p0 + s * d1 - (q0 + t * d2)).squaredNorm();
}

using TriangleD = std::array<Vec3d, 3>;

/// The gap between two triangles (double) over all 17 separating axes of a triangle pair:
/// exact for triangles (positive: apart by at least that; <= 0: they intersect).
inline double triangleGap(const TriangleD& a, const TriangleD& b) {
  double best = -1e300;
  const auto test = [&](const Vec3d& axis) {
    if (axis.norm() < 1e-12) return;
    const Vec3d u = axis.normalized();
    double minA = 1e300, maxA = -1e300, minB = 1e300, maxB = -1e300;
    for (std::size_t k = 0; k < 3; ++k) {
      minA = std::min(minA, u.dot(a[k])), maxA = std::max(maxA, u.dot(a[k]));
      minB = std::min(minB, u.dot(b[k])), maxB = std::max(maxB, u.dot(b[k]));
    }
    best = std::max(best, std::max(minB - maxA, minA - maxB));
  };
  const Vec3d na = (a[1] - a[0]).cross(a[2] - a[0]), nb = (b[1] - b[0]).cross(b[2] - b[0]);
  test(na);
  test(nb);
  for (std::size_t i = 0; i < 3; ++i) {
    const Vec3d ea = a[(i + 1) % 3] - a[i], eb = b[(i + 1) % 3] - b[i];
    test(na.cross(ea));
    test(nb.cross(eb));
    for (std::size_t j = 0; j < 3; ++j) test(ea.cross(b[(j + 1) % 3] - b[j]));
  }
  return best;
}

}  // namespace inertia::test
