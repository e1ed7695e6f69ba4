// GJK ray casting against the Minkowski difference (van den Bergen 2004), with the rounding
// radii handled as in Box2D's b2ShapeCast: a translated convex shape against a fixed one.
#include <cmath>
#include <limits>

#include "gjk.h"
#include "local_queries.h"

namespace inertia::detail {

// A moved by lambda * r touches B when the point x = -lambda * r comes within R = rA + rB of
// D = A - B (the cores). March x along the ray: each support plane of D that keeps x more than
// R away moves x up to that plane (the shapes cannot touch before), until x is within
// `tolerance` of R from the GJK simplex's closest point of D.
std::optional<CastResult> shapeCast(const ConvexProxy& a, const Vec3& r, const ConvexProxy& b,
                                    Real tolerance) {
  const Real radii = a.radius + b.radius;
  Simplex s;  // points p_i = a_i - b_i of D (w holds p_i)
  Real lambda = 0;
  Vec3 x = Vec3::Zero();
  Vec3 n = Vec3::Zero();
  Vec3 v = x - (a.centre() - b.centre());
  if (!(v.squaredNorm() > 0)) v = normalizedOr(-r, Vec3::UnitX());

  CastResult out;
  while (out.iterations < kGjkMaxIterations) {
    const Real vLen = v.norm();
    if (vLen - radii <= tolerance) break;
    ++out.iterations;
    SimplexVertex p;
    p.a = a.support(v);
    p.b = b.support(-v);
    p.w = p.a - p.b;
    const Real vw = v.dot(x - p.w);
    bool advanced = false;
    if (vw > radii * vLen) {
      // x lies beyond the support plane grown by R: move it onto that plane, or miss.
      const Real vr = -v.dot(r);
      if (!(vr < 0)) return std::nullopt;
      const Real next = lambda + (radii * vLen - vw) / vr;
      if (!(next <= 1)) return std::nullopt;
      lambda = next;
      x = -lambda * r;
      n = v;
      advanced = true;
    }
    bool repeated = false;
    for (int i = 0; i < s.count; ++i) repeated = repeated || s.v[i].w == p.w;
    if (repeated && !advanced) break;  // no new information: converged as far as rounding lets
    if (!repeated) s.v[s.count++] = p;
    // The point of conv{x - p_i} nearest the origin is x minus the point of conv{p_i} nearest x.
    Simplex shifted = s;
    for (int i = 0; i < s.count; ++i) shifted.v[i].w = x - s.v[i].w;
    v = closestToOrigin(shifted);
    s = shifted;
    for (int i = 0; i < s.count; ++i) s.v[i].w = s.v[i].a - s.v[i].b;
    if (s.count == 4) {
      v.setZero();  // x inside the cores' difference: the cores overlap here
    }
  }

  out.fraction = lambda;
  // The normal and points from a fresh GJK at the hit pose: the cast's own simplex stops as soon
  // as it certifies the gap, before it has settled on the closest features.
  ConvexProxy moved = a;
  const Vec3 shift = lambda * r;
  for (Vec3& q : moved.points) q += shift;
  moved.position += shift;
  const ConvexSeparation sep = separation(moved, b, n);
  out.normal = sep.normal;
  out.pointA = sep.pointA;
  out.pointB = sep.pointB;
  // Touching cores leave the GJK normal to rounding; the last support plane's normal is the
  // robust choice there (Box2D's).
  const Real scale = (moved.centre() - b.centre()).norm() + radii + 1;
  if (lambda > 0 && !(sep.distance + radii > 64 * std::numeric_limits<Real>::epsilon() * scale))
    out.normal = normalizedOr(n, out.normal);
  return out;
}

}  // namespace inertia::detail
