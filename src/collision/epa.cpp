// Expanding polytope algorithm (van den Bergen, GDC 2001 / "Collision Detection in Interactive
// 3D Environments", 2003, 4.3): the penetration depth of two overlapping convex cores as the
// distance from the origin to the boundary of their Minkowski difference A - B.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "gjk.h"
#include "local_queries.h"

namespace inertia::detail {

namespace {

constexpr int kMaxVertices = 128;
// A closed triangulated polytope with V vertices has 2V - 4 faces; the slack absorbs the
// transient faces of a horizon made ragged by rounding.
constexpr int kMaxFaces = 2 * kMaxVertices + 8;

constexpr Real kEps = std::numeric_limits<Real>::epsilon();
// Stop when the new support point lies within this fraction of the depth (plus an absolute
// term, below) of the nearest face: polytopes stop exactly, curved cores at this accuracy.
constexpr Real kEpaRelative = sizeof(Real) == 4 ? Real(1e-5) : Real(1e-7);
// Degeneracy scale: lengths below kEpaAbsolute * size of the Minkowski difference make a flat
// (zero-volume) difference.
constexpr Real kEpaAbsolute = 64 * kEps;
// Rounding of a support point's height over a face: a few ulps of the difference's size.
constexpr Real kEpaRounding = 8 * kEps;

// The faces' planes are computed in double from the (exact) support points: in float, a thin
// face's normal is off by an ulp of the difference's size over the face's width, which on a
// finely refined curved surface folds the polytope inward and stalls the search far short of
// the depth (issue 21).
using Vec3d = Eigen::Vector3d;

struct Face {
  std::array<int, 3> i{};        // vertices, counter-clockwise seen from outside
  std::array<int, 3> adj{};      // adj[e]: the face across edge e (i[e] -> i[e + 1])
  std::array<int, 3> adjEdge{};  // which edge of adj[e] that is
  Vec3d n = Vec3d::Zero();       // outward unit normal (zero for a degenerate face)
  double d = 0;                  // n . w[i0]: distance of the plane from the origin
  bool valid = false;            // false for degenerate faces, never chosen as the nearest
  bool live = false;             // false once removed (the slot is free)
};

// The polytope as faces with neighbour links (as in van den Bergen's and Jolt's EPA), so the
// faces a new point sees are found by a walk from the nearest face: the removed set is always
// connected and its boundary, the horizon, a single loop in order.
struct Polytope {
  std::array<SimplexVertex, kMaxVertices> v;
  std::array<Vec3d, kMaxVertices> w;  // v[k].w in double
  int nv = 0;
  std::array<Face, kMaxFaces> f;
  int nf = 0;  // slots used (live or free)
  std::array<int, kMaxFaces> freeSlots{};
  int nFree = 0;

  int addFace(int a, int b, int c) {
    int k;
    if (nFree > 0) {
      k = freeSlots[--nFree];
    } else if (nf < kMaxFaces) {
      k = nf++;
    } else {
      return -1;
    }
    Face& face = f[k];
    face.i = {a, b, c};
    face.live = true;
    const Vec3d n = (w[b] - w[a]).cross(w[c] - w[a]);
    const double len = n.norm();
    face.valid = len > 0 && std::isfinite(len);
    face.n = face.valid ? Vec3d(n / len) : Vec3d::Zero();
    face.d = face.valid ? face.n.dot(w[a]) : std::numeric_limits<double>::infinity();
    return k;
  }
  void removeFace(int k) {
    f[k].live = false;
    freeSlots[nFree++] = k;
  }
  void link(int fa, int ea, int fb, int eb) {
    f[fa].adj[ea] = fb;
    f[fa].adjEdge[ea] = eb;
    f[fb].adj[eb] = fa;
    f[fb].adjEdge[eb] = ea;
  }
};

// Depth 0: the Minkowski difference is flat (a point, a segment, a polygon) and holds the
// origin, so the cores touch without depth; `normal` is any direction leaving the flat set.
EpaResult flatResult(const ConvexProxy& a, const ConvexProxy& b, const Polytope& p,
                     const Vec3& normal) {
  EpaResult r;
  Simplex s;
  s.count = std::min(p.nv, 3);
  for (int i = 0; i < s.count; ++i) s.v[i] = p.v[i];
  closestToOrigin(s);
  for (int i = 0; i < s.count; ++i) {
    r.pointA += s.lambda[i] * s.v[i].a;
    r.pointB += s.lambda[i] * s.v[i].b;
  }
  const Vec3 axis = normalizedOr(b.centre() - a.centre(), Vec3::UnitY());
  r.normal = normal.dot(axis) < 0 ? Vec3(-normal) : normal;
  r.depth = 0;
  return r;
}

// A unit vector orthogonal to unit u.
Vec3 anyOrthogonal(const Vec3& u) {
  const Vec3 a = u.cwiseAbs();
  const Vec3 e = a.x() <= a.y() && a.x() <= a.z() ? Vec3::UnitX()
                 : a.y() <= a.z()                 ? Vec3::UnitY()
                                                  : Vec3::UnitZ();
  return u.cross(e).normalized();
}

// The foot of the perpendicular from the origin onto face f's plane, d n, as witness points on
// A and B: its barycentric weights in the face (signed areas, in double) applied to the support
// points of A and B, so pointA - pointB = d n. Unclamped: when rounding leaves the foot a hair
// outside the face, the weights go a hair negative rather than moving the foot.
void faceWitness(const Polytope& p, const Face& f, Vec3& pa, Vec3& pb) {
  const Vec3d foot = f.d * f.n;
  const Vec3d& w0 = p.w[f.i[0]];
  const Vec3d& w1 = p.w[f.i[1]];
  const Vec3d& w2 = p.w[f.i[2]];
  const double area = f.n.dot((w1 - w0).cross(w2 - w0));
  const std::array<double, 3> lambda{f.n.dot((w1 - foot).cross(w2 - foot)) / area,
                                     f.n.dot((w2 - foot).cross(w0 - foot)) / area,
                                     f.n.dot((w0 - foot).cross(w1 - foot)) / area};
  pa.setZero();
  pb.setZero();
  for (int k = 0; k < 3; ++k) {
    pa += Real(lambda[k]) * p.v[f.i[k]].a;
    pb += Real(lambda[k]) * p.v[f.i[k]].b;
  }
}

// The bounds of one EPA run, from the size of the Minkowski difference.
struct Tolerances {
  Real scale;  // size of the difference: the centres' distance, the simplex's farthest point
  Real eps;    // lengths below this make the difference flat
  Real noise;  // rounding of a support point's height over a face
};

// Adds the support point farthest off the line of p.v[0], p.v[1] (six directions around it);
// false, with a normal of the line, when the difference is that segment.
bool growFromSegment(const ConvexProxy& a, const ConvexProxy& b, Polytope& p, Real eps,
                     Vec3& flatNormal) {
  const Vec3 axis = normalizedOr(p.v[1].w - p.v[0].w, Vec3::UnitX());
  const Vec3 n1 = anyOrthogonal(axis), n2 = axis.cross(n1);
  flatNormal = n1;
  SimplexVertex best;
  Real far = 0;
  for (int k = 0; k < 6; ++k) {
    const Real angle = Real(k) * Real(M_PI / 3);
    const SimplexVertex w = supportVertex(a, b, std::cos(angle) * n1 + std::sin(angle) * n2);
    const Real off = (w.w - p.v[0].w).cross(axis).norm();
    if (off > far) far = off, best = w;
  }
  if (!(far > eps)) return false;
  p.v[p.nv++] = best;
  return true;
}

// Adds the support point farthest from the single point p.v[0] along the six axes; false when
// the difference is that point.
bool growFromPoint(const ConvexProxy& a, const ConvexProxy& b, Polytope& p, Real eps) {
  const Vec3 dirs[6] = {Vec3::UnitX(),  Vec3::UnitY(),  Vec3::UnitZ(),
                        -Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ()};
  SimplexVertex best;
  Real far = 0;
  for (const Vec3& d : dirs) {
    const SimplexVertex w = supportVertex(a, b, d);
    const Real len = (w.w - p.v[0].w).norm();
    if (len > far) far = len, best = w;
  }
  if (!(far > eps)) return false;
  p.v[p.nv++] = best;
  return true;
}

// Blows a simplex of 1-3 points up to a tetrahedron (the origin on its boundary or inside);
// the flat result instead when the difference has no volume.
std::optional<EpaResult> growToTetrahedron(const ConvexProxy& a, const ConvexProxy& b,
                                           Polytope& p, const Tolerances& tol) {
  constexpr int kMaxSlivers = 64;  // regrowths of a sliver (below) before the result is flat
  int slivers = 0;
  while (p.nv < 4) {
    if (p.nv == 1) {
      if (!growFromPoint(a, b, p, tol.eps))
        return flatResult(a, b, p, normalizedOr(b.centre() - a.centre(), Vec3::UnitY()));
    } else if (p.nv == 2) {
      Vec3 flatNormal;
      if (!growFromSegment(a, b, p, tol.eps, flatNormal)) return flatResult(a, b, p, flatNormal);
    } else {
      const Vec3 n = (p.v[1].w - p.v[0].w).cross(p.v[2].w - p.v[0].w);
      if (!(n.norm() > tol.eps * tol.scale)) {
        // A sliver: keep its longest edge and grow again from that segment (which adds the
        // point farthest off its line). The new point is more than eps off that line, yet the
        // new triangle can be a sliver again against eps * scale (a short edge), with the same
        // longest edge: the loop went round forever (fuzz input
        // convex-epa-sliver-cycle-timeout). After kMaxSlivers the difference is taken as flat.
        int i = 0, j = 1;
        Real longest = (p.v[1].w - p.v[0].w).squaredNorm();
        if ((p.v[2].w - p.v[0].w).squaredNorm() > longest)
          longest = (p.v[2].w - p.v[0].w).squaredNorm(), j = 2;
        if ((p.v[2].w - p.v[1].w).squaredNorm() > longest) i = 1, j = 2;
        if (++slivers > kMaxSlivers)
          return flatResult(
              a, b, p,
              normalizedOr(n, anyOrthogonal(normalizedOr(p.v[j].w - p.v[i].w, Vec3::UnitX()))));
        p.v[0] = p.v[i];
        p.v[1] = p.v[j];
        p.nv = 2;
        Vec3 flatNormal;
        if (!growFromSegment(a, b, p, tol.eps, flatNormal))
          return flatResult(a, b, p, flatNormal);
        continue;
      }
      const Vec3 un = unitOf(n);  // |n| > eps scale: not zero, but perhaps tiny
      const SimplexVertex up = supportVertex(a, b, un), down = supportVertex(a, b, -un);
      const Real hUp = un.dot(up.w - p.v[0].w), hDown = -un.dot(down.w - p.v[0].w);
      if (!(std::max(hUp, hDown) > tol.eps)) return flatResult(a, b, p, un);
      p.v[p.nv++] = hUp >= hDown ? up : down;
    }
  }
  return std::nullopt;
}

// The tetrahedron's four faces, wound outward (away from the opposite vertex), and linked.
void closeTetrahedron(Polytope& p) {
  for (int k = 0; k < 4; ++k) p.w[k] = p.v[k].w.cast<double>();
  const Vec3d& w0 = p.w[0];
  const double vol = (p.w[1] - w0).dot((p.w[2] - w0).cross(p.w[3] - w0));
  if (vol > 0)
    std::swap(p.v[1], p.v[2]), std::swap(p.w[1], p.w[2]);  // (0, 1, 2) faces away from 3
  p.addFace(0, 1, 2);
  p.addFace(0, 3, 1);
  p.addFace(0, 2, 3);
  p.addFace(1, 3, 2);
  // Each edge appears in two faces in opposite directions: link them.
  for (int fa = 0; fa < 4; ++fa)
    for (int ea = 0; ea < 3; ++ea)
      for (int fb = 0; fb < 4; ++fb)
        for (int eb = 0; eb < 3; ++eb)
          if (p.f[fa].i[ea] == p.f[fb].i[(eb + 1) % 3] &&
              p.f[fa].i[(ea + 1) % 3] == p.f[fb].i[eb])
            p.link(fa, ea, fb, eb);
}

// The live, valid face nearest the origin (-1 when every face is degenerate); among faces tied
// with it (coplanar pieces of one face of the difference), one that holds the foot of the
// perpendicular, so the witness points need no clamping. `nearest` is the least distance.
int nearestFace(const Polytope& p, Real noise, double& nearest) {
  int best = -1;
  for (int k = 0; k < p.nf; ++k)
    if (p.f[k].live && p.f[k].valid && (best < 0 || p.f[k].d < p.f[best].d)) best = k;
  if (best < 0) return best;
  nearest = p.f[best].d;
  for (int k = 0; k < p.nf; ++k) {
    const Face& f = p.f[k];
    if (!f.live || !f.valid || f.d > nearest + noise) continue;
    const Vec3d foot = f.d * f.n;
    bool inside = true;
    for (int e = 0; e < 3; ++e) {
      const Vec3d& x = p.w[f.i[e]];
      const Vec3d& y = p.w[f.i[(e + 1) % 3]];
      inside = inside && f.n.dot((y - x).cross(foot - x)) >= 0;
    }
    if (inside) return k;
  }
  return best;
}

// Horizon edges as (kept face, its edge), in loop order, and the walk's stack.
struct Horizon {
  std::array<std::array<int, 2>, kMaxFaces> edges;
  int count = 0;
  std::array<std::array<int, 2>, 2 * kMaxFaces + 4> stack;
};

// Removes the faces the new point wd sees, walking from face `best` (a copy of which is
// `face`) across edges; an edge into a face it does not see is a horizon edge. Depth first,
// edges in winding order, so the horizon comes out as one loop in order. False when a bound
// is hit.
bool carveHorizon(Polytope& p, int best, const Face& face, const Vec3d& wd, Horizon& h) {
  int top = 0;
  h.count = 0;
  p.removeFace(best);
  for (int e = 2; e >= 0; --e) h.stack[top++] = {face.adj[e], face.adjEdge[e]};
  while (top > 0) {
    const auto [fk, ek] = h.stack[--top];
    Face& f = p.f[fk];
    if (!f.live) continue;
    const bool visible = f.valid && f.n.dot(wd - p.w[f.i[0]]) > 0;
    if (!visible) {
      if (h.count == kMaxFaces) return false;
      h.edges[h.count++] = {fk, ek};
      continue;
    }
    p.removeFace(fk);
    if (top + 2 > int(h.stack.size())) return false;
    // Entered across edge ek: continue with the next two edges in winding order.
    for (int k = 2; k >= 1; --k) {
      const int e = (ek + k) % 3;
      h.stack[top++] = {f.adj[e], f.adjEdge[e]};
    }
  }
  return true;
}

// A new face per horizon edge to vertex iw (reversed, as the removed face held it), then links:
// to the kept face across the horizon edge and to the neighbours in the loop. False when the
// polytope would no longer be closed and growing outward.
bool coneToHorizon(Polytope& p, const Horizon& h, int iw, double nearest, Real noise) {
  int first = -1, prev = -1;
  for (int k = 0; k < h.count; ++k) {
    const auto [fk, ek] = h.edges[k];
    const int from = p.f[fk].i[(ek + 1) % 3], to = p.f[fk].i[ek];
    const int nf = p.addFace(from, to, iw);
    if (nf < 0) return false;
    p.link(nf, 0, fk, ek);
    // The polytope only grows, so no face may come nearer than the one replaced: a nearer one
    // folds inward (rounding on a nearly flat horizon) and would lead the search astray.
    if (p.f[nf].valid && p.f[nf].d < nearest - noise) return false;
    if (prev >= 0) {
      if (p.f[prev].i[1] != from) return false;  // not a loop: rounding made a mess
      p.link(prev, 1, nf, 2);
    } else {
      first = nf;
    }
    prev = nf;
  }
  if (h.count < 3 || p.f[prev].i[1] != p.f[first].i[0]) return false;
  p.link(prev, 1, first, 2);
  return true;
}

// Expands the closed polytope toward the boundary of the difference, face nearest the origin
// first, until the support point along its normal reaches no farther than the face.
EpaResult expand(const ConvexProxy& a, const ConvexProxy& b, Polytope& p, Real noise) {
  EpaResult r;
  r.converged = false;
  Horizon horizon;
  for (int iter = 0; iter < kMaxVertices; ++iter) {
    r.iterations = iter + 1;
    double nearest = 0;
    const int best = nearestFace(p, noise, nearest);
    if (best < 0) break;  // every face degenerate: keep the last answer
    const Face face = p.f[best];
    r.normal = face.n.cast<Real>();
    r.depth = Real(std::max(face.d, 0.0));
    faceWitness(p, face, r.pointA, r.pointB);

    const SimplexVertex w = supportVertex(a, b, r.normal);
    const Vec3d wd = w.w.cast<double>();
    // How far the difference reaches beyond the face: the depth lies in [d, d + gain].
    const double gain = face.n.dot(wd - p.w[face.i[0]]);
    if (gain <= kEpaRelative * std::max(face.d, 0.0) + noise) {
      r.converged = true;
      break;
    }
    if (p.nv == kMaxVertices) break;

    const int iw = p.nv;
    p.w[p.nv] = wd;
    p.v[p.nv++] = w;
    // Past a bound, or once the polytope is no longer closed, keep this iteration's answer.
    if (!carveHorizon(p, best, face, wd, horizon)) break;
    if (!coneToHorizon(p, horizon, iw, nearest, noise)) break;
  }
  return r;
}

}  // namespace

EpaResult epa(const ConvexProxy& a, const ConvexProxy& b, const Simplex& simplex) {
  Polytope p;
  for (int i = 0; i < simplex.count; ++i) p.v[p.nv++] = simplex.v[i];
  if (p.nv == 0) p.v[p.nv++] = supportVertex(a, b, Vec3::UnitX());

  Real scale = (a.centre() - b.centre()).norm();
  for (int i = 0; i < p.nv; ++i) scale = std::max(scale, p.v[i].w.norm());
  const Tolerances tol{scale, kEpaAbsolute * std::max(scale, std::numeric_limits<Real>::min()),
                       kEpaRounding * std::max(scale, std::numeric_limits<Real>::min())};
  if (auto flat = growToTetrahedron(a, b, p, tol)) return *flat;
  closeTetrahedron(p);
  return expand(a, b, p, tol.noise);
}

}  // namespace inertia::detail
