// Test oracle: brute-force checks that deformables do not pass through themselves or each
// other, independent of the self-collision stage's own continuous tests.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "inertia/collision/triangle.h"
#include "inertia/deformable/deformable.h"

namespace inertia::test {

using Eigen::Vector3d;

// Does vertex p cross triangle (a, b, c) while all move linearly over the step (positions at
// the start s and end e)? Independently of collision/continuous_triangle: the coplanarity
// function f(t) = (b - a) x (c - a) . (p - a) sampled at 64 times, each sign change refined
// by bisection, the crossing point then tested inside the triangle (barycentric >= -1e-6).
// A tangency that does not change sign is not a crossing.
inline bool crosses(const Vector3d* s, const Vector3d* e) {
  const auto at = [&](double t, int k) -> Vector3d { return (1 - t) * s[k] + t * e[k]; };
  const auto f = [&](double t) {
    const Vector3d p = at(t, 0), a = at(t, 1), b = at(t, 2), c = at(t, 3);
    return (b - a).cross(c - a).dot(p - a);
  };
  const int samples = 64;
  double t0 = 0, f0 = f(0);
  for (int k = 1; k <= samples; ++k) {
    const double t1 = double(k) / samples, f1 = f(t1);
    if ((f0 < 0 && f1 > 0) || (f0 > 0 && f1 < 0)) {
      double lo = t0, hi = t1, flo = f0;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi), fm = f(mid);
        if ((fm < 0) == (flo < 0))
          lo = mid, flo = fm;
        else
          hi = mid;
      }
      const double t = 0.5 * (lo + hi);
      const Vector3d p = at(t, 0), a = at(t, 1), b = at(t, 2), c = at(t, 3);
      const Vector3d n = (b - a).cross(c - a);
      const double area = n.squaredNorm();
      if (area > 0) {
        const double u = (c - b).cross(p - b).dot(n) / area, v = (a - c).cross(p - c).dot(n) / area;
        if (u >= -1e-6 && v >= -1e-6 && 1 - u - v >= -1e-6) return true;
      }
    }
    t0 = t1, f0 = f1;
  }
  return false;
}

struct Crossings {
  int vertexTriangle = 0, edgeTriangle = 0;
};

inline std::vector<Vector3d> positions(const Deformable& d) {
  std::vector<Vector3d> x(d.vertexCount());
  for (std::size_t i = 0; i < d.vertexCount(); ++i) x[i] = d.position(i).cast<double>();
  return x;
}

// Brute force over all pairs of vertices of `p` and triangles of `q` (non-incident when they
// are the same deformable): vertices crossing triangles between the two states, and edges of
// p's triangles piercing q's triangles at the end state (Moller-Trumbore).
inline Crossings countCrossings(const Deformable& p, const std::vector<Vector3d>& pBefore,
                                const Deformable& q, const std::vector<Vector3d>& qBefore) {
  Crossings c;
  const bool same = &p == &q;
  const std::vector<Vector3d> pNow = positions(p), qNow = positions(q);
  // Each point's swept box: two features whose boxes are apart cannot meet (an exact filter).
  const auto boxes = [](const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
    std::vector<Eigen::AlignedBox3d> box(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) box[i] = Eigen::AlignedBox3d(a[i]).extend(b[i]);
    return box;
  };
  const auto pBox = boxes(pBefore, pNow), qBox = boxes(qBefore, qNow);
  const auto incident = [&](const std::array<std::uint32_t, 3>& t, std::size_t i) {
    return same && (t[0] == i || t[1] == i || t[2] == i);
  };
  for (std::size_t i = 0; i < p.vertexCount(); ++i)
    for (const auto& t : q.triangles()) {
      if (incident(t, i)) continue;
      if (!pBox[i].intersects(qBox[t[0]].merged(qBox[t[1]]).merged(qBox[t[2]]))) continue;
      const Vector3d s[] = {pBefore[i], qBefore[t[0]], qBefore[t[1]], qBefore[t[2]]};
      const Vector3d e[] = {pNow[i], qNow[t[0]], qNow[t[1]], qNow[t[2]]};
      c.vertexTriangle += crosses(s, e);
    }
  for (const auto& u : p.triangles())
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = u[std::size_t(k)], b = u[std::size_t((k + 1) % 3)];
      for (const auto& t : q.triangles()) {
        if (incident(t, a) || incident(t, b)) continue;
        const Vec3 origin = p.position(a), direction = p.position(b) - p.position(a);
        c.edgeTriangle += intersectRayTriangle(origin, direction, 1, q.position(t[0]),
                                               q.position(t[1]), q.position(t[2])) >= 0;
      }
    }
  return c;
}

}  // namespace inertia::test
