// GJK distance between convex cores with the signed-volume sub-algorithm (Montanari et al.
// 2017), and the combination of GJK and EPA with the rounding radii.
#include "gjk.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "inertia/core/error.h"
#include "inertia/geometry/support.h"
#include "local_queries.h"

namespace inertia::detail {

// ---------------------------------------------------------------------------------------------
// ConvexProxy

ConvexProxy ConvexProxy::fromCollider(const Collider& collider, const Transform& pose) {
  const Shape& shape = collider.shape();
  ConvexProxy p;
  switch (shape.type()) {
    case ShapeType::Sphere:
      return point(pose.p, shape.get<Sphere>().radius);
    case ShapeType::Capsule: {
      const Capsule& c = shape.get<Capsule>();
      const Vec3 half = pose.rotate(Vec3(0, c.halfHeight, 0));
      return segment(pose.p - half, pose.p + half, c.radius);
    }
    case ShapeType::Box:
      p.core = Core::Box;
      p.halfExtents = shape.get<Box>().halfExtents;
      break;
    case ShapeType::Cylinder:
      p.core = Core::Cylinder;
      p.cylinderRadius = shape.get<Cylinder>().radius;
      p.halfHeight = shape.get<Cylinder>().halfHeight;
      break;
    case ShapeType::Hull:
      p.core = Core::Hull;
      p.hull = &shape.get<ConvexHull>();
      break;
    default:
      throw InvalidArgument(std::string("convex query: a ") + shapeTypeName(shape.type()) +
                            " is not convex (sphere, capsule, box, cylinder or hull expected)");
  }
  p.rotation = pose.q.toRotationMatrix();
  p.position = pose.p;
  return p;
}

ConvexProxy ConvexProxy::point(const Vec3& p, Real radius) {
  ConvexProxy r;
  r.core = Core::Point;
  r.points = {p, p, p};
  r.radius = radius;
  return r;
}

ConvexProxy ConvexProxy::segment(const Vec3& a, const Vec3& b, Real radius) {
  ConvexProxy r;
  r.core = Core::Segment;
  r.points = {a, b, b};
  r.radius = radius;
  return r;
}

ConvexProxy ConvexProxy::triangle(const Vec3& a, const Vec3& b, const Vec3& c, Real radius) {
  ConvexProxy r;
  r.core = Core::Triangle;
  r.points = {a, b, c};
  r.radius = radius;
  return r;
}

Vec3 ConvexProxy::support(const Vec3& d) const {
  switch (core) {
    case Core::Point:
      return points[0];
    case Core::Segment:
      return d.dot(points[1] - points[0]) > 0 ? points[1] : points[0];
    case Core::Triangle: {
      const Real d0 = d.dot(points[0]), d1 = d.dot(points[1]), d2 = d.dot(points[2]);
      if (d0 >= d1 && d0 >= d2) return points[0];
      return d1 >= d2 ? points[1] : points[2];
    }
    case Core::Box: {
      const Vec3 local = rotation.transpose() * d;
      return rotation * inertia::support(Box{halfExtents}, local) + position;
    }
    case Core::Cylinder: {
      const Vec3 local = rotation.transpose() * d;
      return rotation * inertia::support(Cylinder{cylinderRadius, halfHeight}, local) + position;
    }
    case Core::Hull: {
      const Vec3 local = rotation.transpose() * d;
      return rotation * inertia::support(*hull, local) + position;
    }
  }
  return points[0];
}

Vec3 ConvexProxy::centre() const {
  switch (core) {
    case Core::Point:
      return points[0];
    case Core::Segment:
      return Real(0.5) * (points[0] + points[1]);
    case Core::Triangle:
      return (points[0] + points[1] + points[2]) / Real(3);
    case Core::Box:
    case Core::Cylinder:
      return position;
    case Core::Hull:
      return rotation * hull->interiorPoint() + position;
  }
  return position;
}

// ---------------------------------------------------------------------------------------------
// Signed-volume distance sub-algorithm (Montanari, Petrinic and Barbieri 2017, section 3).
// Each routine finds the barycentric weights of the point of a simplex closest to the origin by
// projecting onto the coordinate axis / plane of largest extent and comparing signed volumes,
// which stays accurate for thin simplices where Johnson's determinants lose their sign.

namespace {

// The sub-algorithm's simplex in scalar S: the vertices' points, their weights, and where each
// came from in the caller's Simplex (reductions keep a subset, in order).
template <class S>
struct SubSimplex {
  using V = Eigen::Matrix<S, 3, 1>;
  std::array<V, 4> p{V::Zero(), V::Zero(), V::Zero(), V::Zero()};
  std::array<S, 4> lambda{};
  std::array<int, 4> id{};
  int count = 0;
};

template <class S>
bool sameSign(S a, S b) {
  return (a > 0 && b > 0) || (a < 0 && b < 0);
}

template <class V>
int largestAxis(const V& v) {
  const V a = v.cwiseAbs();
  return a.x() >= a.y() ? (a.x() >= a.z() ? 0 : 2) : (a.y() >= a.z() ? 1 : 2);
}

template <class S>
typename SubSimplex<S>::V combine(const SubSimplex<S>& s) {
  typename SubSimplex<S>::V v = SubSimplex<S>::V::Zero();
  for (int i = 0; i < s.count; ++i) v += s.lambda[i] * s.p[i];
  return v;
}

// Keeps vertices idx[0..n) of s, in that order, with weights lam.
template <class S>
void reduce(SubSimplex<S>& s, const int* idx, const S* lam, int n) {
  SubSimplex<S> r;
  for (int i = 0; i < n; ++i) r.p[i] = s.p[idx[i]], r.id[i] = s.id[idx[i]], r.lambda[i] = lam[i];
  r.count = n;
  s = r;
}

template <class S>
void s1d(SubSimplex<S>& s) {
  using V = typename SubSimplex<S>::V;
  const V& p1 = s.p[0];
  const V& p2 = s.p[1];
  const V t = p2 - p1;
  const S tt = t.squaredNorm();
  const int keep1[1] = {0}, keep2[1] = {1};
  const S one[1] = {1};
  if (!(tt > 0)) {
    reduce(s, keep2, one, 1);
    return;
  }
  // Projection of the origin onto the line, then 1D signed lengths on the dominant axis.
  const V p0 = p1 - t * (p1.dot(t) / tt);
  const int i = largestAxis(t);
  const S mu = p1[i] - p2[i];
  const S c1 = p0[i] - p2[i];  // mu * weight of p1
  const S c2 = p1[i] - p0[i];  // mu * weight of p2
  if (sameSign(mu, c1) && sameSign(mu, c2)) {
    s.lambda = {c1 / mu, c2 / mu, 0, 0};
  } else if (!sameSign(mu, c1)) {
    reduce(s, keep2, one, 1);  // beyond p2
  } else {
    reduce(s, keep1, one, 1);  // beyond p1
  }
}

template <class S>
void s2d(SubSimplex<S>& s) {
  using V = typename SubSimplex<S>::V;
  const V& p1 = s.p[0];
  const V& p2 = s.p[1];
  const V& p3 = s.p[2];
  const V n = (p2 - p1).cross(p3 - p1);
  const S nn = n.squaredNorm();
  std::array<S, 3> c{0, 0, 0};
  S mu = 0;
  if (nn > 0) {
    // Projection of the origin onto the plane; signed areas in the coordinate plane where the
    // triangle's projection is largest (drop axis k, keep the cyclic pair (x, y)).
    const V p0 = n * (p1.dot(n) / nn);
    const int k = largestAxis(n);
    const int x = (k + 1) % 3, y = (k + 2) % 3;
    const auto area = [&](const V& a, const V& b, const V& cc) {
      return (b[x] - a[x]) * (cc[y] - a[y]) - (b[y] - a[y]) * (cc[x] - a[x]);
    };
    c = {area(p0, p2, p3), area(p1, p0, p3), area(p1, p2, p0)};
    mu = c[0] + c[1] + c[2];
    if (sameSign(mu, c[0]) && sameSign(mu, c[1]) && sameSign(mu, c[2])) {
      s.lambda = {c[0] / mu, c[1] / mu, c[2] / mu, 0};
      return;
    }
  }
  // The closest point lies on an edge opposite a vertex whose weight is not positive (or on
  // any edge of a degenerate triangle): try those edges, keep the nearest.
  SubSimplex<S> best;
  S bestD = std::numeric_limits<S>::infinity();
  for (int j = 0; j < 3; ++j) {
    if (mu != 0 && sameSign(mu, c[j])) continue;
    const int edge[2] = {(j + 1) % 3, (j + 2) % 3};
    const S none[2] = {0, 0};
    SubSimplex<S> e = s;
    reduce(e, edge, none, 2);
    s1d(e);
    const S d = combine(e).squaredNorm();
    if (d < bestD) bestD = d, best = e;
  }
  s = best;
}

template <class S>
void s3d(SubSimplex<S>& s) {
  using V = typename SubSimplex<S>::V;
  const V& p1 = s.p[0];
  const V& p2 = s.p[1];
  const V& p3 = s.p[2];
  const V& p4 = s.p[3];
  // Cofactors of [[p1 p2 p3 p4]; [1 1 1 1]]: signed volumes with the origin in place of p_j.
  const std::array<S, 4> c{-p2.dot(p3.cross(p4)), p1.dot(p3.cross(p4)), -p1.dot(p2.cross(p4)),
                           p1.dot(p2.cross(p3))};
  const S det = c[0] + c[1] + c[2] + c[3];
  if (sameSign(det, c[0]) && sameSign(det, c[1]) && sameSign(det, c[2]) && sameSign(det, c[3])) {
    s.lambda = {c[0] / det, c[1] / det, c[2] / det, c[3] / det};
    return;  // origin inside
  }
  SubSimplex<S> best;
  S bestD = std::numeric_limits<S>::infinity();
  for (int j = 0; j < 4; ++j) {
    if (det != 0 && sameSign(det, c[j])) continue;
    int face[3];
    for (int i = 0, k = 0; i < 4; ++i)
      if (i != j) face[k++] = i;
    const S none[3] = {0, 0, 0};
    SubSimplex<S> f = s;
    reduce(f, face, none, 3);
    s2d(f);
    const S d = combine(f).squaredNorm();
    if (d < bestD) bestD = d, best = f;
  }
  s = best;
}

// closestToOrigin() with the signed volumes in scalar S.
template <class S>
Vec3 closestToOriginIn(Simplex& simplex) {
  SubSimplex<S> s;
  s.count = simplex.count;
  for (int i = 0; i < s.count; ++i) s.p[i] = simplex.v[i].w.template cast<S>(), s.id[i] = i;
  switch (s.count) {
    case 1:
      s.lambda = {1, 0, 0, 0};
      break;
    case 2:
      s1d(s);
      break;
    case 3:
      s2d(s);
      break;
    case 4:
      s3d(s);
      break;
    default:
      simplex.count = 0;
      return Vec3::Zero();
  }
  std::array<SimplexVertex, 4> v{};
  for (int i = 0; i < s.count; ++i) v[i] = simplex.v[s.id[i]];
  simplex.v = v;
  for (int i = 0; i < 4; ++i) simplex.lambda[i] = i < s.count ? Real(s.lambda[i]) : Real(0);
  simplex.count = s.count;
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < simplex.count; ++i) p += simplex.lambda[i] * simplex.v[i].w;
  return p;
}

}  // namespace

Vec3 closestToOrigin(Simplex& s) { return closestToOriginIn<Real>(s); }

// Wider than Real: double for float; for double, long double (x87's 64-bit significand here,
// eleven bits more).
using Wide = std::conditional_t<sizeof(Real) == 4, double, long double>;

Vec3 closestToOriginWide(Simplex& s) { return closestToOriginIn<Wide>(s); }

// ---------------------------------------------------------------------------------------------
// GJK

namespace {

// Relative gap between |v| and the lower bound v.w/|v| at which GJK stops: a few ulps in float,
// 1e-12 in double (below that, curved cores only make GJK crawl).
constexpr Real kGjkRelative = std::max(Real(8) * std::numeric_limits<Real>::epsilon(), Real(1e-12));
// |v| below this times the size of the Minkowski difference counts as touching.
constexpr Real kGjkAbsolute = Real(32) * std::numeric_limits<Real>::epsilon();

void witnessPoints(const Simplex& s, Vec3& a, Vec3& b) {
  a.setZero();
  b.setZero();
  for (int i = 0; i < s.count; ++i) {
    a += s.lambda[i] * s.v[i].a;
    b += s.lambda[i] * s.v[i].b;
  }
}

}  // namespace

SimplexVertex supportVertex(const ConvexProxy& a, const ConvexProxy& b, const Vec3& d) {
  SimplexVertex sv;
  sv.a = a.support(d);
  sv.b = b.support(-d);
  sv.w = sv.a - sv.b;
  return sv;
}

GjkResult gjk(const ConvexProxy& a, const ConvexProxy& b, const Vec3& guess) {
  GjkResult r;
  Vec3 d = guess.squaredNorm() > 0 ? Vec3(-guess) : Vec3(a.centre() - b.centre());
  if (!(d.squaredNorm() > 0)) d = Vec3::UnitX();

  Simplex& s = r.simplex;
  s.v[0] = supportVertex(a, b, -d);
  s.count = 1;
  s.lambda = {1, 0, 0, 0};
  Vec3 v = s.v[0].w;
  Real vv = v.squaredNorm();
  Real scale2 = vv;
  r.iterations = 1;

  while (true) {
    if (vv <= kGjkAbsolute * kGjkAbsolute * scale2) {
      r.overlapping = true;  // the origin is (within rounding) on the simplex
      break;
    }
    if (r.iterations >= kGjkMaxIterations) break;
    const SimplexVertex w = supportVertex(a, b, -v);
    ++r.iterations;
    scale2 = std::max(scale2, w.w.squaredNorm());
    // Termination: the lower bound v.w/|v| is within the relative tolerance of |v|
    // (van den Bergen 2003, 4.3.5).
    if (vv - v.dot(w.w) <= kGjkRelative * vv) break;
    // A support point already in the simplex brings nothing new.
    bool repeated = false;
    for (int i = 0; i < s.count; ++i) repeated = repeated || s.v[i].w == w.w;
    if (repeated) break;

    const Simplex previous = s;
    s.v[s.count++] = w;
    Vec3 next = closestToOrigin(s);
    // w lies nearer than |v| along v (the relative test above), so the hull's closest point
    // is nearer than v. When Real's signed volumes say otherwise, a thin simplex (support
    // points close together on a curved core) has lost their sign: again, wider. A capsule
    // against a cylinder stopped 0.3% short of its distance in float (issue 21), 1.5e-10
    // relative in double (documented: 1e-12).
    if (s.count < 4 && !(next.squaredNorm() < vv)) {
      s = previous;
      s.v[s.count++] = w;
      next = closestToOriginWide(s);
    }
    if (s.count == 4) {
      r.overlapping = true;  // origin inside the tetrahedron
      v.setZero();
      vv = 0;
      break;
    }
    const Real nextVv = next.squaredNorm();
    // No progress: rounding has taken over; keep the better previous simplex.
    if (nextVv >= vv) {
      s = previous;
      break;
    }
    v = next;
    vv = nextVv;
  }

  witnessPoints(s, r.pointA, r.pointB);
  r.distance = r.overlapping ? Real(0) : std::sqrt(vv);
  return r;
}

// ---------------------------------------------------------------------------------------------
// GJK + EPA with the radii

namespace {

// Rounded shapes whose cores are apart by less than their radii overlap by radii - distance
// along the cores' closest direction, n = (pointB - pointA) / distance. Rounding puts an ulp of
// the coordinates into pointB - pointA, so for nearly touching cores n is off by ulps over the
// distance, and moving B along it by the depth leaves the shapes overlapping (issue 21). The
// supports' gap along n, h_B(-n) - h_A(n), is at most the distance, equal when n is right: when
// it falls short beyond the depth accuracy, the normal is taken from EPA instead, on B moved
// towards A until the cores overlap by about their size's thousandth (EPA's face normals come
// from differences of support points a whole face apart). The shift biases EPA's normal towards
// n by (1 - cos angle) * shift, second order in the angle; the depth stays radii - distance.
void refineRoundedNormal(const ConvexProxy& a, const ConvexProxy& b, const GjkResult& g,
                         ConvexSeparation& out) {
  const Vec3& n = out.normal;
  const Vec3 sa = a.support(n), sb = b.support(-n);
  const Real scale =
      (sa - a.centre()).norm() + (sb - b.centre()).norm() + (a.centre() - b.centre()).norm();
  const Real noise = Real(8) * std::numeric_limits<Real>::epsilon() * scale;
  const Real gap = n.dot(sb - sa);
  const Real depth = -out.distance;
  const Real rel = sizeof(Real) == 4 ? Real(1e-5) : Real(1e-7);
  if (!(g.distance - gap > rel * depth + noise)) return;
  ConvexProxy moved = b;
  const Vec3 shift = -(g.distance + Real(1e-3) * scale) * n;
  for (Vec3& x : moved.points) x += shift;
  moved.position += shift;
  const GjkResult h = gjk(a, moved, n);
  if (!h.overlapping) return;
  const EpaResult e = epa(a, moved, h.simplex);
  if (!e.converged) return;
  // The shift can make another face the shallowest: a core just outside one face of a box and
  // just inside the next one's plane gave that next face's normal, a right angle off. The
  // cores' distance is the largest gap over the directions, so EPA's normal replaces n only
  // where its gap on the unmoved cores is the larger.
  if (!(e.normal.dot(b.support(-e.normal) - a.support(e.normal)) > gap)) return;
  out.normal = e.normal;
  out.pointA = e.pointA + a.radius * e.normal;
  out.pointB = out.pointA - depth * e.normal;
}

}  // namespace

ConvexSeparation separation(const ConvexProxy& a, const ConvexProxy& b, const Vec3& guess) {
  ConvexSeparation out;
  const GjkResult g = gjk(a, b, guess);
  out.gjkIterations = g.iterations;
  const Real radii = a.radius + b.radius;
  if (!g.overlapping) {
    // Cores apart: the rounded shapes are the cores grown along the core normal.
    const Vec3 fallback = normalizedOr(b.centre() - a.centre(), Vec3::UnitY());
    out.normal = normalizedOr(g.pointB - g.pointA, fallback);
    out.distance = g.distance - radii;
    out.pointA = g.pointA + a.radius * out.normal;
    out.pointB = g.pointB - b.radius * out.normal;
    if (out.distance < 0) refineRoundedNormal(a, b, g, out);
    return out;
  }
  const EpaResult e = epa(a, b, g.simplex);
  out.epaIterations = e.iterations;
  out.normal = e.normal;
  out.distance = -(e.depth + radii);
  out.pointA = e.pointA + a.radius * out.normal;
  out.pointB = e.pointB - b.radius * out.normal;
  return out;
}

}  // namespace inertia::detail
