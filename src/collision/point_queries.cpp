// Point queries (signed distance, closest point, normal) for every shape type, computed in the
// shape's local frame. Inputs are assumed finite (not checked: these run per particle per step).
#include <algorithm>
#include <cmath>
#include <limits>

#include "inertia/collision/mesh_bvh.h"
#include "inertia/collision/queries.h"
#include "inertia/collision/triangle.h"
#include "local_queries.h"

namespace inertia {

namespace {

using detail::normalizedOr;

PointQuery query(const Plane& plane, const Vec3& p) {
  const Real d = plane.normal.dot(p) - plane.offset;
  return {d, p - d * plane.normal, plane.normal};
}

// Seed 000 (particle-sphere): d = |p - c| - r, n = norm(p - c). At the centre n = local +y.
PointQuery query(const Sphere& sphere, const Vec3& p) {
  const Vec3 n = normalizedOr(p, Vec3::UnitY());
  return {p.dot(n) - sphere.radius, sphere.radius * n, n};
}

// Seed 000 (particle-capsule): project onto the segment; the Voronoi regions of the two end
// points (spheres) and of the axis (cylinder) are the clamped projection. On the axis (inside,
// no unique direction) n = local +x.
PointQuery query(const Capsule& capsule, const Vec3& p) {
  const Vec3 q(0, std::clamp(p.y(), -capsule.halfHeight, capsule.halfHeight), 0);
  const Vec3 v = p - q;
  const Vec3 n = normalizedOr(v, Vec3::UnitX());
  return {v.dot(n) - capsule.radius, q + capsule.radius * n, n};
}

// Outside: clamp to the box. Inside (or on it): the nearest face; ties go to the lower axis
// (x before y before z) and to the + side, so the exact centre gets +x when x is shortest.
PointQuery query(const Box& box, const Vec3& p) {
  const Vec3& h = box.halfExtents;
  const Vec3 excess = p.cwiseAbs() - h;
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (excess[i] > excess[axis]) axis = i;
  Vec3 faceNormal = Vec3::Zero();
  faceNormal[axis] = p[axis] >= 0 ? Real(1) : Real(-1);
  if (excess[axis] > 0) {
    const Vec3 q = p.cwiseMax(-h).cwiseMin(h);
    const Vec3 n = normalizedOr(p - q, faceNormal);
    return {(p - q).dot(n), q, n};
  }
  Vec3 q = p;
  q[axis] = faceNormal[axis] * h[axis];
  return {excess[axis], q, faceNormal};
}

// Outside: clamp radially and axially. Inside: the nearer of the side (radial normal) and the
// caps (ties go to the cap). On the axis the radial direction is local +x.
PointQuery query(const Cylinder& cyl, const Vec3& p) {
  const Vec3 radial(p.x(), 0, p.z());
  const Real r = radial.norm();
  const Vec3 u = normalizedOr(radial, Vec3::UnitX());
  const Real capSign = p.y() >= 0 ? Real(1) : Real(-1);
  if (r > cyl.radius || std::abs(p.y()) > cyl.halfHeight) {
    Vec3 q = r > cyl.radius ? Vec3(cyl.radius * u) : radial;
    q.y() = std::clamp(p.y(), -cyl.halfHeight, cyl.halfHeight);
    const Vec3 fallback = std::abs(p.y()) > cyl.halfHeight ? Vec3(0, capSign, 0) : u;
    const Vec3 n = normalizedOr(p - q, fallback);
    return {(p - q).dot(n), q, n};
  }
  const Real sideGap = cyl.radius - r, capGap = cyl.halfHeight - std::abs(p.y());
  if (sideGap < capGap) {
    const Vec3 q(cyl.radius * u.x(), p.y(), cyl.radius * u.z());
    return {-sideGap, q, u};
  }
  return {-capGap, Vec3(p.x(), capSign * cyl.halfHeight, p.z()), Vec3(0, capSign, 0)};
}

// Inside: the face plane of largest separation (the nearest face). Outside: the exact closest
// point, the minimum over the faces p sees (positive separation; the closest point lies on one
// of them) of the distance to the face polygon: the projection when it falls inside the loop,
// else the nearest loop edge.
PointQuery query(const ConvexHull& hull, const Vec3& p) {
  const auto& faces = hull.faces();
  const auto& verts = hull.vertices();
  const auto& halfEdges = hull.halfEdges();
  Real maxSep = -kInfinity;
  std::size_t maxFace = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Real s = faces[f].normal.dot(p) - faces[f].offset;
    if (s > maxSep) {
      maxSep = s;
      maxFace = f;
    }
  }
  const Vec3& n0 = faces[maxFace].normal;
  if (maxSep <= 0) return {maxSep, p - maxSep * n0, n0};

  Real bestD2 = kInfinity;
  Vec3 best = p - maxSep * n0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const HullFace& face = faces[f];
    const Real s = face.normal.dot(p) - face.offset;
    if (s <= 0 || s * s >= bestD2) continue;  // face not visible, or cannot beat the best
    const Vec3 projected = p - s * face.normal;
    bool insideLoop = true;
    for (std::uint32_t k = 0; k < face.edgeCount && insideLoop; ++k) {
      const HullHalfEdge& e = halfEdges[face.firstEdge + k];
      const Vec3& a = verts[e.origin];
      const Vec3& b = verts[halfEdges[e.next].origin];
      insideLoop = (b - a).cross(projected - a).dot(face.normal) >= 0;
    }
    if (insideLoop) {
      bestD2 = s * s;
      best = projected;
      continue;
    }
    for (std::uint32_t k = 0; k < face.edgeCount; ++k) {
      const HullHalfEdge& e = halfEdges[face.firstEdge + k];
      const Vec3& a = verts[e.origin];
      const Vec3 ab = verts[halfEdges[e.next].origin] - a;
      const Real len2 = ab.squaredNorm();
      const Real t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, Real(0), Real(1)) : Real(0);
      const Vec3 q = a + t * ab;
      const Real d2 = (p - q).squaredNorm();
      if (d2 < bestD2) {
        bestD2 = d2;
        best = q;
      }
    }
  }
  const Vec3 n = normalizedOr(p - best, n0);
  return {(p - best).dot(n), best, n};
}

// BVH closest point; for closed meshes signed by the angle-weighted pseudonormal of the
// closest feature (Baerentzen and Aanaes 2005), for open meshes unsigned.
PointQuery query(const MeshBvh& bvh, const Vec3& p) {
  const MeshBvh::Closest c = bvh.closestPoint(p);
  const Vec3 pseudo = bvh.pseudonormal(c.triangle, c.feature);
  const Vec3 v = p - c.point;
  const Real sign = bvh.closed() && v.dot(pseudo) < 0 ? Real(-1) : Real(1);
  const Vec3 n = normalizedOr(sign * v, pseudo);
  return {v.dot(n), c.point, n};
}

// Height of the surface above (x, z), which must lie in the grid's footprint: the cell's
// triangle (split along the diagonal from (i, j) to (i + 1, j + 1)) interpolated linearly.
Real surfaceHeight(const HeightField& field, Real x, Real z) {
  const Real s = field.spacing();
  const std::size_t j = std::min(std::size_t(std::max(x / s, Real(0))), field.cols() - 2);
  const std::size_t i = std::min(std::size_t(std::max(z / s, Real(0))), field.rows() - 2);
  const Real u = x / s - Real(j), w = z / s - Real(i);
  const Real ha = field.height(i, j), hb = field.height(i, j + 1);
  const Real hc = field.height(i + 1, j + 1), hd = field.height(i + 1, j);
  if (u >= w) return ha + (hb - ha) * u + (hc - hb) * w;  // triangle (a, c, b)
  return ha + (hd - ha) * w + (hc - hd) * u;              // triangle (a, d, c)
}

// The distance to the surface point above or below the clamped (x, z) bounds the distance,
// so only cells within that radius (in x and z) can hold the closest point: cost grows with
// (distance / spacing)^2, small for points near the terrain. Below the surface is inside.
PointQuery query(const HeightField& field, const Vec3& p) {
  const Real s = field.spacing();
  const Real xMax = Real(field.cols() - 1) * s, zMax = Real(field.rows() - 1) * s;
  const Real xc = std::clamp(p.x(), Real(0), xMax), zc = std::clamp(p.z(), Real(0), zMax);
  const Real hc = surfaceHeight(field, xc, zc);
  const bool inside = xc == p.x() && zc == p.z() && p.y() < hc;
  const Real radius = (p - Vec3(xc, hc, zc)).norm();

  const auto cellRange = [s](Real lo, Real hi, std::size_t cells, std::size_t* a, std::size_t* b) {
    const Real fa = std::floor(lo / s), fb = std::floor(hi / s);
    const Real last = Real(cells - 1);
    *a = fa <= 0 ? 0 : fa >= last ? cells - 1 : std::size_t(fa);
    *b = fb <= 0 ? 0 : fb >= last ? cells - 1 : std::size_t(fb);
  };
  std::size_t j0, j1, i0, i1;
  cellRange(p.x() - radius, p.x() + radius, field.cols() - 1, &j0, &j1);
  cellRange(p.z() - radius, p.z() + radius, field.rows() - 1, &i0, &i1);

  Real bestD2 = kInfinity;
  Vec3 best = Vec3(xc, hc, zc), bestNormal = Vec3::UnitY();
  for (std::size_t i = i0; i <= i1; ++i)
    for (std::size_t j = j0; j <= j1; ++j) {
      // Skip cells whose footprint is already farther than the best point.
      const Real dx = std::max({Real(j) * s - p.x(), p.x() - Real(j + 1) * s, Real(0)});
      const Real dz = std::max({Real(i) * s - p.z(), p.z() - Real(i + 1) * s, Real(0)});
      if (dx * dx + dz * dz >= bestD2) continue;
      for (const auto& t : field.cellTriangles(i, j)) {
        const TriangleClosest c = closestPointOnTriangle(p, t[0], t[1], t[2]);
        const Real d2 = (p - c.point).squaredNorm();
        if (d2 < bestD2) {
          bestD2 = d2;
          best = c.point;
          bestNormal = normalizedOr((t[1] - t[0]).cross(t[2] - t[0]), Vec3::UnitY());
        }
      }
    }
  const Real sign = inside ? Real(-1) : Real(1);
  const Vec3 v = p - best;
  const Vec3 n = normalizedOr(sign * v, bestNormal);
  return {v.dot(n), best, n};
}

// The union's distance: the minimum over the children (exact outside; inside, the depth below
// the surface of the child reporting the smallest value).
PointQuery query(const Collider& collider, const Compound& compound, const Vec3& p) {
  PointQuery best;
  best.distance = kInfinity;
  const auto& children = collider.children();
  for (std::size_t k = 0; k < children.size(); ++k) {
    const Transform& xf = compound.children()[k].transform;
    const PointQuery q = detail::queryPointLocal(children[k], xf.applyInverse(p));
    if (q.distance < best.distance) best = {q.distance, xf.apply(q.point), xf.rotate(q.normal)};
  }
  return best;
}

}  // namespace

namespace detail {

PointQuery queryPointLocal(const Collider& collider, const Vec3& p) {
  const Shape& shape = collider.shape();
  switch (shape.type()) {
    case ShapeType::Plane:
      return query(*shape.getIf<Plane>(), p);
    case ShapeType::Sphere:
      return query(*shape.getIf<Sphere>(), p);
    case ShapeType::Capsule:
      return query(*shape.getIf<Capsule>(), p);
    case ShapeType::Box:
      return query(*shape.getIf<Box>(), p);
    case ShapeType::Cylinder:
      return query(*shape.getIf<Cylinder>(), p);
    case ShapeType::Hull:
      return query(*shape.getIf<ConvexHull>(), p);
    case ShapeType::Mesh:
      return query(*collider.meshBvh(), p);
    case ShapeType::HeightField:
      return query(*shape.getIf<HeightField>(), p);
    case ShapeType::Compound:
      return query(collider, *shape.getIf<Compound>(), p);
  }
  return {};
}

}  // namespace detail

PointQuery queryPoint(const Collider& collider, const Transform& pose, const Vec3& point) {
  const PointQuery local = detail::queryPointLocal(collider, pose.applyInverse(point));
  return {local.distance, pose.apply(local.point), pose.rotate(local.normal)};
}

}  // namespace inertia
