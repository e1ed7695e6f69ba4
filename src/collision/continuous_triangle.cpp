// Continuous vertex-face and edge-edge tests by the coplanarity cubic (Provot 1997; Bridson,
// Fedkiw and Anderson 2002), roots isolated by the critical points and refined by safeguarded
// Newton; proximity by Ericson's closest points (Real-Time Collision Detection 5.1.5, 5.1.9).
#include "inertia/collision/continuous_triangle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

#include "inertia/core/error.h"

namespace inertia {

namespace {

using V = Eigen::Vector3d;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// A linear motion in double: x(t) = x + t d.
struct Moving {
  V x, d;
  V at(double t) const { return x + t * d; }
};

Moving inDouble(const LinearMotion& m) {
  const V s = m.start.cast<double>();
  return {s, m.end.cast<double>() - s};
}

Moving minus(const Moving& a, const Moving& b) { return {a.x - b.x, a.d - b.d}; }

// f(t) = (A(t) x B(t)) . C(t) with A, B, C moving linearly: the coplanarity function, its cubic
// coefficients for the critical points, direct evaluation for the roots (more accurate near a
// root than Horner on the expanded coefficients).
struct TripleProduct {
  Moving A, B, C;
  std::array<double, 4> k{};  // f(t) = k0 + k1 t + k2 t^2 + k3 t^3

  TripleProduct(const Moving& a, const Moving& b, const Moving& c) : A(a), B(b), C(c) {
    const V ab = A.x.cross(B.x);
    const V mixed = A.x.cross(B.d) + A.d.cross(B.x);
    const V dd = A.d.cross(B.d);
    k[0] = ab.dot(C.x);
    k[1] = mixed.dot(C.x) + ab.dot(C.d);
    k[2] = dd.dot(C.x) + mixed.dot(C.d);
    k[3] = dd.dot(C.d);
  }
  double operator()(double t) const { return A.at(t).cross(B.at(t)).dot(C.at(t)); }
  double derivative(double t) const { return k[1] + t * (2 * k[2] + t * 3 * k[3]); }
  // |A(t) x B(t)|: f / this is the signed distance of C's tip from the plane (or line pair).
  double normalLength(double t) const { return A.at(t).cross(B.at(t)).norm(); }
};

// Real roots of c0 + c1 t + c2 t^2 strictly inside (0, 1), ascending, appended to `out`.
// Stable form (Numerical Recipes 5.6): q = -(c1 + sign(c1) sqrt(disc)) / 2, roots q / c2 and
// c0 / q, so a vanishing c2 degrades to the linear root without cancellation.
template <std::size_t N>
int quadraticRootsInUnit(double c0, double c1, double c2, std::array<double, N>& out, int n) {
  double r[2];
  int m = 0;
  if (c2 == 0) {
    if (c1 != 0) r[m++] = -c0 / c1;
  } else {
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc >= 0) {
      const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
      r[m++] = q / c2;
      if (q != 0) r[m++] = c0 / q;
    }
  }
  if (m == 2 && r[1] < r[0]) std::swap(r[0], r[1]);
  for (int i = 0; i < m; ++i)
    if (r[i] > 0 && r[i] < 1 && std::isfinite(r[i]) && (n == 0 || r[i] > out[n - 1]))
      out[n++] = r[i];
  return n;
}

// A root of f in the bracket [lo, hi] (f(lo), f(hi) of opposite signs): Newton steps, replaced
// by bisection whenever they leave the bracket; the bracket shrinks every iteration. 100
// iterations bound the cost (bisection alone reaches double resolution of [0, 1] in ~55).
double refineRoot(const TripleProduct& f, double lo, double hi, double flo) {
  double t = 0.5 * (lo + hi);
  for (int it = 0; it < 100; ++it) {
    const double ft = f(t);
    if (ft == 0) return t;
    if ((ft < 0) == (flo < 0)) {
      lo = t;
      flo = ft;
    } else {
      hi = t;
    }
    if (hi - lo <= 4 * kEps * std::max(1.0, hi)) break;
    const double df = f.derivative(t);
    double next = df != 0 ? t - ft / df : lo - 1;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == t) break;
    t = next;
  }
  return t;
}

// Closest point of triangle (a, b, c) to p with barycentrics (Ericson 5.1.5); slivers that
// defeat the region tests fall back to the closest edge.
struct TriangleNearest {
  V point;
  V bary;
};

TriangleNearest closestOnSegment(const V& p, const V& a, const V& b) {
  const V ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return {a + t * ab, V(1 - t, t, 0)};
}

TriangleNearest closestOnTriangle(const V& p, const V& a, const V& b, const V& c) {
  const V ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, V(1, 0, 0)};
  const V bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, V(0, 1, 0)};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 - d3 > 0 ? std::min(d1 / (d1 - d3), 1.0) : 0.0;
    return {a + v * ab, V(1 - v, v, 0)};
  }
  const V cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, V(0, 0, 1)};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 - d6 > 0 ? std::min(d2 / (d2 - d6), 1.0) : 0.0;
    return {a + w * ac, V(1 - w, 0, w)};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    const double w = den > 0 ? std::min((d4 - d3) / den, 1.0) : 0.0;
    return {b + w * (c - b), V(0, 1 - w, w)};
  }
  const double sum = va + vb + vc;
  if (sum > 0 && va >= 0 && vb >= 0 && vc >= 0) {
    const double v = vb / sum, w = vc / sum;
    return {a + v * ab + w * ac, V(1 - v - w, v, w)};
  }
  TriangleNearest best = closestOnSegment(p, a, b);
  const TriangleNearest e1 = closestOnSegment(p, b, c), e2 = closestOnSegment(p, c, a);
  if ((p - e1.point).squaredNorm() < (p - best.point).squaredNorm())
    best = {e1.point, V(0, e1.bary[0], e1.bary[1])};
  if ((p - e2.point).squaredNorm() < (p - best.point).squaredNorm())
    best = {e2.point, V(e2.bary[1], 0, e2.bary[0])};
  return best;
}

// Closest points of segments p0 + s (p1 - p0) and q0 + u (q1 - q0), s, u in [0, 1]
// (Ericson 5.1.9), degenerate (point) segments and parallel segments included.
void closestSegmentSegment(const V& p0, const V& p1, const V& q0, const V& q1, double& s,
                           double& u) {
  const V d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= 0 && e <= 0) {
    s = u = 0;
    return;
  }
  if (a <= 0) {
    s = 0;
    u = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = d1.dot(r);
  if (e <= 0) {
    u = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = d1.dot(d2), denom = a * e - b * b;
  // Parallel (denom ~ 0 relative to a e): any s works; take s = 0 and clamp u from it.
  s = denom > kEps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  u = (b * s + f) / e;
  if (u < 0) {
    u = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (u > 1) {
    u = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

// Any unit vector perpendicular to v (v need not be unit; UnitY for v = 0).
V perpendicular(const V& v) {
  if (v.squaredNorm() == 0) return V::UnitY();
  Eigen::Index k = 0;
  v.cwiseAbs().minCoeff(&k);  // the axis least aligned with v
  return v.cross(V::Unit(k)).normalized();
}

// Times of the degenerate (always coplanar) case, appended unsorted to `times`.
struct TimeList {
  std::array<double, 40> t{};
  int n = 0;
  void add(double x) {
    if (n < static_cast<int>(t.size()) && x >= 0 && x <= 1 && std::isfinite(x)) t[n++] = x;
  }
};

// Times in (0, 1) at which point P crosses the line of edge (E0, E1), measured along `axis`
// (the plane's normal): (E1 - E0)(t) x (P - E0)(t) . axis, a quadratic in t.
void addLineCrossings(const Moving& P, const Moving& E0, const Moving& E1, const V& axis,
                      TimeList& times) {
  const Moving D = minus(E1, E0), Q = minus(P, E0);
  const double c0 = D.x.cross(Q.x).dot(axis);
  const double c1 = (D.x.cross(Q.d) + D.d.cross(Q.x)).dot(axis);
  const double c2 = D.d.cross(Q.d).dot(axis);
  std::array<double, 2> r{};
  const int m = quadraticRootsInUnit(c0, c1, c2, r, 0);
  for (int i = 0; i < m; ++i) times.add(r[i]);
}

// Time in [0, 1] of closest approach of two moving points.
void addApproach(const Moving& P, const Moving& Q, TimeList& times) {
  const Moving r = minus(P, Q);
  const double dd = r.d.squaredNorm();
  if (dd > 0) times.add(std::clamp(-r.x.dot(r.d) / dd, 0.0, 1.0));
}

// Scales for the tolerances: L bounds |A(t)|, |B(t)|, |C(t)| over [0, 1] (convexity), M the
// largest coordinate magnitude (the inputs' rounding is relative to it).
struct Scales {
  double L = 0, M = 0;
};

Scales scalesOf(std::initializer_list<const Moving*> points, const TripleProduct& f) {
  Scales s;
  for (const Moving* m : {&f.A, &f.B, &f.C})
    s.L = std::max({s.L, m->x.norm(), (m->x + m->d).norm()});
  for (const Moving* p : points)
    s.M = std::max({s.M, p->x.cwiseAbs().maxCoeff(), (p->x + p->d).cwiseAbs().maxCoeff()});
  s.M = std::max(s.M, s.L);
  return s;
}

// Inputs carry Real's rounding (relative eps to the coordinates' magnitude M); 16 ulps of M
// absorb it together with the double arithmetic on top.
double realSlack(double M) { return 16 * double(std::numeric_limits<Real>::epsilon()) * M; }

// The candidate times of the generic case, in order: for each monotone piece of f between 0,
// the critical points and 1, its start when f is within `tol` of zero there (a graze or a start
// in contact), then the root of a sign change.
template <class Test>
bool scanCubic(const TripleProduct& f, double tol, Test&& test) {
  std::array<double, 4> split{0, 0, 0, 0};
  int n = 1;
  n = quadraticRootsInUnit(f.k[1], 2 * f.k[2], 3 * f.k[3], split, n);
  split[n++] = 1;
  double prev = f(split[0]);
  for (int i = 0; i < n; ++i) {
    const double t = split[i];
    const double ft = i == 0 ? prev : f(t);
    if (std::abs(ft) <= tol * f.normalLength(t) && test(t)) return true;
    if (i + 1 == n) break;
    const double next = f(split[i + 1]);
    if ((ft < 0 && next > 0) || (ft > 0 && next < 0)) {
      if (test(refineRoot(f, t, split[i + 1], ft))) return true;
    }
    prev = next;
  }
  return false;
}

// -sign(f'(t)) as the side a feature came from, with fallbacks for a stationary f.
double approachSide(const TripleProduct& f, double t) {
  const double df = f.derivative(t);
  if (df != 0) return df < 0 ? 1.0 : -1.0;
  const double ft = f(t);
  if (ft != 0) return ft > 0 ? 1.0 : -1.0;
  const double f0 = f(0);
  return f0 < 0 ? -1.0 : 1.0;
}

bool nearlyCoplanarAlways(const TripleProduct& f, const Scales& s) {
  const double sum = std::abs(f.k[0]) + std::abs(f.k[1]) + std::abs(f.k[2]) + std::abs(f.k[3]);
  return sum <= realSlack(s.M) * s.L * s.L;
}

void requireSettings(const ContinuousTriangleSettings& settings, const char* what) {
  require(std::isfinite(settings.thickness) && settings.thickness >= 0,
          std::string(what) + ": thickness must be finite and >= 0");
}

Vec3 toReal(const V& v) { return v.cast<Real>(); }

}  // namespace

std::optional<VertexFaceContact> vertexFaceContinuous(const LinearMotion& pm,
                                                      const LinearMotion& am,
                                                      const LinearMotion& bm,
                                                      const LinearMotion& cm,
                                                      const ContinuousTriangleSettings& settings) {
  requireSettings(settings, "vertexFaceContinuous");
  const Moving p = inDouble(pm), a = inDouble(am), b = inDouble(bm), c = inDouble(cm);
  // f(t) = ((b - a) x (c - a)) . (p - a): the vertex's signed distance times |normal|.
  const TripleProduct f(minus(b, a), minus(c, a), minus(p, a));
  const Scales scales = scalesOf({&p, &a, &b, &c}, f);
  const double tol = double(settings.thickness) + realSlack(scales.M);

  std::optional<VertexFaceContact> result;
  auto test = [&](double t) {
    const V pt = p.at(t), at = a.at(t), bt = b.at(t), ct = c.at(t);
    const TriangleNearest near = closestOnTriangle(pt, at, bt, ct);
    const double dist = (pt - near.point).norm();
    if (!(dist <= tol)) return false;
    V n = (bt - at).cross(ct - at);
    const double len = n.norm();
    if (len > 0) {
      n *= approachSide(f, t) / len;
    } else {
      // Zero-area triangle: against the vertex's velocity relative to the closest point, else
      // from the triangle towards the vertex.
      const V rel = p.d - (near.bary[0] * a.d + near.bary[1] * b.d + near.bary[2] * c.d);
      n = rel.squaredNorm() > 0 ? V(-rel.normalized())
          : dist > 0            ? V((pt - near.point) / dist)
                                : V(V::UnitY());
    }
    VertexFaceContact contact;
    contact.time = Real(t);
    contact.barycentric = toReal(near.bary);
    contact.normal = toReal(n);
    contact.distance = Real(dist);
    result = contact;
    return true;
  };

  if (!nearlyCoplanarAlways(f, scales)) {
    scanCubic(f, tol, test);
    return result;
  }
  // Always coplanar: the vertex enters the triangle across an edge's line or at a vertex.
  TimeList times;
  times.add(0);
  times.add(1);
  V axis = V::Zero();
  for (double t : {0.0, 0.5, 1.0}) {
    const V n = (b.at(t) - a.at(t)).cross(c.at(t) - a.at(t));
    if (n.squaredNorm() > axis.squaredNorm()) axis = n;
  }
  if (axis.squaredNorm() > 0) {
    addLineCrossings(p, a, b, axis, times);
    addLineCrossings(p, b, c, axis, times);
    addLineCrossings(p, c, a, axis, times);
  }
  for (const Moving* v : {&a, &b, &c}) addApproach(p, *v, times);
  std::sort(times.t.begin(), times.t.begin() + times.n);
  for (int i = 0; i < times.n; ++i)
    if (test(times.t[i])) break;
  return result;
}

std::optional<EdgeEdgeContact> edgeEdgeContinuous(const LinearMotion& p0m, const LinearMotion& p1m,
                                                  const LinearMotion& q0m, const LinearMotion& q1m,
                                                  const ContinuousTriangleSettings& settings) {
  requireSettings(settings, "edgeEdgeContinuous");
  const Moving p0 = inDouble(p0m), p1 = inDouble(p1m), q0 = inDouble(q0m), q1 = inDouble(q1m);
  // f(t) = ((p1 - p0) x (q1 - q0)) . (q0 - p0): the lines' signed distance times |cross|.
  const TripleProduct f(minus(p1, p0), minus(q1, q0), minus(q0, p0));
  const Scales scales = scalesOf({&p0, &p1, &q0, &q1}, f);
  const double tol = double(settings.thickness) + realSlack(scales.M);

  std::optional<EdgeEdgeContact> result;
  auto test = [&](double t) {
    const V a0 = p0.at(t), a1 = p1.at(t), b0 = q0.at(t), b1 = q1.at(t);
    double s = 0, u = 0;
    closestSegmentSegment(a0, a1, b0, b1, s, u);
    const V onA = a0 + s * (a1 - a0), onB = b0 + u * (b1 - b0);
    const double dist = (onA - onB).norm();
    if (!(dist <= tol)) return false;
    const V dA = a1 - a0, dB = b1 - b0;
    V n = dA.cross(dB);
    const double len = n.norm();
    // Parallel edges when the cross product is below rounding of the product of lengths.
    if (len > 64 * kEps * dA.norm() * dB.norm() && len > 0) {
      n *= -approachSide(f, t) / len;
    } else {
      // Parallel (or point) edges: against A's velocity relative to B, across the edges, else
      // from B towards A, else any perpendicular.
      const V axis = dA.squaredNorm() > 0 ? dA : dB;
      V rel = (p0.d + s * (p1.d - p0.d)) - (q0.d + u * (q1.d - q0.d));
      if (axis.squaredNorm() > 0) rel -= axis * (rel.dot(axis) / axis.squaredNorm());
      n = rel.norm() > 64 * kEps * (p0.d.norm() + p1.d.norm() + q0.d.norm() + q1.d.norm())
              ? V(-rel.normalized())
          : dist > 0 ? V((onA - onB) / dist)
                     : perpendicular(axis);
    }
    EdgeEdgeContact contact;
    contact.time = Real(t);
    contact.s = Real(s);
    contact.u = Real(u);
    contact.normal = toReal(n);
    contact.distance = Real(dist);
    result = contact;
    return true;
  };

  if (!nearlyCoplanarAlways(f, scales)) {
    scanCubic(f, tol, test);
    return result;
  }
  // Always coplanar: the segments start to meet when an end point crosses the other's line or
  // two end points meet.
  TimeList times;
  times.add(0);
  times.add(1);
  V axis = V::Zero();
  for (double t : {0.0, 0.5, 1.0}) {
    const V a0 = p0.at(t), a1 = p1.at(t), b0 = q0.at(t), b1 = q1.at(t);
    for (const V& n : {V((a1 - a0).cross(b1 - b0)), V((a1 - a0).cross(b0 - a0)),
                       V((a1 - a0).cross(b1 - a0)), V((b1 - b0).cross(a0 - b0))})
      if (n.squaredNorm() > axis.squaredNorm()) axis = n;
  }
  if (axis.squaredNorm() > 0) {
    addLineCrossings(p0, q0, q1, axis, times);
    addLineCrossings(p1, q0, q1, axis, times);
    addLineCrossings(q0, p0, p1, axis, times);
    addLineCrossings(q1, p0, p1, axis, times);
  }
  for (const Moving* x : {&p0, &p1})
    for (const Moving* y : {&q0, &q1}) addApproach(*x, *y, times);
  std::sort(times.t.begin(), times.t.begin() + times.n);
  for (int i = 0; i < times.n; ++i)
    if (test(times.t[i])) break;
  return result;
}

}  // namespace inertia
