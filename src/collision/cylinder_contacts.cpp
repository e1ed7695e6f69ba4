// Cylinder pairs: GJK/EPA (gjk.h) give the normal; the supporting features of the two shapes in
// that direction (a cap polygon, a side segment, a face, an edge, a point) are then clipped
// against each other, so a cylinder standing on a box gets its rim, lying on it two points.
#include <algorithm>
#include <cmath>

#include "contact_pairs.h"
#include "gjk.h"
#include "inertia/collision/triangle.h"
#include "local_queries.h"
#include "polyhedron.h"

namespace inertia::detail {

namespace {

constexpr Real kTwoPi = Real(6.283185307179586);

// A supporting feature in the world: a convex polygon (>= 3 points, in loop order), a segment
// (2) or a point (1) of the core, rounded by `radius` (capsules).
struct SupportFeature {
  std::array<Vec3, kMaxClipVertices> p{};
  std::array<std::uint32_t, kMaxClipVertices> key{};
  int count = 0;
  Real radius = 0;
  Vec3 core0 = Vec3::Zero(), core1 = Vec3::Zero();  // a capsule's core segment (world)

  // The surface point facing `u` (unit) from core point p: a capsule's surface needs the
  // hemisphere / cylinder distinction (capsuleOffset); other cores have no radius.
  Vec3 surface(const Vec3& p, const Vec3& u) const {
    if (radius == 0) return p;
    const Real t = p == core0 ? Real(0) : p == core1 ? Real(1) : Real(0.5);
    return p - radius * capsuleOffset(-u, core1 - core0, t);
  }
};

// The supporting feature of a polyhedron view (pose to the world) in world direction d: the
// face most aligned with d when within kCylinderFeatureSine, else an edge of the support
// vertex nearly perpendicular to d, else the vertex.
void polyFeature(const PolyView& v, const Transform& pose, const Vec3& dWorld,
                 SupportFeature& f) {
  const Vec3 d = pose.q.conjugate() * dWorld;
  const Real cosTol = std::sqrt(1 - kCylinderFeatureSine * kCylinderFeatureSine);
  int face = 0;
  for (int k = 1; k < v.faceCount; ++k)
    if (v.faces[k].normal.dot(d) > v.faces[face].normal.dot(d)) face = k;
  if (v.faces[face].normal.dot(d) >= cosTol) {
    const HullFace& hf = v.faces[face];
    for (std::uint32_t k = 0; k < hf.edgeCount && f.count < kMaxClipVertices; ++k) {
      const std::uint32_t vi = v.halfEdges[hf.firstEdge + k].origin;
      f.p[std::size_t(f.count)] = pose.apply(v.vertices[vi]);
      f.key[std::size_t(f.count++)] = featureKey(Feature::Vertex, vi);
    }
    return;
  }
  const int s = v.supportIndex(d);
  f.p[0] = pose.apply(v.vertices[s]);
  f.key[0] = featureKey(Feature::Vertex, std::uint32_t(s));
  f.count = 1;
  for (int e = 0; e < v.edgeCount; ++e) {
    const HullEdge& edge = v.edges[e];
    if (int(edge.v0) != s && int(edge.v1) != s) continue;
    const Vec3 dir = v.edgeDirection(e).normalized();
    if (std::abs(dir.dot(d)) < kCylinderFeatureSine) {
      const std::uint32_t other = int(edge.v0) == s ? edge.v1 : edge.v0;
      f.p[1] = pose.apply(v.vertices[other]);
      f.key[1] = featureKey(Feature::Vertex, other);
      f.count = 2;
      return;
    }
  }
}

// A convex piece: a collider at a pose, or a triangle (world points).
struct Piece {
  const Collider* collider = nullptr;
  Transform pose;
  const Vec3 (*tri)[3] = nullptr;
};

void supportFeature(const Piece& piece, const Vec3& d, SupportFeature& f) {
  f.count = 0;
  f.radius = 0;
  PolyStorage storage;
  if (piece.tri) return polyFeature(makePolyView(*piece.tri, storage), piece.pose, d, f);
  const Shape& shape = piece.collider->shape();
  const Vec3 dl = piece.pose.q.conjugate() * d;
  switch (shape.type()) {
    case ShapeType::Cylinder: {
      std::array<Vec3, kCylinderRimPoints> pts;
      f.count = cylinderSupportFeature(shape.get<Cylinder>(), dl, pts.data(), f.key.data());
      for (int k = 0; k < f.count; ++k) f.p[std::size_t(k)] = piece.pose.apply(pts[std::size_t(k)]);
      return;
    }
    case ShapeType::Capsule: {
      const Capsule& c = shape.get<Capsule>();
      f.radius = c.radius;
      f.core0 = piece.pose.apply(Vec3(0, -c.halfHeight, 0));
      f.core1 = piece.pose.apply(Vec3(0, c.halfHeight, 0));
      const Real along = dl.y() / std::max(dl.norm(), std::numeric_limits<Real>::min());
      const int ends = std::abs(along) < kCylinderFeatureSine ? 2 : 1;
      for (int k = 0; k < ends; ++k) {
        const Real y = (ends == 2 ? (k ? 1 : -1) : (along > 0 ? 1 : -1)) * c.halfHeight;
        f.p[std::size_t(k)] = y > 0 ? f.core1 : f.core0;
        f.key[std::size_t(k)] = featureKey(Feature::Vertex, y > 0 ? 1u : 0u);
      }
      f.count = ends;
      return;
    }
    case ShapeType::Box:
      return polyFeature(makePolyView(shape.get<Box>(), storage), piece.pose, d, f);
    case ShapeType::Hull:
      return polyFeature(makePolyView(shape.get<ConvexHull>()), piece.pose, d, f);
    default: {  // a sphere: its centre
      f.p[0] = piece.pose.p;
      f.radius = shape.get<Sphere>().radius;
      f.count = 1;
    }
  }
}

struct Tagged {
  Vec3 p = Vec3::Zero();
  std::uint32_t tag = 0;  // outgoing edge: incident edge j | kInc, or reference edge i
};
constexpr std::uint32_t kInc = 0x80000000u;

// Points of `inc` (polygon or segment) inside the prism of polygon `ref` (side planes through
// its edges, parallel to n), each with the features of both that made it.
int clipFeatures(const SupportFeature& ref, const SupportFeature& inc, const Vec3& n,
                 std::array<Tagged, kMaxClipVertices>& out) {
  std::array<Tagged, kMaxClipVertices> buf[2];
  int count = inc.count;
  for (int k = 0; k < count; ++k) buf[0][std::size_t(k)] = {inc.p[std::size_t(k)], std::uint32_t(k) | kInc};
  Vec3 centroid = Vec3::Zero();
  for (int k = 0; k < ref.count; ++k) centroid += ref.p[std::size_t(k)];
  centroid /= Real(ref.count);
  int cur = 0;
  for (int i = 0; i < ref.count && count > 0; ++i) {
    const Vec3& v0 = ref.p[std::size_t(i)];
    Vec3 side = (ref.p[std::size_t((i + 1) % ref.count)] - v0).cross(n);
    if (side.dot(centroid - v0) > 0) side = -side;
    const auto& in = buf[cur];
    auto& o = buf[1 - cur];
    int m = 0;
    const auto push = [&](const Vec3& p, std::uint32_t tag) {
      if (m < kMaxClipVertices) o[std::size_t(m++)] = {p, tag};
    };
    if (count == 2) {  // a segment: parametric clip keeps it a segment
      const Real da = side.dot(in[0].p - v0), db = side.dot(in[1].p - v0);
      if (da > 0 && db > 0) { count = 0; break; }
      const Vec3 x = da != db ? Vec3(in[0].p + (da / (da - db)) * (in[1].p - in[0].p)) : in[0].p;
      push(da <= 0 ? in[0].p : x, da <= 0 ? in[0].tag : std::uint32_t(i));
      push(db <= 0 ? in[1].p : x, db <= 0 ? in[1].tag : std::uint32_t(i));
    } else {
      for (int k = 0; k < count; ++k) {
        const Tagged& a = in[std::size_t(k)];
        const Tagged& b = in[std::size_t((k + 1) % count)];
        const Real da = side.dot(a.p - v0), db = side.dot(b.p - v0);
        if (da <= 0) push(a.p, a.tag);
        if ((da <= 0) != (db <= 0))
          push(a.p + (da / (da - db)) * (b.p - a.p), da <= 0 ? std::uint32_t(i) : a.tag);
      }
    }
    count = m;
    cur = 1 - cur;
  }
  for (int k = 0; k < count; ++k) out[std::size_t(k)] = buf[cur][std::size_t(k)];
  return count;
}

// The manifold of two pieces given the normal from GJK/EPA (world, A to B).
bool featureContacts(const Piece& a, const Piece& b, const ConvexSeparation& sep,
                     const ContactSettings& settings, ContactManifold& m) {
  const Vec3 n = sep.normal;
  SupportFeature fa, fb;
  supportFeature(a, n, fa);
  supportFeature(b, -n, fb);
  std::array<ContactCandidate, kMaxClipVertices> pts;
  int count = 0;
  const bool aRef = fa.count >= 3 && fa.count >= fb.count;
  if ((aRef || fb.count >= 3) && std::min(fa.count, fb.count) >= 2) {
    const SupportFeature& ref = aRef ? fa : fb;
    const SupportFeature& inc = aRef ? fb : fa;
    std::array<Tagged, kMaxClipVertices> clipped;
    const int c = clipFeatures(ref, inc, n, clipped);
    // The reference polygon's plane, to measure each point's gap along n.
    Vec3 pn = (ref.p[1] - ref.p[0]).cross(ref.p[2] - ref.p[0]);
    if (pn.dot(n) < 0) pn = -pn;
    const Real pnDotN = pn.dot(n);
    for (int k = 0; k < c && pnDotN > 0; ++k) {
      const Tagged& t = clipped[std::size_t(k)];
      const Tagged& prev = clipped[std::size_t((k + c - 1) % c)];
      const Vec3 onRef = t.p + (pn.dot(ref.p[0] - t.p) / pnDotN) * n;
      // Inc point p minus its projection on ref along n, signed as B - A.
      const Vec3 pa = aRef ? onRef : t.p, pb = aRef ? t.p : onRef;
      ContactCandidate& cc = pts[std::size_t(count)];
      cc.pointA = fa.surface(pa, n);
      cc.pointB = fb.surface(pb, -n);
      cc.separation = (cc.pointB - cc.pointA).dot(n);
      if (cc.separation > settings.speculativeDistance) continue;
      const bool inIn = prev.tag & kInc, outIn = t.tag & kInc;
      const std::uint32_t hi = prev.tag & ~kInc, ho = t.tag & ~kInc;
      std::uint32_t kRef, kInc2;
      if (inIn && outIn) {
        kInc2 = inc.key[ho], kRef = featureKey(Feature::Face, ref.key[0]);
      } else if (!inIn && !outIn) {
        kRef = ref.key[ho], kInc2 = featureKey(Feature::Face, inc.key[0]);
      } else {
        kInc2 = featureKey(Feature::Edge, inc.key[inIn ? hi : ho]);
        kRef = featureKey(Feature::Edge, ref.key[inIn ? ho : hi]);
      }
      cc.id = aRef ? makeId(kRef, kInc2) : makeId(kInc2, kRef);
      ++count;
    }
  } else if (fa.count == 2 && fb.count == 2) {
    // Two segments: parallel ones overlap in two points, others touch in one (GJK's).
    const Vec3 da = fa.p[1] - fa.p[0], db = fb.p[1] - fb.p[0];
    if (da.cross(db).norm() < kCylinderFeatureSine * da.norm() * db.norm()) {
      const Real la2 = da.squaredNorm();
      const Real t0 = (fb.p[0] - fa.p[0]).dot(da) / la2, t1 = (fb.p[1] - fa.p[0]).dot(da) / la2;
      const Real lo = std::max(Real(0), std::min(t0, t1)), hi = std::min(Real(1), std::max(t0, t1));
      for (int k = 0; k < 2 && hi > lo; ++k) {
        const Vec3 onA = fa.p[0] + (k ? hi : lo) * da;
        const Real t = std::clamp((onA - fb.p[0]).dot(db) / db.squaredNorm(), Real(0), Real(1));
        ContactCandidate& cc = pts[std::size_t(count)];
        cc.pointA = fa.surface(onA, n);
        cc.pointB = fb.surface(fb.p[0] + t * db, -n);
        cc.separation = (cc.pointB - cc.pointA).dot(n);
        cc.id = makeId(featureKey(Feature::Edge, fa.key[0]) + std::uint32_t(k),
                       featureKey(Feature::Edge, fb.key[0]));
        if (cc.separation <= settings.speculativeDistance) ++count;
      }
    }
  }
  if (count > 0) return reduceManifold(pts.data(), count, n, Transform::identity(), m);
  if (sep.distance > settings.speculativeDistance) return false;
  // One point: a single-point feature is the exact support point along n (on the surface);
  // otherwise GJK/EPA's witness point, which on the curved cylinder may sit on a chord.
  const Vec3 pa = fa.count == 1 ? fa.surface(fa.p[0], n) : sep.pointA;
  const Vec3 pb = fb.count == 1 ? fb.surface(fb.p[0], -n) : sep.pointB;
  pts[0] = {pa, pb, (pb - pa).dot(n), makeId(fa.key[0], fb.key[0])};
  if (pts[0].separation > settings.speculativeDistance) return false;
  return reduceManifold(pts.data(), 1, n, Transform::identity(), m);
}

ConvexProxy proxyOf(const Piece& piece) {
  if (piece.tri)
    return ConvexProxy::triangle(piece.pose.apply((*piece.tri)[0]),
                                 piece.pose.apply((*piece.tri)[1]),
                                 piece.pose.apply((*piece.tri)[2]));
  return ConvexProxy::fromCollider(*piece.collider, piece.pose);
}

bool collidePieces(const Piece& a, const Piece& b, const ContactSettings& settings,
                   ContactManifold& m) {
  const ConvexSeparation sep = separation(proxyOf(a), proxyOf(b));
  if (sep.distance > settings.speculativeDistance) return false;
  return featureContacts(a, b, sep, settings, m);
}

}  // namespace

int cylinderSupportFeature(const Cylinder& cyl, const Vec3& d, Vec3* points,
                           std::uint32_t* features) {
  const Real len = d.norm();
  const Real h = cyl.halfHeight, r = cyl.radius;
  const Real along = len > 0 ? d.y() / len : Real(1);
  const std::uint32_t cap = along >= 0 ? 1 : 0;
  const Real y = along >= 0 ? h : -h;
  if (std::abs(along) > std::sqrt(1 - kCylinderFeatureSine * kCylinderFeatureSine)) {
    for (int k = 0; k < kCylinderRimPoints; ++k) {
      const Real angle = kTwoPi * Real(k) / Real(kCylinderRimPoints);
      points[k] = Vec3(r * std::cos(angle), y, r * std::sin(angle));
      features[k] = featureKey(Feature::Vertex, cap * kCylinderRimPoints + std::uint32_t(k));
    }
    return kCylinderRimPoints;
  }
  const Vec3 radial = normalizedOr(Vec3(d.x(), 0, d.z()), Vec3::UnitX()) * r;
  const std::uint32_t base = 2 * kCylinderRimPoints;
  if (std::abs(along) < kCylinderFeatureSine) {
    points[0] = radial + Vec3(0, -h, 0);
    points[1] = radial + Vec3(0, h, 0);
    features[0] = featureKey(Feature::Vertex, base);
    features[1] = featureKey(Feature::Vertex, base + 1);
    return 2;
  }
  points[0] = radial + Vec3(0, y, 0);
  features[0] = featureKey(Feature::Vertex, base + cap);
  return 1;
}

bool collideCylinderConvex(const Collider& a, const Transform& poseA, const Collider& b,
                           const Transform& poseB, const ContactSettings& settings,
                           ContactManifold& m) {
  return collidePieces({&a, poseA, nullptr}, {&b, poseB, nullptr}, settings, m);
}

bool collideTriangle(const Vec3 (&tri)[3], const Collider& convex, const Transform& pose,
                     const ContactSettings& settings, ContactManifold& out) {
  out = ContactManifold{};
  PolyStorage storage;
  const PolyView view = makePolyView(tri, storage);
  const Shape& shape = convex.shape();
  switch (shape.type()) {
    case ShapeType::Sphere: {
      const Real r = shape.get<Sphere>().radius;
      const TriangleClosest c = closestPointOnTriangle(pose.p, tri[0], tri[1], tri[2]);
      const Real dist = (pose.p - c.point).norm();
      if (dist - r > settings.speculativeDistance) return false;
      // On the triangle (centre in its plane): the front normal.
      const Vec3 n = normalizedOr(pose.p - c.point, view.faces[0].normal);
      out.normal = n;
      out.pointCount = 1;
      out.points[0] = {c.point, pose.p - r * n, dist - r,
                       makeId(featureKey(Feature::Face, std::uint32_t(c.feature)), 0)};
      return true;
    }
    case ShapeType::Capsule:
      return collidePolyhedronCapsule(view, Transform::identity(), shape.get<Capsule>(), pose,
                                      settings, out);
    case ShapeType::Box: {
      PolyStorage boxStorage;
      return collidePolyhedra(view, Transform::identity(),
                              makePolyView(shape.get<Box>(), boxStorage), pose, settings, out);
    }
    case ShapeType::Hull:
      return collidePolyhedra(view, Transform::identity(),
                              makePolyView(shape.get<ConvexHull>()), pose, settings, out);
    case ShapeType::Cylinder:
      return collidePieces({nullptr, Transform::identity(), &tri}, {&convex, pose, nullptr},
                           settings, out);
    default:
      return false;
  }
}

}  // namespace inertia::detail
