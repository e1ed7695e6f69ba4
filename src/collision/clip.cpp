// Face clipping (Sutherland-Hodgman) with feature tracking, manifold reduction to four points,
// and the closest points of two segments.
#include <algorithm>
#include <cmath>
#include <limits>

#include "polyhedron.h"

namespace inertia::detail {

namespace {

// A vertex of the polygon being clipped and the tag of its outgoing edge: a half-edge of the
// incident face (kIncidentTag set) or of the reference face whose side plane made the edge.
// A vertex's features are its incoming and outgoing tags, which is what keeps ids stable: they
// name the edges of the two faces that cut it, not its position in the arrays.
struct ClipVertex {  // uninitialised, as ContactCandidate: push() sets both
  Vec3 p;
  std::uint32_t tag;
};
constexpr std::uint32_t kIncidentTag = 0x80000000u;

struct ClipPolygon {
  std::array<ClipVertex, kMaxClipVertices> v;  // the first `count` are set
  int count = 0;
  void push(const Vec3& p, std::uint32_t tag) {
    if (count < kMaxClipVertices) v[std::size_t(count++)] = {p, tag};
  }
};

// Keeps the part of `in` with n . p <= offset; the edge along the plane gets `planeTag`.
void clipPolygon(const ClipPolygon& in, const Vec3& n, Real offset, std::uint32_t planeTag,
                 ClipPolygon& out) {
  out.count = 0;
  if (in.count == 0) return;
  // Edges (a, b) = (v[i], v[i + 1]), the last closing the loop; each vertex's plane distance
  // is computed once (no modulo: an integer division per vertex cost more than the clipping).
  Real db = n.dot(in.v[0].p) - offset;
  for (int i = 0; i < in.count; ++i) {
    const ClipVertex& a = in.v[std::size_t(i)];
    const ClipVertex& b = in.v[std::size_t(i + 1 < in.count ? i + 1 : 0)];
    const Real da = db;
    db = n.dot(b.p) - offset;
    if (da <= 0) {
      if (db <= 0) {
        out.push(a.p, a.tag);
      } else {  // leaving: a, then the crossing, whose outgoing edge runs along the plane
        out.push(a.p, a.tag);
        out.push(a.p + (da / (da - db)) * (b.p - a.p), planeTag);
      }
    } else if (db <= 0) {  // entering: the crossing continues along a's edge
      out.push(a.p + (da / (da - db)) * (b.p - a.p), a.tag);
    }
  }
}

std::uint32_t destination(const PolyView& poly, std::uint32_t h) {
  return poly.halfEdges[poly.halfEdges[h].next].origin;
}

}  // namespace

int incidentFace(const PolyView& poly, const Vec3& direction) {
  int best = 0;
  Real bestDot = poly.faces[0].normal.dot(direction);
  for (int f = 1; f < poly.faceCount; ++f) {
    const Real d = poly.faces[f].normal.dot(direction);
    if (d < bestDot) bestDot = d, best = f;
  }
  return best;
}

int clipFaces(const PolyView& ref, int refFace, const PolyView& inc, int incFace,
              const Transform& incToRef, bool refIsA, Real speculativeDistance,
              ContactCandidate* out) {
  ClipPolygon polys[2];
  const HullFace& fi = inc.faces[incFace];
  for (std::uint32_t k = 0; k < fi.edgeCount; ++k) {
    const std::uint32_t h = fi.firstEdge + k;
    polys[0].push(incToRef.apply(inc.vertices[inc.halfEdges[h].origin]), h | kIncidentTag);
  }
  const HullFace& fr = ref.faces[refFace];
  int cur = 0;
  for (std::uint32_t k = 0; k < fr.edgeCount && polys[cur].count > 0; ++k) {
    const std::uint32_t h = fr.firstEdge + k;
    const Vec3& v0 = ref.vertices[ref.halfEdges[h].origin];
    const Vec3& v1 = ref.vertices[destination(ref, h)];
    const Vec3 side = (v1 - v0).cross(fr.normal);  // outward side-plane normal of the edge
    clipPolygon(polys[cur], side, side.dot(v0), h, polys[1 - cur]);
    cur = 1 - cur;
  }

  const ClipPolygon& poly = polys[cur];
  int count = 0;
  for (int i = 0; i < poly.count; ++i) {
    const ClipVertex& v = poly.v[std::size_t(i)];
    const Real sep = fr.normal.dot(v.p) - fr.offset;
    if (sep > speculativeDistance) continue;
    const std::uint32_t tagIn = poly.v[std::size_t(i > 0 ? i - 1 : poly.count - 1)].tag;
    const std::uint32_t tagOut = v.tag;
    const bool inIncident = tagIn & kIncidentTag, outIncident = tagOut & kIncidentTag;
    const std::uint32_t hIn = tagIn & ~kIncidentTag, hOut = tagOut & ~kIncidentTag;
    std::uint32_t featureRef, featureInc;
    if (inIncident && outIncident) {  // a vertex of the incident face
      featureInc = featureKey(Feature::Vertex, inc.halfEdges[hOut].origin);
      featureRef = featureKey(Feature::Face, std::uint32_t(refFace));
    } else if (!inIncident && !outIncident) {  // a corner of the reference face
      std::uint32_t corner = ref.halfEdges[hOut].origin;
      if (ref.halfEdges[hIn].origin == destination(ref, hOut)) corner = ref.halfEdges[hIn].origin;
      if (destination(ref, hIn) == ref.halfEdges[hOut].origin) corner = ref.halfEdges[hOut].origin;
      featureRef = featureKey(Feature::Vertex, corner);
      featureInc = featureKey(Feature::Face, std::uint32_t(incFace));
    } else {  // an incident edge crossing a reference side plane
      const std::uint32_t hInc = inIncident ? hIn : hOut, hRef = inIncident ? hOut : hIn;
      featureInc = featureKey(Feature::Edge, inc.halfEdges[hInc].edge);
      featureRef = featureKey(Feature::Edge, ref.halfEdges[hRef].edge);
    }
    ContactCandidate& c = out[count++];
    const Vec3 onRef = v.p - sep * fr.normal;
    c.separation = sep;
    if (refIsA) {
      c.pointA = onRef, c.pointB = v.p, c.id = makeId(featureRef, featureInc);
    } else {
      c.pointA = v.p, c.pointB = onRef, c.id = makeId(featureInc, featureRef);
    }
  }
  return count;
}

int spanningFour(const ContactCandidate* points, const int* index, int n, const Vec3& normal,
                 bool flatTies, std::array<int, 4>& keep) {
  const auto at = [&](int i) -> const Vec3& { return points[index[i]].pointB; };
  const auto depth = [&](int i) { return points[index[i]].separation; };
  int kept = 0;
  if (n <= 4) {
    for (int i = 0; i < n; ++i) keep[std::size_t(kept++)] = index[i];
    return kept;
  }
  // 1. the deepest point; 2. the farthest from it; 3., 4. the largest triangles with that
  // segment on either side (signed areas about the normal).
  int i0 = 0;
  for (int i = 1; i < n; ++i)
    if (depth(i) < depth(i0)) i0 = i;
  if (flatTies) {
    // Among points as deep up to rounding, the one farthest from their centroid.
    Real scale = 0;
    Vec3 centroid = Vec3::Zero();
    for (int i = 0; i < n; ++i) {
      scale = std::max(scale, at(i).cwiseAbs().maxCoeff());
      centroid += at(i);
    }
    centroid /= Real(n);
    const Real tie = depth(i0) + 100 * std::numeric_limits<Real>::epsilon() * (1 + scale);
    for (int i = 0; i < n; ++i)
      if (depth(i) <= tie && (at(i) - centroid).squaredNorm() > (at(i0) - centroid).squaredNorm())
        i0 = i;
  }
  int i1 = i0 == 0 ? 1 : 0;
  for (int i = 0; i < n; ++i)
    if ((at(i) - at(i0)).squaredNorm() > (at(i1) - at(i0)).squaredNorm()) i1 = i;
  const Vec3 base = at(i1) - at(i0);
  int iPos = -1, iNeg = -1;
  Real aPos = 0, aNeg = 0;
  for (int i = 0; i < n; ++i) {
    const Real area = base.cross(at(i) - at(i0)).dot(normal);
    if (area > aPos) aPos = area, iPos = i;
    if (area < aNeg) aNeg = area, iNeg = i;
  }
  keep[std::size_t(kept++)] = index[i0];
  keep[std::size_t(kept++)] = index[i1];
  if (iPos >= 0) keep[std::size_t(kept++)] = index[iPos];
  if (iNeg >= 0) keep[std::size_t(kept++)] = index[iNeg];
  return kept;
}

int selectContacts(const ContactCandidate* points, int count, const Vec3& normal,
                   std::array<int, 4>& keep) {
  // Unique ids only (a degenerate clip may repeat a feature pair).
  std::array<int, kMaxClipVertices> idx;  // the first n are set
  int n = 0;
  for (int i = 0; i < count && n < kMaxClipVertices; ++i) {
    bool seen = false;
    for (int j = 0; j < n && !seen; ++j) seen = points[idx[std::size_t(j)]].id == points[i].id;
    if (!seen) idx[std::size_t(n++)] = i;
  }
  return spanningFour(points, idx.data(), n, normal, false, keep);
}

bool reduceManifold(const ContactCandidate* points, int count, const Vec3& normalLocal,
                    const Transform& pose, ContactManifold& m) {
  std::array<int, 4> keep{};
  const int kept = selectContacts(points, count, normalLocal, keep);
  m.normal = pose.rotate(normalLocal).normalized();
  m.pointCount = kept;
  for (int k = 0; k < kept; ++k) {
    const ContactCandidate& c = points[keep[std::size_t(k)]];
    ContactPoint& p = m.points[std::size_t(k)];
    p.pointA = pose.apply(c.pointA);
    p.pointB = pose.apply(c.pointB);
    p.separation = c.separation;
    p.id = c.id;
  }
  return kept > 0;
}

void closestSegmentPoints(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                          Real* sOut, Real* tOut) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const Real a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  Real s = 0, t = 0;
  if (a <= 0 && e <= 0) {
  } else if (a <= 0) {
    t = std::clamp(f / e, Real(0), Real(1));
  } else {
    const Real c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, Real(0), Real(1));
    } else {
      const Real b = d1.dot(d2), denom = a * e - b * b;
      // Parallel segments (denom 0): any s works; take 0 and let t follow.
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, Real(0), Real(1)) : Real(0);
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0, s = std::clamp(-c / a, Real(0), Real(1));
      } else if (t > 1) {
        t = 1, s = std::clamp((b - c) / a, Real(0), Real(1));
      }
    }
  }
  *sOut = s;
  *tOut = t;
}

}  // namespace inertia::detail
