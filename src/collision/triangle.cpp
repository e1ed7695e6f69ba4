// Closest point on a triangle (Ericson 5.1.5) and the two-sided Moller-Trumbore ray test.
#include "inertia/collision/triangle.h"

#include <algorithm>
#include <limits>

namespace inertia {

namespace {

// Closest point of segment [a, b] to p: a + t (b - a), t clamped to [0, 1].
Vec3 closestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b, Real* tOut) {
  const Vec3 ab = b - a;
  const Real len2 = ab.squaredNorm();
  Real t = len2 > 0 ? (p - a).dot(ab) / len2 : Real(0);
  t = std::clamp(t, Real(0), Real(1));
  *tOut = t;
  return a + t * ab;
}

// A sliver that defeats the region tests: the closest of its three edges.
TriangleClosest closestOnEdges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3* v[3] = {&a, &b, &c};
  TriangleClosest best;
  Real bestD2 = std::numeric_limits<Real>::infinity();
  for (int k = 0; k < 3; ++k) {
    Real t;
    const Vec3 q = closestOnSegment(p, *v[k], *v[(k + 1) % 3], &t);
    const Real d2 = (p - q).squaredNorm();
    if (d2 < bestD2) {
      bestD2 = d2;
      best.point = q;
      best.feature = t <= 0   ? TriangleFeature(k)
                     : t >= 1 ? TriangleFeature((k + 1) % 3)
                              : TriangleFeature(3 + k);
    }
  }
  return best;
}

}  // namespace

TriangleClosest closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5: test the vertex regions, then the edge
  // regions, with the barycentric numerators d1..d6; the remaining region is the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, TriangleFeature::Vertex0};
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, TriangleFeature::Vertex1};
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const Real den = d1 - d3;  // >= d1 >= 0
    const Real v = den > 0 ? std::min(d1 / den, Real(1)) : Real(0);
    return {a + v * ab, TriangleFeature::Edge0};
  }
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, TriangleFeature::Vertex2};
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const Real den = d2 - d6;
    const Real w = den > 0 ? std::min(d2 / den, Real(1)) : Real(0);
    return {a + w * ac, TriangleFeature::Edge2};
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const Real den = (d4 - d3) + (d5 - d6);
    const Real w = den > 0 ? std::min((d4 - d3) / den, Real(1)) : Real(0);
    return {b + w * (c - b), TriangleFeature::Edge1};
  }
  // Face region. In exact arithmetic va + vb + vc = |ab x ac|^2 > 0; rounding on slivers may
  // break that, then fall back to the edges.
  const Real sum = va + vb + vc;
  if (!(sum > 0) || va < 0 || vb < 0 || vc < 0) return closestOnEdges(p, a, b, c);
  const Real v = vb / sum, w = vc / sum;
  return {a + v * ab + w * ac, TriangleFeature::Face};
}

Real intersectRayTriangle(const Vec3& origin, const Vec3& direction, Real maxFraction,
                          const Vec3& a, const Vec3& b, const Vec3& c) {
  // Moller and Trumbore 1997, with the division by the determinant deferred: the barycentric
  // tests compare u, v, u + v against det, so a tiny det cannot produce inf or NaN.
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pv = direction.cross(e2);
  Real det = e1.dot(pv);
  if (det == 0) return Real(-1);
  const Vec3 s = origin - a;
  Real u = s.dot(pv);
  const Vec3 qv = s.cross(e1);
  Real v = direction.dot(qv);
  Real t = e2.dot(qv);
  if (det < 0) {  // two-sided: flip to a positive determinant
    det = -det;
    u = -u;
    v = -v;
    t = -t;
  }
  if (u < 0 || v < 0 || u + v > det) return Real(-1);
  if (t < 0 || t > maxFraction * det) return Real(-1);
  return std::min(t / det, maxFraction);
}

}  // namespace inertia
