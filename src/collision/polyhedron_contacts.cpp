// Manifolds between polyhedra (box, hull, triangle) and between a polyhedron and a capsule:
// the separating-axis test, then clipping of the incident feature against the reference face.
#include <cmath>

#include "contact_pairs.h"
#include "local_queries.h"
#include "polyhedron.h"

namespace inertia::detail {

namespace {

// `candidate` beats `incumbent` only by a margin: the hysteresis that keeps the chosen axis
// from flip-flopping between nearly equal ones (see collidePolyhedra).
bool clearlyBetter(Real candidate, Real incumbent) {
  return candidate > incumbent + kAxisRelTolerance * std::abs(incumbent) + kAxisAbsTolerance;
}

bool edgeContact(const PolyView& a, const Transform& poseA, const PolyView& b,
                 const Transform& bToA, const EdgeQuery& q, ContactManifold& m) {
  const HullEdge& ea = a.edges[q.edgeA];
  const HullEdge& eb = b.edges[q.edgeB];
  const Vec3 a0 = a.vertices[ea.v0], a1 = a.vertices[ea.v1];
  const Vec3 b0 = bToA.apply(b.vertices[eb.v0]), b1 = bToA.apply(b.vertices[eb.v1]);
  Real s, t;
  closestSegmentPoints(a0, a1, b0, b1, &s, &t);
  ContactCandidate c;
  c.pointA = a0 + s * (a1 - a0);
  c.pointB = b0 + t * (b1 - b0);
  c.separation = (c.pointB - c.pointA).dot(q.axis);
  c.id = makeId(featureKey(Feature::Edge, std::uint32_t(q.edgeA)),
                featureKey(Feature::Edge, std::uint32_t(q.edgeB)));
  return reduceManifold(&c, 1, q.axis, poseA, m);
}

// The closest point of the polyhedron's surface to p, for p outside it: the minimum over the
// faces p sees of the distance to the face polygon (the projection inside the loop, else the
// nearest loop edge), as the hull point query does.
Vec3 closestPointOutside(const PolyView& poly, const Vec3& p) {
  Real bestD2 = std::numeric_limits<Real>::infinity();
  Vec3 best = poly.vertices[0];
  for (int f = 0; f < poly.faceCount; ++f) {
    const HullFace& face = poly.faces[f];
    const Real s = face.normal.dot(p) - face.offset;
    if (s < 0 || s * s >= bestD2) continue;
    const Vec3 projected = p - s * face.normal;
    bool inside = true;
    for (std::uint32_t k = 0; k < face.edgeCount && inside; ++k) {
      const HullHalfEdge& e = poly.halfEdges[face.firstEdge + k];
      const Vec3& v0 = poly.vertices[e.origin];
      const Vec3& v1 = poly.vertices[poly.halfEdges[e.next].origin];
      inside = (v1 - v0).cross(projected - v0).dot(face.normal) >= 0;
    }
    if (inside) {
      bestD2 = s * s, best = projected;
      continue;
    }
    for (std::uint32_t k = 0; k < face.edgeCount; ++k) {
      const HullHalfEdge& e = poly.halfEdges[face.firstEdge + k];
      const Vec3& v0 = poly.vertices[e.origin];
      const Vec3 d = poly.vertices[poly.halfEdges[e.next].origin] - v0;
      const Real len2 = d.squaredNorm();
      const Real t = len2 > 0 ? std::clamp((p - v0).dot(d) / len2, Real(0), Real(1)) : Real(0);
      const Vec3 q = v0 + t * d;
      if ((p - q).squaredNorm() < bestD2) bestD2 = (p - q).squaredNorm(), best = q;
    }
  }
  return best;
}

}  // namespace

Vec3 capsuleOffset(const Vec3& n, const Vec3& axis, Real t) {
  // An end's hemisphere holds the directions pointing away from the segment.
  const Real along = n.dot(axis);
  if ((t <= 0 && along >= 0) || (t >= 1 && along <= 0)) return n;
  const Real a2 = axis.squaredNorm();
  return a2 > 0 ? normalizedOr(n - (along / a2) * axis, n) : n;
}

namespace {

// The manifold from the three SAT queries of a touching pair (none above the speculative
// distance): the reference face clipped, or the closest points of the edge pair.
bool polyhedraManifold(const PolyView& a, const Transform& poseA, const PolyView& b,
                       const Transform& poseB, const Transform& bToA, const Transform& aToB,
                       const FaceQuery& faceA, const FaceQuery& faceB, const EdgeQuery& edge,
                       Real spec, ContactManifold& m) {
  const bool useB = clearlyBetter(faceB.separation, faceA.separation);
  const Real faceSep = useB ? faceB.separation : faceA.separation;
  const bool useEdge = edge.edgeA >= 0 && clearlyBetter(edge.separation, faceSep);
  if (!useEdge) {
    std::array<ContactCandidate, kMaxClipVertices> pts;
    if (!useB) {
      const Vec3& n = a.faces[faceA.face].normal;
      const int inc = incidentFace(b, aToB.rotate(n));
      const int count = clipFaces(a, faceA.face, b, inc, bToA, true, spec, pts.data());
      if (count > 0) return reduceManifold(pts.data(), count, n, poseA, m);
    } else {
      const Vec3& n = b.faces[faceB.face].normal;
      const int inc = incidentFace(a, bToA.rotate(n));
      const int count = clipFaces(b, faceB.face, a, inc, aToB, false, spec, pts.data());
      if (count > 0) return reduceManifold(pts.data(), count, -n, poseB, m);
    }
    // Nothing survived the clip (the faces barely overlap, e.g. edge on edge within the
    // tolerance band): the edge pair describes the contact.
    if (edge.edgeA < 0) return false;
  }
  return edgeContact(a, poseA, b, bToA, edge, m);
}

}  // namespace

bool collidePolyhedra(const PolyView& a, const Transform& poseA, const PolyView& b,
                      const Transform& poseB, const ContactSettings& settings,
                      ContactManifold& m) {
  const Real spec = settings.speculativeDistance;
  const Transform bToA = poseA.inverse() * poseB;
  const Transform aToB = poseB.inverse() * poseA;
  const FaceQuery faceA = queryFaceDirections(a, b, bToA);
  if (faceA.separation > spec) return false;
  const FaceQuery faceB = queryFaceDirections(b, a, aToB);
  if (faceB.separation > spec) return false;
  const EdgeQuery edge = queryEdgeDirections(a, b, bToA);
  if (edge.separation > spec) return false;
  return polyhedraManifold(a, poseA, b, poseB, bToA, aToB, faceA, faceB, edge, spec, m);
}

bool collideBoxes(const Box& boxA, const Transform& poseA, const Box& boxB,
                  const Transform& poseB, const ContactSettings& settings, ContactManifold& m) {
  const Real spec = settings.speculativeDistance;
  // The boxes are at least the centres' distance minus their circumradii apart: such pairs end
  // here, before the fifteen axes. (The world's narrow phase makes the same test on every pair
  // of shapes before it calls a collision function.)
  const Real reach = boxA.halfExtents.norm() + boxB.halfExtents.norm() + spec;
  if ((poseB.p - poseA.p).squaredNorm() > reach * reach) return false;
  const Transform bToA = poseA.inverse() * poseB;
  const BoxBoxQuery q = queryBoxBox(boxA.halfExtents, boxB.halfExtents, bToA, spec);
  if (q.faceA.separation > spec || q.faceB.separation > spec || q.edge.separation > spec)
    return false;
  PolyStorage sa, sb;
  const PolyView a = makePolyView(boxA, sa), b = makePolyView(boxB, sb);
  return polyhedraManifold(a, poseA, b, poseB, bToA, poseB.inverse() * poseA, q.faceA, q.faceB,
                           q.edge, spec, m);
}

bool collidePolyhedronCapsule(const PolyView& a, const Transform& poseA, const Capsule& capsule,
                              const Transform& poseB, const ContactSettings& settings,
                              ContactManifold& m) {
  const Real spec = settings.speculativeDistance, r = capsule.radius;
  const Transform bToA = poseA.inverse() * poseB;
  const Vec3 s0 = bToA.apply(Vec3(0, -capsule.halfHeight, 0));
  const Vec3 s1 = bToA.apply(Vec3(0, capsule.halfHeight, 0));
  const Vec3 d = s1 - s0;

  // SAT of the polyhedron against the core segment: the faces of the Minkowski difference are
  // the polyhedron's faces and the parallelograms edge x segment. The segment's Gauss map is
  // the great circle normal to d, which crosses an edge's arc when n0 . d and n1 . d differ in
  // sign (a flat polygon's half-circle arc always crosses it unless d lies in its plane).
  FaceQuery face;
  for (int f = 0; f < a.faceCount; ++f) {
    const HullFace& hf = a.faces[f];
    const Real s = std::min(hf.normal.dot(s0), hf.normal.dot(s1)) - hf.offset;
    if (s > face.separation) face = {s, f};
  }
  if (face.separation - r > spec) return false;
  EdgeQuery edge;
  for (int i = 0; i < a.edgeCount; ++i) {
    const HullEdge& e = a.edges[i];
    const Real d0 = a.faces[e.face0].normal.dot(d), d1 = a.faces[e.face1].normal.dot(d);
    if (!(d0 * d1 < 0)) continue;
    const Vec3 de = a.edgeDirection(i);
    Vec3 axis = de.cross(d);
    const Real len = axis.norm();
    if (!(len > kParallelSine * de.norm() * d.norm())) continue;
    axis /= len;
    if (axis.dot(a.edgeOutward(i)) < 0) axis = -axis;
    const Real s = axis.dot(s0 - a.vertices[e.v0]);
    if (s > edge.separation) edge = {s, i, 0, axis};
  }
  if (edge.separation - r > spec) return false;

  const std::uint32_t segFeature = featureKey(Feature::Edge, 0);
  const auto finish = [&](ContactCandidate* pts, int count, const Vec3& n) {
    return reduceManifold(pts, count, n, poseA, m);
  };
  const auto pointContact = [&](const Vec3& onPoly, const Vec3& onSeg, const Vec3& n,
                                std::uint32_t polyFeature) {
    ContactCandidate c;
    c.pointA = onPoly;
    Real t = 0.5;  // where onSeg lies on the segment (ends exactly 0 or 1)
    if (onSeg == s0) t = 0;
    if (onSeg == s1) t = 1;
    c.pointB = onSeg - r * capsuleOffset(n, d, t);
    c.separation = (c.pointB - c.pointA).dot(n);
    c.id = makeId(polyFeature, segFeature);
    if (c.separation > spec) return false;
    return finish(&c, 1, n);
  };

  // Face axis: clip the segment to the face's prism (parametric, against each side plane).
  if (edge.edgeA < 0 || !clearlyBetter(edge.separation, face.separation)) {
    const HullFace& hf = a.faces[face.face];
    Real t0 = 0, t1 = 1;
    std::uint32_t f0 = featureKey(Feature::Face, std::uint32_t(face.face)), f1 = f0;
    for (std::uint32_t k = 0; k < hf.edgeCount && t0 <= t1; ++k) {
      const HullHalfEdge& h = a.halfEdges[hf.firstEdge + k];
      const Vec3& v0 = a.vertices[h.origin];
      const Vec3 side = (a.vertices[a.halfEdges[h.next].origin] - v0).cross(hf.normal);
      const Real da = side.dot(s0 - v0), dd = side.dot(d);
      const std::uint32_t feature = featureKey(Feature::Edge, h.edge);
      if (dd == 0) {
        if (da > 0) t1 = -1;  // parallel and outside
      } else if (dd > 0) {    // leaves the prism at t = -da / dd
        const Real t = -da / dd;
        if (t < t1) t1 = t, f1 = feature;
      } else {
        const Real t = -da / dd;
        if (t > t0) t0 = t, f0 = feature;
      }
    }
    if (t0 <= t1) {
      ContactCandidate pts[2];
      int count = 0;
      const Real ts[2] = {t0, t1};
      const std::uint32_t fs[2] = {f0, f1};
      for (int k = 0; k < (t1 > t0 ? 2 : 1); ++k) {
        const Vec3 p = s0 + ts[k] * d;
        // The core point's foot on the face (inside the prism, so on the polyhedron) and the
        // capsule's surface point facing the face; separation along the face normal.
        const Vec3 onCapsule = p - r * capsuleOffset(hf.normal, d, ts[k]);
        const Vec3 onFace = p - (hf.normal.dot(p) - hf.offset) * hf.normal;
        const Real sep = (onCapsule - onFace).dot(hf.normal);
        if (sep > spec) continue;
        ContactCandidate& c = pts[count++];
        c.pointB = onCapsule;
        c.pointA = onFace;
        c.separation = sep;
        c.id = makeId(fs[k], featureKey(Feature::Vertex, std::uint32_t(k)));
      }
      if (count > 0) return finish(pts, count, hf.normal);
    }
  }

  const Real maxSep = std::max(face.separation, edge.separation);
  if (maxSep > 0) {
    // The core is outside: the exact closest points, between an end of the segment and the
    // polyhedron, or between the segment and an edge.
    Vec3 bestPoly = closestPointOutside(a, s0), bestSeg = s0;
    Real bestD2 = (s0 - bestPoly).squaredNorm();
    const Vec3 q1 = closestPointOutside(a, s1);
    if ((s1 - q1).squaredNorm() < bestD2) bestD2 = (s1 - q1).squaredNorm(), bestPoly = q1, bestSeg = s1;
    std::uint32_t polyFeature = featureKey(Feature::Face, std::uint32_t(face.face));
    for (int i = 0; i < a.edgeCount; ++i) {
      const Vec3 v0 = a.vertices[a.edges[i].v0], v1 = a.vertices[a.edges[i].v1];
      Real s, t;
      closestSegmentPoints(s0, s1, v0, v1, &s, &t);
      const Vec3 ps = s0 + s * d, pe = v0 + t * (v1 - v0);
      if ((ps - pe).squaredNorm() < bestD2) {
        bestD2 = (ps - pe).squaredNorm(), bestPoly = pe, bestSeg = ps;
        polyFeature = featureKey(Feature::Edge, std::uint32_t(i));
      }
    }
    const Vec3 n = normalizedOr(bestSeg - bestPoly, a.faces[face.face].normal);
    return pointContact(bestPoly, bestSeg, n, polyFeature);
  }
  if (edge.edgeA >= 0 && edge.separation >= face.separation) {
    const HullEdge& e = a.edges[edge.edgeA];
    const Vec3 v0 = a.vertices[e.v0], v1 = a.vertices[e.v1];
    Real s, t;
    closestSegmentPoints(s0, s1, v0, v1, &s, &t);
    return pointContact(v0 + t * (v1 - v0), s0 + s * d, edge.axis,
                        featureKey(Feature::Edge, std::uint32_t(edge.edgeA)));
  }
  // Deep, with the segment outside the face's prism: its deepest end along the face normal.
  const HullFace& hf = a.faces[face.face];
  const Vec3 p = hf.normal.dot(s0) <= hf.normal.dot(s1) ? s0 : s1;
  return pointContact(p - (hf.normal.dot(p) - hf.offset) * hf.normal, p, hf.normal,
                      featureKey(Feature::Face, std::uint32_t(face.face)));
}

}  // namespace inertia::detail

namespace inertia::detail {

namespace {
PolyView viewOf(const Collider& c, PolyStorage& storage) {
  return c.type() == ShapeType::Box ? makePolyView(c.shape().get<Box>(), storage)
                                    : makePolyView(c.shape().get<ConvexHull>());
}
}  // namespace

bool collidePolyhedronPair(const Collider& a, const Transform& poseA, const Collider& b,
                           const Transform& poseB, const ContactSettings& settings,
                           ContactManifold& m) {
  if (a.type() == ShapeType::Box && b.type() == ShapeType::Box)
    return collideBoxes(a.shape().get<Box>(), poseA, b.shape().get<Box>(), poseB, settings, m);
  PolyStorage sa, sb;
  return collidePolyhedra(viewOf(a, sa), poseA, viewOf(b, sb), poseB, settings, m);
}

}  // namespace inertia::detail
