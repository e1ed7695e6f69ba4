// Polyhedron views of boxes, hulls and triangles, and the separating-axis queries between two
// polyhedra: face directions by support points, edge pairs pruned on the Gauss map (Dirk
// Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "polyhedron.h"

namespace inertia::detail {

namespace {

// Corner k of a box has coordinates (+-hx, +-hy, +-hz) by its bits (bit 0: x, 1: y, 2: z).
// Faces +x, -x, +y, -y, +z, -z, each loop counter-clockwise seen from outside.
constexpr int kBoxQuads[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3},
                                 {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};

struct BoxTopology {
  std::array<HullHalfEdge, 24> halfEdges{};
  std::array<HullEdge, 12> edges{};
};

// Built once: twins by matching reversed half-edges, undirected edges listed from the
// half-edge whose origin is the lower vertex (so face0's loop runs v0 -> v1).
BoxTopology buildBoxTopology() {
  BoxTopology t;
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < 4; ++k) {
      HullHalfEdge& h = t.halfEdges[std::size_t(4 * f + k)];
      h.origin = std::uint32_t(kBoxQuads[f][k]);
      h.next = std::uint32_t(4 * f + (k + 1) % 4);
      h.face = std::uint32_t(f);
    }
  std::uint32_t edgeCount = 0;
  for (std::uint32_t i = 0; i < 24; ++i) {
    HullHalfEdge& h = t.halfEdges[i];
    const std::uint32_t dest = t.halfEdges[h.next].origin;
    for (std::uint32_t j = 0; j < 24; ++j)
      if (t.halfEdges[j].origin == dest && t.halfEdges[t.halfEdges[j].next].origin == h.origin)
        h.twin = j;
    if (h.origin < dest) {
      h.edge = edgeCount;
      t.edges[edgeCount++] = {h.origin, dest, h.face, 0, i};
    }
  }
  for (HullEdge& e : t.edges) e.face1 = t.halfEdges[t.halfEdges[e.halfEdge].twin].face;
  for (HullHalfEdge& h : t.halfEdges)
    if (h.origin > t.halfEdges[h.next].origin) h.edge = t.halfEdges[h.twin].edge;
  return t;
}

const BoxTopology& boxTopology() {
  static const BoxTopology topology = buildBoxTopology();
  return topology;
}

// The index of the box edge along axis i whose lower corner has the bits `corner` (bit i
// clear): boxEdgeIndex()[i][corner].
using BoxEdgeTable = std::array<std::array<int, 8>, 3>;
BoxEdgeTable buildBoxEdgeTable() {
  BoxEdgeTable table{};
  const BoxTopology& t = boxTopology();
  for (int e = 0; e < 12; ++e) {
    const std::uint32_t v0 = t.edges[std::size_t(e)].v0, v1 = t.edges[std::size_t(e)].v1;
    const std::uint32_t bit = v0 ^ v1;  // a box edge changes one coordinate
    const int axis = bit == 1 ? 0 : bit == 2 ? 1 : 2;
    table[std::size_t(axis)][std::min(v0, v1)] = e;
  }
  return table;
}

const BoxEdgeTable& boxEdgeIndex() {
  static const BoxEdgeTable table = buildBoxEdgeTable();
  return table;
}

// Arcs (a0, a1) of edge i of `pa` and (b0, b1) of edge j of `pb` (b's already negated and in
// a's frame) intersect. A flat polygon's arc is half a great circle, which the arc test cannot
// take in one piece (its end points are antipodal): it is split at the edge's outward
// direction into two quarter circles with the same plane normal.
bool edgeArcsIntersect(const PolyView& pa, int i, const Vec3& a0, const Vec3& a1,
                       const Vec3& aNormal, const PolyView& pb, int j, const Vec3& b0,
                       const Vec3& b1, const Vec3& bNormal, const Transform& bToA) {
  // Sub-arcs as (start, end) pairs: one for a solid's edge, two for a flat polygon's.
  Vec3 arcA[3] = {a0, a1, a1}, arcB[3] = {b0, b1, b1};
  const int nA = pa.flat ? 2 : 1, nB = pb.flat ? 2 : 1;
  if (pa.flat) arcA[1] = pa.edgeOutward(i);
  if (pb.flat) arcB[1] = -bToA.rotate(pb.edgeOutward(j));
  for (int x = 0; x < nA; ++x)
    for (int y = 0; y < nB; ++y)
      if (arcsIntersect(arcA[x], arcA[x + 1], aNormal, arcB[y], arcB[y + 1], bNormal))
        return true;
  return false;
}

}  // namespace

int PolyView::supportIndex(const Vec3& d) const {
  int best = 0;
  Real bestDot = vertices[0].dot(d);
  for (int i = 1; i < vertexCount; ++i) {
    const Real dot = vertices[i].dot(d);
    if (dot > bestDot) bestDot = dot, best = i;
  }
  return best;
}

PolyView makePolyView(const ConvexHull& hull) {
  PolyView v;
  v.vertices = hull.vertices().data();
  v.faces = hull.faces().data();
  v.halfEdges = hull.halfEdges().data();
  v.edges = hull.edges().data();
  v.vertexCount = int(hull.vertices().size());
  v.faceCount = int(hull.faces().size());
  v.edgeCount = int(hull.edges().size());
  return v;
}

PolyView makePolyView(const Box& box, PolyStorage& storage) {
  const Vec3& h = box.halfExtents;
  for (int k = 0; k < 8; ++k)
    storage.vertices[std::size_t(k)] =
        Vec3((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  for (int f = 0; f < 6; ++f) {
    Vec3 n = Vec3::Zero();
    n[f / 2] = (f % 2) ? Real(-1) : Real(1);
    storage.faces[std::size_t(f)] = {n, h[f / 2], std::uint32_t(4 * f), 4};
  }
  const BoxTopology& t = boxTopology();
  PolyView v;
  v.vertices = storage.vertices.data();
  v.faces = storage.faces.data();
  v.halfEdges = t.halfEdges.data();
  v.edges = t.edges.data();
  v.vertexCount = 8;
  v.faceCount = 6;
  v.edgeCount = 12;
  return v;
}

PolyView makePolyView(const Vec3 (&tri)[3], PolyStorage& storage) {
  for (int k = 0; k < 3; ++k) storage.vertices[std::size_t(k)] = tri[k];
  Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
  const Real len = n.norm();
  n = len > 0 ? Vec3(n / len) : Vec3::UnitY();
  storage.faces[0] = {n, n.dot(tri[0]), 0, 3};
  storage.faces[1] = {-n, -n.dot(tri[0]), 3, 3};
  // Front loop 0 -> 1 -> 2 (half-edges 0..2, half-edge k = edge k); back loop 0 -> 2 -> 1
  // (half-edge 3 + j runs from back[j] to back[j + 1]).
  constexpr std::uint32_t back[3] = {0, 2, 1};
  for (std::uint32_t k = 0; k < 3; ++k) {
    storage.halfEdges[k] = {k, (k + 1) % 3, 0, 0, k};
    storage.edges[k] = {k, (k + 1) % 3, 0, 1, k};
  }
  for (std::uint32_t j = 0; j < 3; ++j) {
    const std::uint32_t from = back[j], to = back[(j + 1) % 3];
    // The front edge to -> from is edge `to` when from == (to + 1) % 3.
    const std::uint32_t edge = (to + 1) % 3 == from ? to : from;
    storage.halfEdges[3 + j] = {from, 3 + (j + 1) % 3, edge, 1, edge};
    storage.halfEdges[edge].twin = 3 + j;
  }
  PolyView v;
  v.vertices = storage.vertices.data();
  v.faces = storage.faces.data();
  v.halfEdges = storage.halfEdges.data();
  v.edges = storage.edges.data();
  v.vertexCount = 3;
  v.faceCount = 2;
  v.edgeCount = 3;
  v.flat = true;
  return v;
}

FaceQuery queryFaceDirections(const PolyView& a, const PolyView& b, const Transform& bToA) {
  FaceQuery best;
  for (int f = 0; f < a.faceCount; ++f) {
    const HullFace& face = a.faces[f];
    // b's deepest point along -n, found in b's frame.
    const Vec3 dirB = bToA.q.conjugate() * (-face.normal);
    const Vec3 p = bToA.apply(b.vertices[b.supportIndex(dirB)]);
    const Real s = face.normal.dot(p) - face.offset;
    if (s > best.separation) best = {s, f};
  }
  return best;
}

EdgeQuery queryEdgeDirections(const PolyView& a, const PolyView& b, const Transform& bToA) {
  // B's face normals, edge directions and edge origins in A's frame, transformed once rather
  // than once per edge pair (a box pair has 144 pairs and 12 edges).
  thread_local std::vector<Vec3> normalsB, directionsB, originsB;
  const Mat3 R = bToA.q.toRotationMatrix();
  normalsB.resize(std::size_t(b.faceCount));
  for (int f = 0; f < b.faceCount; ++f) normalsB[std::size_t(f)] = R * b.faces[f].normal;
  directionsB.resize(std::size_t(b.edgeCount));
  originsB.resize(std::size_t(b.edgeCount));
  for (int j = 0; j < b.edgeCount; ++j) {
    directionsB[std::size_t(j)] = R * b.edgeDirection(j);
    originsB[std::size_t(j)] = R * b.vertices[b.edges[j].v0] + bToA.p;
  }
  // Between two solids the arc test's first condition, B's arc crossing the plane of A's arc,
  // is the sign change of n . dA between B's two face normals: taken once per face of B for
  // each edge of A (F_B dot products instead of 2 E_B), it rejects most pairs with a multiply.
  // The products are the very ones arcsIntersect forms ((-n) . (-d) = n . d exactly).
  // The candidates are gathered without branching (a stored index advances only when the
  // test passes), so the unpredictable test costs no mispredicted jumps.
  thread_local std::vector<Real> sideB;
  thread_local std::vector<int> candidates;
  const bool presort = !a.flat && !b.flat;
  sideB.resize(std::size_t(b.faceCount));
  candidates.resize(std::size_t(b.edgeCount));
  EdgeQuery best;
  for (int i = 0; i < a.edgeCount; ++i) {
    const HullEdge& ea = a.edges[i];
    const Vec3& na0 = a.faces[ea.face0].normal;
    const Vec3& na1 = a.faces[ea.face1].normal;
    const Vec3 pa = a.vertices[ea.v0];
    const Vec3 da = a.edgeDirection(i);
    const Vec3 outA = a.edgeOutward(i);
    int count = 0;
    if (presort) {
      for (int f = 0; f < b.faceCount; ++f) sideB[std::size_t(f)] = normalsB[std::size_t(f)].dot(da);
      for (int j = 0; j < b.edgeCount; ++j) {
        candidates[std::size_t(count)] = j;
        count += sideB[b.edges[j].face0] * sideB[b.edges[j].face1] < 0;
      }
    } else {
      for (int j = 0; j < b.edgeCount; ++j) candidates[std::size_t(count++)] = j;
    }
    for (int c = 0; c < count; ++c) {
      const int j = candidates[std::size_t(c)];
      const HullEdge& eb = b.edges[j];
      const Vec3& nb0 = normalsB[eb.face0];
      const Vec3& nb1 = normalsB[eb.face1];
      const Vec3& db = directionsB[std::size_t(j)];
      // For a convex edge v0 -> v1 on face0, n1 x n0 = -(v1 - v0) (up to a positive factor);
      // the arcs of B are negated (Minkowski difference A - B): (-nb1) x (-nb0) = -db.
      if (!edgeArcsIntersect(a, i, na0, na1, -da, b, j, -nb0, -nb1, -db, bToA)) continue;
      Vec3 axis = da.cross(db);
      const Real len = axis.norm();
      if (!(len > kParallelSine * da.norm() * db.norm())) continue;
      axis /= len;
      const Real side = axis.dot(outA);
      if (side == 0) continue;
      if (side < 0) axis = -axis;
      const Real s = axis.dot(originsB[std::size_t(j)] - pa);
      if (s > best.separation) best = {s, i, j, axis};
    }
  }
  return best;
}

BoxBoxQuery queryBoxBox(const Vec3& hA, const Vec3& hB, const Transform& bToA, Real stopAbove) {
  // R's columns are B's axes in A's frame; t is B's centre. |R| with a small bias would be the
  // Gottschalk-style guard against parallel axes; the edge axes below skip those instead.
  const Mat3 R = bToA.q.toRotationMatrix();
  const Mat3 absR = R.cwiseAbs();
  const Vec3& t = bToA.p;
  const Vec3 tB = R.transpose() * (-t);  // A's centre in B's frame
  BoxBoxQuery q;
  // Face i of A (normal s e_i, s the sign of t_i): s t_i - hA_i - sum_j |R_ij| hB_j, the
  // separation of B's deepest corner along -s e_i; faces 2i (+) and 2i + 1 (-) as in
  // makePolyView, the + face on a tie as queryFaceDirections picks it.
  const Vec3 radiiBinA = absR * hB, radiiAinB = absR.transpose() * hA;
  for (int i = 0; i < 3; ++i) {
    const Real s = std::abs(t[i]) - hA[i] - radiiBinA[i];
    if (s > q.faceA.separation) q.faceA = {s, 2 * i + (t[i] < 0 ? 1 : 0)};
    const Real sb = std::abs(tB[i]) - hB[i] - radiiAinB[i];
    if (sb > q.faceB.separation) q.faceB = {sb, 2 * i + (tB[i] < 0 ? 1 : 0)};
  }
  if (q.faceA.separation > stopAbove || q.faceB.separation > stopAbove) return q;
  // Edge axes c = e_i x b_j (b_j = R e_j, B's axis j in A's frame): of the 16 parallel edge
  // pairs of each direction pair, the two whose Gauss-map arcs cross build the Minkowski faces
  // with normals +-c, and the larger separation is |c . t| - r_A - r_B over |c| (Gottschalk's
  // OBB-tree closed forms). Evaluated for all nine without branching on the data, which is
  // what makes it fast; the supporting edges are found for the best axis only.
  const Real inf = std::numeric_limits<Real>::infinity();
  Real best = -inf;
  int bi = -1, bj = -1;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      // c = (.., -R(i2, j) at i1, R(i1, j) at i2) in A's frame; in B's frame it is
      // (R(i, j2) at j1, -R(i, j1) at j2), since e_i . (b_j x b_k) gives its components.
      const Real ct = R(i1, j) * t[i2] - R(i2, j) * t[i1];
      const Real rA = hA[i1] * absR(i2, j) + hA[i2] * absR(i1, j);
      const Real rB = hB[j1] * absR(i, j2) + hB[j2] * absR(i, j1);
      const Real len = std::sqrt(R(i1, j) * R(i1, j) + R(i2, j) * R(i2, j));
      // Nearly parallel pairs are skipped with the general query's sine cut (unit directions).
      const Real s = len > kParallelSine ? (std::abs(ct) - rA - rB) / len : -inf;
      const bool better = s > best;
      best = better ? s : best;
      bi = better ? i : bi;
      bj = better ? j : bj;
    }
  }
  if (bi >= 0) {
    const int i1 = (bi + 1) % 3, i2 = (bi + 2) % 3, j1 = (bj + 1) % 3, j2 = (bj + 2) % 3;
    Vec3 u = Vec3::Zero(), uB = Vec3::Zero();
    u[i1] = -R(i2, bj), u[i2] = R(i1, bj);
    uB[j1] = R(bi, j2), uB[j2] = -R(bi, j1);
    // Unit, and pointing from A towards B (the larger of the two separations).
    const Real scale = (u.dot(t) < 0 ? Real(-1) : Real(1)) / u.norm();
    u *= scale, uB *= scale;
    // A's edge supports u, B's edge supports -u: the corner bits off the edge's own axis.
    const int cornerA = (u[i1] > 0 ? 1 << i1 : 0) | (u[i2] > 0 ? 1 << i2 : 0);
    const int cornerB = (uB[j1] < 0 ? 1 << j1 : 0) | (uB[j2] < 0 ? 1 << j2 : 0);
    const BoxEdgeTable& edges = boxEdgeIndex();
    q.edge = {best, edges[std::size_t(bi)][std::size_t(cornerA)],
              edges[std::size_t(bj)][std::size_t(cornerB)], u};
  }
  return q;
}

}  // namespace inertia::detail
