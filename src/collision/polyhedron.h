// Internal: a polyhedron as the separating-axis test and face clipping see it, and those two
// algorithms. A box, a convex hull and a single triangle (a flat, two-sided polyhedron with a
// front and a back face) all present the same view, so one SAT and one clipper serve the
// box-box, box-hull, hull-hull, capsule-polyhedron and triangle-convex pairs.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include "inertia/collision/contact.h"
#include "inertia/core/types.h"
#include "inertia/geometry/hull.h"
#include "inertia/geometry/shapes.h"

namespace inertia::detail {

/// Vertices, face planes with their loops, half-edges and undirected edges, with the same
/// conventions as ConvexHull (loops counter-clockwise about the outward normal; HullEdge v0 -> v1
/// runs along face0's loop). A hull's view points into the hull; a box's and a triangle's into
/// the PolyStorage they were made with (which must outlive the view).
struct PolyView {
  const Vec3* vertices = nullptr;
  const HullFace* faces = nullptr;
  const HullHalfEdge* halfEdges = nullptr;
  const HullEdge* edges = nullptr;
  int vertexCount = 0;
  int faceCount = 0;
  int edgeCount = 0;
  /// A triangle: faces 0 (front) and 1 (back) are antipodal, so an edge's Gauss-map arc is the
  /// half great circle from n through the edge's outward in-plane direction to -n.
  bool flat = false;

  Vec3 edgeDirection(int e) const { return vertices[edges[e].v1] - vertices[edges[e].v0]; }
  /// A direction on the edge's Gauss-map arc, strictly between its two face normals: the
  /// outward direction of the edge (n0 + n1; for a flat polygon the in-plane outward normal).
  Vec3 edgeOutward(int e) const {
    const HullEdge& edge = edges[e];
    if (flat) return edgeDirection(e).cross(faces[edge.face0].normal);
    return faces[edge.face0].normal + faces[edge.face1].normal;
  }
  /// The vertex of largest d . v (brute force; boxes have 8, triangles 3).
  int supportIndex(const Vec3& d) const;
};

/// Storage for the views of shapes that are not stored as half-edge meshes.
struct PolyStorage {
  std::array<Vec3, 8> vertices{};
  std::array<HullFace, 6> faces{};
  std::array<HullHalfEdge, 6> halfEdges{};  // a triangle's (a box's topology is shared, static)
  std::array<HullEdge, 3> edges{};
};

PolyView makePolyView(const ConvexHull& hull);
PolyView makePolyView(const Box& box, PolyStorage& storage);
/// The triangle (a, b, c): face 0 has normal (b - a) x (c - a) (normalised), face 1 the
/// opposite; edge k runs from vertex k to vertex (k + 1) % 3 as in TriangleMesh. A degenerate
/// triangle (zero area) gets an arbitrary unit normal; its SAT is then only approximate.
PolyView makePolyView(const Vec3 (&tri)[3], PolyStorage& storage);

// ---- Feature ids ---------------------------------------------------------------------------
// A ContactPoint::id is (feature of A) << 16 | (feature of B); a feature is a type in the top 2
// bits and an index in the low 14 (indices wrap past 16383: ids may then collide, and the
// manifold drops the duplicate).
enum class Feature : std::uint32_t { None = 0, Vertex = 1, Edge = 2, Face = 3 };
constexpr std::uint32_t featureKey(Feature type, std::uint32_t index) {
  return (static_cast<std::uint32_t>(type) << 14) | (index & 0x3fffu);
}
constexpr std::uint32_t makeId(std::uint32_t featureA, std::uint32_t featureB) {
  return (featureA << 16) | (featureB & 0xffffu);
}
constexpr std::uint32_t flipId(std::uint32_t id) { return (id >> 16) | (id << 16); }

// ---- Separating-axis queries ----------------------------------------------------------------
// Everything in A's local frame; `bToA` maps B's local frame into it.

struct FaceQuery {
  Real separation = -std::numeric_limits<Real>::infinity();
  int face = -1;  ///< The face of the first polyhedron with the largest separation.
};
/// max over the faces f of `a` of n_f . s_b(-n_f) - offset_f, with s_b the support of `b`:
/// the separation along each face normal of a (Gregorius 2013).
FaceQuery queryFaceDirections(const PolyView& a, const PolyView& b, const Transform& bToA);

struct EdgeQuery {
  Real separation = -std::numeric_limits<Real>::infinity();
  int edgeA = -1, edgeB = -1;
  Vec3 axis = Vec3::Zero();  ///< Unit, in A's frame, pointing from A towards B.
};
/// The largest separation along eA x eB over the pairs of edges whose Gauss-map arcs cross
/// (they build a face of the Minkowski difference: Gregorius, GDC 2013); the other pairs give
/// no supporting axis and are pruned. Nearly parallel pairs (sine below kParallelSine) are
/// skipped: their axis is ill-conditioned and the adjacent face normals cover it.
EdgeQuery queryEdgeDirections(const PolyView& a, const PolyView& b, const Transform& bToA);
inline constexpr Real kParallelSine = Real(1e-4);

/// The three queries of two boxes (half extents hA, hB) in closed form: faces from |t| and |R|
/// (the 6 face axes of the seeds' 15-axis OBB test), and the 9 edge-pair axes e_i x R e_j with
/// their supporting edges, instead of the 144 edge pairs of queryEdgeDirections. Same
/// conventions and face/edge indices as the general queries on makePolyView(Box) views.
/// When a face axis separates the boxes by more than `stopAbove`, the nine edge axes are not
/// evaluated and `edge` stays empty (most pairs of a rain's overlapping fat boxes end there).
struct BoxBoxQuery {
  FaceQuery faceA, faceB;
  EdgeQuery edge;
};
BoxBoxQuery queryBoxBox(const Vec3& hA, const Vec3& hB, const Transform& bToA,
                        Real stopAbove = std::numeric_limits<Real>::infinity());

/// Gauss-map arcs (a, b) and (c, d) intersect on the unit sphere; bxa and dxc are the normals of
/// the arcs' planes (b x a and d x c for arcs shorter than half a circle; given explicitly so a
/// half great circle, as a flat polygon's edge has, is defined by its orientation).
inline bool arcsIntersect(const Vec3& a, const Vec3& b, const Vec3& bxa, const Vec3& c,
                          const Vec3& d, const Vec3& dxc) {
  const Real cba = c.dot(bxa), dba = d.dot(bxa), adc = a.dot(dxc), bdc = b.dot(dxc);
  // c and d on opposite sides of plane(a, b), a and b on opposite sides of plane(c, d), and
  // the crossing on the same hemisphere (not the antipodal point of the two great circles).
  return cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0;
}

// ---- Contact construction ----------------------------------------------------------------

/// A candidate contact point in a local frame, before reduction. Left uninitialised (arrays of
/// kMaxClipVertices of them sit on the stack of every polyhedron pair, and zeroing them cost
/// more than the box-box SAT): whoever fills one sets all four members.
struct ContactCandidate {
  Vec3 pointA;
  Vec3 pointB;
  Real separation;
  std::uint32_t id;
};

/// Capacity of the fixed-size clipping polygons: an incident face clipped by a reference face
/// gains at most one vertex per side plane; a face pair past this loses the excess vertices
/// (the manifold is then a subset of the true contact polygon, still valid).
inline constexpr int kMaxClipVertices = 64;

/// The indices of at most four of `points` (unique ids) that keep the deepest and span the
/// largest area: the deepest, the farthest from it, then the largest triangles on either side
/// of that line (areas about `normal`). Returns how many.
int selectContacts(const ContactCandidate* points, int count, const Vec3& normal,
                   std::array<int, 4>& keep);

/// The rule of selectContacts on points[index[0..n)] (unique ids already), writing indices into
/// `points`. With `flatTies`, the deepest point is chosen among those as deep up to rounding as
/// the one farthest from their centroid, so that a face lying flat keeps its corners.
int spanningFour(const ContactCandidate* points, const int* index, int n, const Vec3& normal,
                 bool flatTies, std::array<int, 4>& keep);

/// Writes into m the at most four of `points` that keep the deepest and span the largest area
/// (deepest, farthest from it, then the largest triangles on either side of that line), mapped
/// from A's frame to the world by poseA; duplicates by id are dropped. Returns m.pointCount > 0.
bool reduceManifold(const ContactCandidate* points, int count, const Vec3& normalLocal,
                    const Transform& poseA, ContactManifold& m);

/// Contacts of a face pair: the incident face `incFace` of `inc` clipped against the side
/// planes of the reference face `refFace` of `ref` (Sutherland-Hodgman), the points below the
/// reference plane + speculativeDistance kept. Frame of `ref`; `incToRef` maps inc's frame into
/// it. `refIsA` says which shape the reference belongs to (points and ids ordered as A, B).
/// Writes candidates into out (capacity kMaxClipVertices); returns their count.
int clipFaces(const PolyView& ref, int refFace, const PolyView& inc, int incFace,
              const Transform& incToRef, bool refIsA, Real speculativeDistance,
              ContactCandidate* out);

/// The face of `poly` whose normal is most anti-parallel to `direction` (its own frame).
int incidentFace(const PolyView& poly, const Vec3& direction);

/// Closest points of segments p0 + s (p1 - p0) and q0 + t (q1 - q0), s, t in [0, 1]
/// (Ericson, Real-Time Collision Detection, 5.1.9). Never NaN for finite input.
void closestSegmentPoints(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                          Real* s, Real* t);

/// The manifold between two polyhedra: SAT, then face clipping or the closest points of the
/// edge pair. Face axes are preferred over edge axes, and A's faces over B's, unless the other
/// is better by a relative kAxisRelTolerance plus kAxisAbsTolerance (Gregorius 2013): within
/// that band the normal does not flip-flop from step to step between nearly equal axes, at the
/// cost of a depth up to that much above the minimum overlap.
bool collidePolyhedra(const PolyView& a, const Transform& poseA, const PolyView& b,
                      const Transform& poseB, const ContactSettings& settings,
                      ContactManifold& m);
/// collidePolyhedra for two boxes, with the closed-form queries of queryBoxBox.
bool collideBoxes(const Box& boxA, const Transform& poseA, const Box& boxB,
                  const Transform& poseB, const ContactSettings& settings, ContactManifold& m);
inline constexpr Real kAxisRelTolerance = Real(0.05);
inline constexpr Real kAxisAbsTolerance = Real(0.5e-3);  // m

/// The capsule's surface point facing -n from core point p (segment parameter t, exactly 0 or 1
/// at the ends, direction `axis`) is p - radius * capsuleOffset(n, axis, t): n where an end's
/// hemisphere faces -n, else n without its axial component (the cylindrical part), so the
/// point lies on the surface also when the segment is tilted against n.
Vec3 capsuleOffset(const Vec3& n, const Vec3& axis, Real t);

/// The manifold between a polyhedron (A) and a capsule (B): SAT of the polyhedron against the
/// capsule's core segment (face normals, edge x segment axes), the segment clipped against the
/// reference face (two points when lying on it) or the closest points (one point).
bool collidePolyhedronCapsule(const PolyView& a, const Transform& poseA, const Capsule& capsule,
                              const Transform& poseB, const ContactSettings& settings,
                              ContactManifold& m);

}  // namespace inertia::detail
