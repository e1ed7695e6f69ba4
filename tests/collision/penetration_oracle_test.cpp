// Penetration depth and distance of random convex pairs (sphere, capsule, box, cylinder, hull)
// against an exact reference written here in double, independent of GJK and EPA.
//
// The reference: the depth is D = min over unit u of the support overlap
// o(u) = h_A(u) + h_B(-u) (translating B by o(u) u separates the pair), and the distance of
// apart shapes is -D. Each shape is a core (a point, a segment, a polytope or a cylinder) grown by
// a radius, and o adds the radii. Then:
// - a point core (a sphere) against any core: D = radii - sdf(core, centre), exact (for a
//   cylinder this is the closed form r + min(R - rho, h - |y|) when the centre is inside);
// - a segment core (a capsule) apart from the other core: D = radii - min_t sdf(core, p(t)), the
//   signed distance being convex along the segment (golden-section search);
// - otherwise the cores overlap and D is the least overlap over the separating-axis candidates
//   of the Minkowski difference (the face normals of either core and the crosses of their edge
//   directions), exact for polytopes. A cylinder lies between the prisms inscribed in it and
//   circumscribed about it; the depth grows with the sets, so the inscribed prism's depth is a
//   lower bound `lo`, and min over the candidates of the exact o(u), refined by a local search
//   on the sphere, an upper bound `hi` (any direction's overlap bounds D from above).
// Three assertions follow for a penetration (depth d, normal n), all certified by these bounds:
// d >= lo, d <= hi, and o(n) <= d (1 + rel) + abs (B moved along EPA's own normal by about d
// separates, which with D <= o(n) proves d is not too shallow: the defect of issue 21).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>
#include <vector>

#include "collision/gjk.h"
#include "collision_test_util.h"
#include "inertia/collision/distance.h"

using namespace inertia;
using namespace inertia::test;

namespace {

enum class Kind { Sphere, Capsule, Box, Cylinder, Hull };
const char* kindName(Kind k) {
  constexpr const char* names[] = {"sphere", "capsule", "box", "cylinder", "hull"};
  return names[int(k)];
}

// A shape at a pose, in double: the core in world coordinates and the rounding radius.
struct ShapeD {
  Kind kind;
  Shape shape;
  Transform pose;
  Eigen::Matrix3d rot;
  Vec3d centre;
  double radius = 0;  // rounding radius (sphere, capsule)
  Vec3d seg0, seg1;   // capsule core, world
  std::vector<Vec3d> hullLocal;
};

ShapeD makeShape(Kind kind, const Shape& shape, const Transform& pose) {
  ShapeD s{kind, shape, pose, pose.q.cast<double>().normalized().toRotationMatrix(), toD(pose.p), 0,
           {},   {},    {}};
  switch (kind) {
    case Kind::Sphere:
      s.radius = shape.get<Sphere>().radius;
      break;
    case Kind::Capsule: {
      const Capsule& c = shape.get<Capsule>();
      s.radius = c.radius;
      s.seg0 = s.centre - s.rot * Vec3d(0, c.halfHeight, 0);
      s.seg1 = s.centre + s.rot * Vec3d(0, c.halfHeight, 0);
      break;
    }
    case Kind::Hull:
      for (const Vec3& v : shape.get<ConvexHull>().vertices()) s.hullLocal.push_back(toD(v));
      break;
    default:
      break;
  }
  return s;
}

// Exact support point of the core in world direction u.
Vec3d coreSupport(const ShapeD& s, const Vec3d& u) {
  const Vec3d l = s.rot.transpose() * u;
  switch (s.kind) {
    case Kind::Sphere:
      return s.centre;
    case Kind::Capsule:
      return u.dot(s.seg1 - s.seg0) > 0 ? s.seg1 : s.seg0;
    case Kind::Box: {
      const Vec3d h = toD(s.shape.get<Box>().halfExtents);
      return s.centre + s.rot * Vec3d(l.x() >= 0 ? h.x() : -h.x(), l.y() >= 0 ? h.y() : -h.y(),
                                      l.z() >= 0 ? h.z() : -h.z());
    }
    case Kind::Cylinder: {
      const Cylinder& c = s.shape.get<Cylinder>();
      const double rho = std::hypot(l.x(), l.z());
      const double y = l.y() >= 0 ? c.halfHeight : -double(c.halfHeight);
      const Vec3d p =
          rho > 0 ? Vec3d(c.radius * l.x() / rho, y, c.radius * l.z() / rho) : Vec3d(0, y, 0);
      return s.centre + s.rot * p;
    }
    case Kind::Hull: {
      std::size_t best = 0;
      for (std::size_t i = 1; i < s.hullLocal.size(); ++i)
        if (l.dot(s.hullLocal[i]) > l.dot(s.hullLocal[best])) best = i;
      return s.centre + s.rot * s.hullLocal[best];
    }
  }
  return s.centre;
}

// Support overlap along unit u: the translation of B along u that separates the pair.
double overlap(const ShapeD& a, const ShapeD& b, const Vec3d& u) {
  return u.dot(coreSupport(a, u) - coreSupport(b, -u)) + a.radius + b.radius;
}

// Signed distance of point p (world) to a hull core: inside, the largest plane distance;
// outside, the nearest face (projection inside its loop) or edge.
double hullSdf(const ConvexHull& hull, const Vec3d& p) {
  double inside = -std::numeric_limits<double>::infinity();
  for (const HullFace& f : hull.faces())
    inside = std::max(inside, toD(f.normal).dot(p) - double(f.offset));
  if (inside <= 0) return inside;
  double best2 = std::numeric_limits<double>::infinity();
  for (const HullEdge& e : hull.edges()) {
    const Vec3d x = toD(hull.vertices()[e.v0]);
    best2 = std::min(best2, segmentDistance2(p, p, x, toD(hull.vertices()[e.v1])));
  }
  for (std::size_t f = 0; f < hull.faces().size(); ++f) {
    const Vec3d n = toD(hull.faces()[f].normal);
    const double h = n.dot(p) - double(hull.faces()[f].offset);
    if (h <= 0) continue;
    const Vec3d q = p - h * n;
    bool in = true;
    const auto loop = hull.faceEdges(f);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec3d x = toD(hull.vertices()[loop[k].origin]);
      const Vec3d y = toD(hull.vertices()[loop[(k + 1) % loop.size()].origin]);
      in = in && n.dot((y - x).cross(q - x)) >= 0;
    }
    if (in) best2 = std::min(best2, h * h);
  }
  return std::sqrt(best2);
}

// Exact signed distance of world point p to the core of s (a point or segment core: distance).
double coreSdf(const ShapeD& s, const Vec3d& p) {
  const Vec3d l = s.rot.transpose() * (p - s.centre);
  switch (s.kind) {
    case Kind::Sphere:
      return (p - s.centre).norm();
    case Kind::Capsule:
      return std::sqrt(segmentDistance2(p, p, s.seg0, s.seg1));
    case Kind::Box:
      return sdf(s.shape.get<Box>(), l).distance;
    case Kind::Cylinder:
      return sdf(s.shape.get<Cylinder>(), l).distance;
    case Kind::Hull:
      return hullSdf(s.shape.get<ConvexHull>(), l);
  }
  return 0;
}

// A polytope standing for a core in the separating-axis test: world vertices, face normals and
// edge directions. A cylinder is a prism of kSides sides, inscribed (scale 1) or circumscribed
// (scale 1 / cos(pi / kSides)).
constexpr int kSides = 64;
struct PolyD {
  std::vector<Vec3d> verts, normals, edges;
};

PolyD polytope(const ShapeD& s, double prismScale) {
  PolyD p;
  const auto world = [&](const Vec3d& l) { return Vec3d(s.centre + s.rot * l); };
  switch (s.kind) {
    case Kind::Sphere:
      p.verts = {s.centre};
      break;
    case Kind::Capsule:
      p.verts = {s.seg0, s.seg1};
      p.edges = {s.seg1 - s.seg0};
      break;
    case Kind::Box: {
      const Vec3d h = toD(s.shape.get<Box>().halfExtents);
      for (int i = 0; i < 8; ++i)
        p.verts.push_back(world(
            Vec3d((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z())));
      for (int k = 0; k < 3; ++k)
        p.normals.push_back(s.rot.col(k)), p.edges.push_back(s.rot.col(k));
      break;
    }
    case Kind::Cylinder: {
      const Cylinder& c = s.shape.get<Cylinder>();
      const double r = c.radius * prismScale;
      for (int k = 0; k < kSides; ++k) {
        const double t = 2 * M_PI * k / kSides, m = t + M_PI / kSides;
        for (double y : {-double(c.halfHeight), double(c.halfHeight)})
          p.verts.push_back(world(Vec3d(r * std::cos(t), y, r * std::sin(t))));
        p.normals.push_back(s.rot * Vec3d(std::cos(m), 0, std::sin(m)));
        p.edges.push_back(s.rot * Vec3d(-std::sin(m), 0, std::cos(m)));
      }
      p.normals.push_back(s.rot.col(1));
      p.edges.push_back(s.rot.col(1));
      break;
    }
    case Kind::Hull: {
      const ConvexHull& h = s.shape.get<ConvexHull>();
      for (const Vec3d& v : s.hullLocal) p.verts.push_back(world(v));
      for (const HullFace& f : h.faces()) p.normals.push_back(s.rot * toD(f.normal));
      for (const HullEdge& e : h.edges())
        p.edges.push_back(s.rot * toD(h.vertices()[e.v1] - h.vertices()[e.v0]));
      break;
    }
  }
  return p;
}

std::vector<Vec3d> candidateAxes(const PolyD& a, const PolyD& b) {
  std::vector<Vec3d> axes = a.normals;
  axes.insert(axes.end(), b.normals.begin(), b.normals.end());
  for (const Vec3d& ea : a.edges)
    for (const Vec3d& eb : b.edges) {
      const Vec3d c = ea.cross(eb);
      if (c.norm() > 1e-9 * ea.norm() * eb.norm()) axes.push_back(c.normalized());
    }
  return axes;
}

double polyOverlap(const PolyD& a, const PolyD& b, const Vec3d& u) {
  double hiA = -std::numeric_limits<double>::infinity(), loB = -hiA;
  for (const Vec3d& x : a.verts) hiA = std::max(hiA, u.dot(x));
  for (const Vec3d& y : b.verts) loB = std::min(loB, u.dot(y));
  return hiA - loB;
}

// The least overlap of the cores over the candidate axes (both signs): the core depth when the
// cores overlap (> 0), <= 0 when some axis separates them.
double leastOverlap(const PolyD& a, const PolyD& b, const std::vector<Vec3d>& axes) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3d& u : axes) best = std::min({best, polyOverlap(a, b, u), polyOverlap(a, b, -u)});
  return best;
}

// Local minimum of the exact overlap from u0 by a compass search on the unit sphere (sixteen
// directions in the tangent plane, turned by the golden angle each round so that a kinked
// valley is not missed; the step halved when none improves).
double refine(const ShapeD& a, const ShapeD& b, Vec3d u) {
  double fu = overlap(a, b, u), turn = 0;
  for (double step = 0.05; step > 1e-11;) {
    const Vec3d t1 =
        (std::abs(u.x()) < 0.6 ? Vec3d::UnitX() : Vec3d::UnitY()).cross(u).normalized();
    const Vec3d t2 = u.cross(t1);
    bool improved = false;
    turn += 2.399963;
    for (int k = 0; k < 16 && !improved; ++k) {
      const double ang = turn + M_PI / 8 * k;
      const Vec3d v = (u + step * (std::cos(ang) * t1 + std::sin(ang) * t2)).normalized();
      const double fv = overlap(a, b, v);
      if (fv < fu) u = v, fu = fv, improved = true;
    }
    if (!improved) step /= 2;
  }
  return fu;
}

// Minimum of a convex function on [0, 1] by golden-section search.
double minimiseConvex(const std::function<double(double)>& f) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double lo = 0, hi = 1, x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 80; ++i) {
    if (f1 < f2)
      hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
    else
      lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
  }
  return std::min({f1, f2, f(0), f(1)});
}

// Bounds on the depth D (negative: minus the distance): lo <= D <= hi; lo == hi when exact.
struct Reference {
  double lo, hi;
  bool exact;
};

Reference reference(const ShapeD& a, const ShapeD& b) {
  const double radii = a.radius + b.radius;
  const bool roundA = a.kind == Kind::Sphere || a.kind == Kind::Capsule;
  const bool roundB = b.kind == Kind::Sphere || b.kind == Kind::Capsule;
  if (roundA && roundB) {
    const Vec3d a0 = a.kind == Kind::Sphere ? a.centre : a.seg0;
    const Vec3d a1 = a.kind == Kind::Sphere ? a.centre : a.seg1;
    const Vec3d b0 = b.kind == Kind::Sphere ? b.centre : b.seg0;
    const Vec3d b1 = b.kind == Kind::Sphere ? b.centre : b.seg1;
    const double d = radii - std::sqrt(segmentDistance2(a0, a1, b0, b1));
    return {d, d, true};
  }
  if (roundA || roundB) {
    const ShapeD& k = roundA ? a : b;  // the point or segment core
    const ShapeD& o = roundA ? b : a;
    const double m = k.kind == Kind::Sphere ? coreSdf(o, k.centre) : minimiseConvex([&](double t) {
      return coreSdf(o, k.seg0 + t * (k.seg1 - k.seg0));
    });
    if (m > 0 || k.kind == Kind::Sphere) return {radii - m, radii - m, true};
  }
  // Overlapping cores (or two solid cores): the separating-axis candidates.
  const PolyD ia = polytope(a, 1), ib = polytope(b, 1);
  const auto axes = candidateAxes(ia, ib);
  const bool curved = a.kind == Kind::Cylinder || b.kind == Kind::Cylinder;
  const double inscribed = leastOverlap(ia, ib, axes);
  // The four best axes, each refined on the exact support functions.
  std::vector<std::pair<double, Vec3d>> scored;
  for (const Vec3d& u : axes)
    for (const Vec3d& s : {u, Vec3d(-u)}) scored.push_back({overlap(a, b, s), s});
  const std::size_t keep = std::min<std::size_t>(4, scored.size());
  std::partial_sort(scored.begin(), scored.begin() + keep, scored.end(),
                    [](const auto& x, const auto& y) { return x.first < y.first; });
  double hi = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < keep; ++i)
    hi = std::min(hi, curved ? refine(a, b, scored[i].second) : scored[i].first);
  if (roundA || roundB) return {radii + std::max(inscribed, 0.0), hi, !curved};
  if (inscribed > 0) return {inscribed, hi, !curved};
  // Cores apart by the inscribed prisms: apart for good when the circumscribed ones are too.
  const PolyD oa = polytope(a, 1 / std::cos(M_PI / kSides)),
              ob = polytope(b, 1 / std::cos(M_PI / kSides));
  const double outer = leastOverlap(oa, ob, axes);
  return {outer <= 0 ? -std::numeric_limits<double>::infinity() : 0.0, std::min(hi, outer), false};
}

Shape randomShape(std::mt19937_64& rng, Kind kind) {
  const auto r = [&] { return Real(uniform(rng, 0.2, 1)); };
  switch (kind) {
    case Kind::Sphere:
      return Sphere{r()};
    case Kind::Capsule:
      return Capsule{r(), r()};
    case Kind::Box:
      return Box{randomVec(rng, 0.2, 1)};
    case Kind::Cylinder:
      return Cylinder{r(), r()};
    case Kind::Hull:
      return Shape(randomHull(rng, 8 + int(rng() % 24), 1));
  }
  return Sphere{1};
}

// The size the rounding scales with: the centres' distance plus both shapes' reach (m).
double pairScale(const ShapeD& a, const ShapeD& b) {
  double reach = 0;
  for (const ShapeD* s : {&a, &b})
    for (const Vec3d u : {Vec3d::UnitX(), Vec3d::UnitY(), Vec3d::UnitZ()})
      reach += std::max((coreSupport(*s, u) - s->centre).norm(),
                        (coreSupport(*s, -u) - s->centre).norm()) /
                   3 +
               s->radius / 3;
  return (a.centre - b.centre).norm() + reach;
}

// Accuracy (distance.h): depth within a relative kDepthRel plus rounding. EPA stops when the
// support point along the nearest face's normal rises less than kDepthRel * depth + 8 ulps of
// the difference's size above it (epa.cpp); the float support points, normal and depth carry a
// few ulps of the coordinates more: kRoundUlps ulps of the pair's size in all.
constexpr double kDepthRel = sizeof(Real) == 4 ? 1e-5 : 1e-7;
// Distance: GJK stops when the lower bound v.w / |v| is within 16 ulps (float) or 1e-12
// (double) of |v| (gjk.cpp), the float closest points carry a few ulps of the coordinates.
constexpr double kDistanceRel = sizeof(Real) == 4 ? 1e-6 : 1e-11;
// The closest points lie on the surfaces to rounding in float; in double, GJK's points on a
// cylinder's curved side come from a simplex that stopped at 1e-12 of the distance, and lie up
// to 1.8e-11 m off the surface (a cylinder-hull pair of size 1): 1e-10 of the pair's size.
constexpr double kPointRel = sizeof(Real) == 4 ? 0 : 1e-10;
// In double the coordinates no longer hide it: the witness points come from barycentric
// weights on the nearest face (EPA) or simplex (GJK), whose conditioning cost up to 650 ulps
// of the pair's size (1.4e-13 m on a sphere-cylinder pair of size 1), so double allows 1024.
constexpr double kRoundUlps = sizeof(Real) == 4 ? 32 : 1024;

struct Tally {
  int overlapping = 0, apart = 0;
  double depthExcess = 0, distanceExcess = 0;  // beyond the relative term, in ulps of the size
};

// Checks penetration() and closestPoints() on one pair against the reference; returns the
// worst error beyond the relative terms in ulps of the pair's size, for the report.
void checkPair(const ShapeD& a, const ShapeD& b, Tally& tally, const std::string& what) {
  const Reference ref = reference(a, b);
  const Collider ca(a.shape), cb(b.shape);
  const double ulp = kEps * pairScale(a, b), abs = kRoundUlps * ulp;
  const auto p = penetration(ca, a.pose, cb, b.pose);
  if (ref.lo > abs) {
    ++tally.overlapping;
    ASSERT_TRUE(p.has_value()) << what << " depth " << ref.lo;
    const double d = p->depth;
    // B moved along the returned normal by the support overlap o(n) separates; D <= o(n).
    const double own = overlap(a, b, toD(p->normal).normalized());
    const double excess = std::max({ref.lo - d, d - ref.hi, own - d}) - kDepthRel * ref.hi;
    tally.depthExcess = std::max(tally.depthExcess, excess / ulp);
    EXPECT_GE(d, ref.lo - kDepthRel * ref.lo - abs) << what;
    EXPECT_LE(d, ref.hi + abs) << what;
    EXPECT_LE(own, d + kDepthRel * d + abs) << what << " depth " << d;
    EXPECT_LE((toD(p->pointA) - toD(p->pointB) - d * toD(p->normal)).norm(), abs) << what;
  } else if (ref.hi < -abs) {
    ++tally.apart;
    EXPECT_FALSE(p.has_value()) << what;
    const ClosestPoints c = closestPoints(ca, a.pose, cb, b.pose);
    ASSERT_FALSE(c.overlapping) << what;
    // The true distance lies between the gap of the supports along any direction (the best
    // of the reference's and one refined from GJK's normal) and the closest points' distance,
    // these lying on the surfaces.
    const Vec3d n = toD(c.normal).normalized();
    const double lower = std::max(-ref.hi, -refine(a, b, n));
    const double len = (toD(c.pointB) - toD(c.pointA)).norm();
    const double onA = coreSdf(a, toD(c.pointA)) - a.radius;
    const double onB = coreSdf(b, toD(c.pointB)) - b.radius;
    const double excess = std::max({lower - c.distance, c.distance - len, std::abs(onA),
                                    std::abs(onB), ref.exact ? std::abs(c.distance + ref.lo) : 0}) -
                          kDistanceRel * c.distance;
    tally.distanceExcess = std::max(tally.distanceExcess, excess / ulp);
    EXPECT_GE(c.distance, lower - kDistanceRel * lower - abs) << what;
    EXPECT_LE(c.distance, len + abs) << what;
    EXPECT_LE(std::abs(onA), abs + kPointRel * ulp / kEps) << what;
    EXPECT_LE(std::abs(onB), abs + kPointRel * ulp / kEps) << what;
    if (ref.exact) {
      EXPECT_NEAR(c.distance, -ref.lo, kDistanceRel * c.distance + abs) << what;
    }
  }
}

}  // namespace

TEST(PenetrationOracle, RandomPairsOfEveryKindMeetTheDocumentedAccuracy) {
  // 24 seeded pairs per ordered pair of kinds (600 in all, 216 per kind), shapes of size 0.2..1 m
  // whose centres lie within 0.6 m per axis: about nine in ten overlap.
  std::mt19937_64 rng(2101);
  constexpr Kind kinds[] = {Kind::Sphere, Kind::Capsule, Kind::Box, Kind::Cylinder, Kind::Hull};
  Tally all;
  for (Kind ka : kinds)
    for (Kind kb : kinds) {
      Tally t;
      for (int k = 0; k < 24; ++k) {
        // The pose before the shape: the order GCC drew the arguments in (tests/draws.h).
        const Transform poseA = randomPose(rng, 0.6);
        const ShapeD a = makeShape(ka, randomShape(rng, ka), poseA);
        const Transform poseB = randomPose(rng, 0.6);
        const ShapeD b = makeShape(kb, randomShape(rng, kb), poseB);
        checkPair(a, b, t,
                  std::string(kindName(ka)) + "-" + kindName(kb) + " #" + std::to_string(k));
      }
      std::printf(
          "%-9s %-9s %2d overlapping, %2d apart; beyond the relative term (ulps of the "
          "size): depth %5.1f, distance %5.1f\n",
          kindName(ka), kindName(kb), t.overlapping, t.apart, t.depthExcess, t.distanceExcess);
      all.overlapping += t.overlapping, all.apart += t.apart;
      all.depthExcess = std::max(all.depthExcess, t.depthExcess);
      all.distanceExcess = std::max(all.distanceExcess, t.distanceExcess);
    }
  EXPECT_GT(all.overlapping, 420);
  EXPECT_GT(all.apart, 36);
  std::printf(
      "all: %d overlapping, %d apart; worst beyond the relative terms: depth %.1f ulps, "
      "distance %.1f ulps of the size\n",
      all.overlapping, all.apart, all.depthExcess, all.distanceExcess);
}

TEST(PenetrationOracle, CapsuleDeepInCylinderFromIssue21) {
  // The worst case of the issue's 20,000 pairs: EPA folded its polytope inward and returned
  // 0.99981 m, the true depth being 1.19632 m.
  const Shape capsule = Capsule{Real(0.576800823), Real(0.370391786)};
  const Shape cylinder = Cylinder{Real(0.941023529), Real(0.68927449)};
  const Transform pa{
      Vec3(Real(-0.0103964321), Real(0.88312155), Real(0.635989785)),
      Quat(Real(0.54994452), Real(-0.397933125), Real(0.245029628), Real(-0.692221582))
          .normalized()};
  const Transform pb{
      Vec3(Real(0.440134764), Real(0.56577903), Real(0.277562559)),
      Quat(Real(-0.719216943), Real(-0.585290372), Real(-0.269517094), Real(0.259851187))
          .normalized()};
  const ShapeD a = makeShape(Kind::Capsule, capsule, pa),
               b = makeShape(Kind::Cylinder, cylinder, pb);
  const Reference ref = reference(a, b);
  // The issue's reference depth, 1.19632 m (six digits), lies in the bracket.
  EXPECT_LE(ref.lo, 1.196325);
  EXPECT_GE(ref.hi, 1.196315);
  Tally t;
  checkPair(a, b, t, "issue 21");
  checkPair(b, a, t, "issue 21, swapped");
  const auto p = penetration(Collider(capsule), pa, Collider(cylinder), pb);
  ASSERT_TRUE(p.has_value());
  // Within the documented accuracy of it (plus the half unit of its last digit).
  EXPECT_NEAR(p->depth, 1.19632, kDepthRel * 1.19632 + 5e-6 + kRoundUlps * kEps * 4);
  std::printf("depth %.7f m (reference %.7f .. %.7f m)\n", p->depth, ref.lo, ref.hi);
}

TEST(PenetrationOracle, CapsuleJustIntoACylinderFromClangsDrawOrder) {
  // Capsule-cylinder #1 of the random pairs in the order clang draws Vec3(u(rng), u(rng),
  // u(rng)). The cores are 12 mm apart, inside the capsule's radius; GJK's float signed volumes
  // lost their sign on a thin simplex of the cylinder's rim and stopped at 12.022 mm, 0.3% long,
  // so the depth came out 3.4e-5 m (6e-5 relative) shallow. The floats as drawn.
  const Shape capsule = Capsule{Real(0x1.139056p-1), Real(0x1.1b5e6p-2)};
  const Shape cylinder = Cylinder{Real(0x1.6e8fc2p-1), Real(0x1.ee484p-1)};
  const Transform pa{Vec3(-Real(0x1.17722cp-2), Real(0x1.3078dep-5), Real(0x1.cfd148p-2)),
                     unitAsDrawn(Quat(-Real(0x1.d2a3c6p-2), Real(0x1.25c6bp-4),
                                      -Real(0x1.0b3924p-1), Real(0x1.6f5aaap-1)))};
  const Transform pb{Vec3(Real(0x1.0fadacp-1), -Real(0x1.cfd61cp-2), Real(0x1.1fe1eep-4)),
                     unitAsDrawn(Quat(Real(0x1.8769ap-1), -Real(0x1.8a43aep-2), Real(0x1.03b8d8p-1),
                                      -Real(0x1.99c3a4p-4)))};
  const ShapeD a = makeShape(Kind::Capsule, capsule, pa),
               b = makeShape(Kind::Cylinder, cylinder, pb);
  Tally t;
  checkPair(a, b, t, "capsule-cylinder");
  checkPair(b, a, t, "cylinder-capsule");
  // The cores' distance, GJK's own result, to its documented accuracy (distance.h).
  const Reference ref = reference(a, b);
  const double cores = a.radius - ref.lo;
  const auto g = detail::gjk(detail::ConvexProxy::fromCollider(Collider(capsule), pa),
                             detail::ConvexProxy::fromCollider(Collider(cylinder), pb));
  ASSERT_FALSE(g.overlapping);
  EXPECT_NEAR(g.distance, cores, kDistanceRel * cores + kRoundUlps * kEps * pairScale(a, b));
}

TEST(PenetrationOracle, SphereInCylinderMatchesTheClosedForm) {
  // A sphere whose centre is inside the cylinder: depth r + min(R - rho, h - |y|) exactly.
  std::mt19937_64 rng(2102);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const Cylinder cyl{Real(uniform(rng, 0.3, 1)), Real(uniform(rng, 0.3, 1))};
    const Sphere sphere{Real(uniform(rng, 0.05, 0.5))};
    const Transform pc = randomPose(rng, 0.5);
    const Vec3 local(Real(uniform(rng, -0.7, 0.7) * cyl.radius),
                     Real(uniform(rng, -1, 1) * cyl.halfHeight),
                     Real(uniform(rng, -0.7, 0.7) * cyl.radius));
    const Transform ps{pc.apply(local), Quat::Identity()};
    const Vec3d l = toLocal(pc, ps.p);
    const double rho = std::hypot(l.x(), l.z());
    if (rho >= cyl.radius) continue;
    const double exact =
        sphere.radius + std::min(cyl.radius - rho, cyl.halfHeight - std::abs(l.y()));
    const auto p = penetration(Collider(sphere), ps, Collider(cyl), pc);
    ASSERT_TRUE(p.has_value());
    const double scale = 2 * (cyl.radius + cyl.halfHeight + sphere.radius);
    EXPECT_NEAR(p->depth, exact, kDepthRel * exact + kRoundUlps * kEps * scale) << k;
    ++checked;
  }
  EXPECT_GT(checked, 250);
}
