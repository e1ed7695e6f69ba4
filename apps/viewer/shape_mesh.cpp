#include "shape_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace inertia::viewer {

namespace {

using V3 = Eigen::Vector3f;

V3 toFloat(const Vec3& v) { return v.cast<float>(); }

std::uint32_t addVertex(MeshData& m, const V3& p, const V3& n) {
  m.positions.push_back(p);
  m.normals.push_back(n);
  return std::uint32_t(m.positions.size() - 1);
}

void addTriangle(MeshData& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  m.indices.insert(m.indices.end(), {a, b, c});
}

// A flat polygon (convex, counter-clockwise about n) as a fan.
void addFlatPolygon(MeshData& m, const std::vector<V3>& loop, const V3& n) {
  const std::uint32_t first = std::uint32_t(m.positions.size());
  for (const V3& p : loop) addVertex(m, p, n);
  for (std::uint32_t k = 1; k + 1 < loop.size(); ++k)
    addTriangle(m, first, first + k, first + k + 1);
}

void addFlatTriangle(MeshData& m, const V3& a, const V3& b, const V3& c) {
  V3 n = (b - a).cross(c - a);
  const float len = n.norm();
  n = len > 0 ? V3(n / len) : V3::UnitY();
  addFlatPolygon(m, {a, b, c}, n);
}

// A sphere of radius r whose upper hemisphere is lifted by +h and lower by -h along y: a
// sphere for h = 0, a capsule otherwise (the equator ring is doubled to join the cylinder).
MeshData roundedCylinder(float r, float h, int segments) {
  MeshData m;
  const int rings = std::max(2, segments / 2);  // latitude bands, even so the equator is a ring
  const int half = (rings + 1) / 2;
  const float pi = std::numbers::pi_v<float>;
  // Rows from the north pole to the south pole; the equator appears twice when h > 0.
  std::vector<std::pair<float, float>> rows;  // (polar angle, y offset)
  for (int i = 0; i <= half; ++i) rows.emplace_back(pi * float(i) / float(2 * half), h);
  for (int i = (h > 0 ? half : half + 1); i <= 2 * half; ++i)
    rows.emplace_back(pi * float(i) / float(2 * half), -h);
  const std::uint32_t stride = std::uint32_t(segments + 1);
  for (const auto& [theta, dy] : rows) {
    for (int j = 0; j <= segments; ++j) {
      const float phi = 2 * pi * float(j) / float(segments);
      const V3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                 -std::sin(theta) * std::sin(phi));
      addVertex(m, r * n + V3(0, dy, 0), n);
    }
  }
  for (std::uint32_t i = 0; i + 1 < rows.size(); ++i) {
    for (std::uint32_t j = 0; j < std::uint32_t(segments); ++j) {
      const std::uint32_t a = i * stride + j, b = a + 1, c = a + stride, d = c + 1;
      addTriangle(m, a, c, d);
      addTriangle(m, a, d, b);
    }
  }
  return m;
}

MeshData cylinder(float r, float h, int segments) {
  MeshData m;
  const float pi = std::numbers::pi_v<float>;
  std::vector<V3> top, bottom;
  for (int j = 0; j <= segments; ++j) {
    const float phi = 2 * pi * float(j) / float(segments);
    const V3 n(std::cos(phi), 0, -std::sin(phi));
    const std::uint32_t a = addVertex(m, r * n + V3(0, h, 0), n);
    addVertex(m, r * n - V3(0, h, 0), n);
    if (j < segments) {
      addTriangle(m, a, a + 1, a + 3);
      addTriangle(m, a, a + 3, a + 2);
      top.push_back(r * n + V3(0, h, 0));
      bottom.push_back(r * n - V3(0, h, 0));
    }
  }
  addFlatPolygon(m, top, V3::UnitY());
  std::reverse(bottom.begin(), bottom.end());
  addFlatPolygon(m, bottom, -V3::UnitY());
  return m;
}

MeshData box(const Vec3& halfExtents) {
  MeshData m;
  const V3 e = toFloat(halfExtents);
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {1.0f, -1.0f}) {
      V3 n = V3::Zero();
      n[axis] = sign;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      std::vector<V3> loop;
      // (u, v) corners counter-clockwise about +axis; reversed for -axis.
      const float cu[4] = {-1, 1, 1, -1}, cv[4] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        const int kk = sign > 0 ? k : 3 - k;
        V3 p;
        p[axis] = sign * e[axis];
        p[u] = cu[kk] * e[u];
        p[v] = cv[kk] * e[v];
        loop.push_back(p);
      }
      addFlatPolygon(m, loop, n);
    }
  }
  return m;
}

MeshData hull(const ConvexHull& h) {
  MeshData m;
  for (std::size_t f = 0; f < h.faces().size(); ++f) {
    std::vector<V3> loop;
    for (const HullHalfEdge& e : h.faceEdges(f)) loop.push_back(toFloat(h.vertices()[e.origin]));
    addFlatPolygon(m, loop, toFloat(h.faces()[f].normal));
  }
  return m;
}

MeshData triangleMesh(const TriangleMesh& mesh) {
  MeshData m;
  for (std::size_t t = 0; t < mesh.triangles().size(); ++t) {
    const Triangle& tri = mesh.triangles()[t];
    std::vector<V3> loop;
    for (std::uint32_t i : tri) loop.push_back(toFloat(mesh.vertices()[i]));
    addFlatPolygon(m, loop, toFloat(mesh.normals()[t]));
  }
  return m;
}

MeshData heightField(const HeightField& field) {
  MeshData m;
  for (std::size_t i = 0; i + 1 < field.rows(); ++i) {
    for (std::size_t j = 0; j + 1 < field.cols(); ++j) {
      for (const auto& tri : field.cellTriangles(i, j))
        addFlatTriangle(m, toFloat(tri[0]), toFloat(tri[1]), toFloat(tri[2]));
    }
  }
  return m;
}

MeshData plane(const Plane& p, Real halfSize) {
  MeshData m;
  Vec3 u, v;
  planeBasis(p.normal, u, v);
  const Vec3 c = p.normal * p.offset;
  std::vector<V3> loop;
  for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
    loop.push_back(toFloat(c + halfSize * (Real(a) * u + Real(b) * v)));
  addFlatPolygon(m, loop, toFloat(p.normal));
  return m;
}

}  // namespace

void MeshData::append(const MeshData& other, const Transform& pose) {
  const std::uint32_t base = std::uint32_t(positions.size());
  const Eigen::Quaternionf q = pose.q.cast<float>();
  const V3 t = toFloat(pose.p);
  for (std::size_t i = 0; i < other.positions.size(); ++i) {
    positions.push_back(q * other.positions[i] + t);
    normals.push_back(q * other.normals[i]);
  }
  for (std::uint32_t i : other.indices) indices.push_back(base + i);
}

void planeBasis(const Vec3& n, Vec3& u, Vec3& v) {
  // From a world axis far from n; (u, v, n) is right-handed (n = +y gives u = +x, v = -z).
  Vec3 a = std::abs(n.x()) < Real(0.6) ? Vec3::UnitX() : Vec3::UnitZ();
  v = n.cross(a).normalized();
  u = v.cross(n).normalized();
}

namespace {

// Each vertex's normal: the sum of its triangles' (b - a) x (c - a), which weights them by area,
// normalised; +y where they cancel.
MeshData deformableSurface(const Deformable& d) {
  MeshData m;
  const std::size_t n = d.vertexCount();
  m.positions.resize(n);
  m.normals.assign(n, Eigen::Vector3f::Zero());
  for (std::size_t i = 0; i < n; ++i) m.positions[i] = d.position(i).cast<float>();
  for (const auto& t : d.triangles()) {
    const Eigen::Vector3f face = (m.positions[t[1]] - m.positions[t[0]])
                                     .cross(m.positions[t[2]] - m.positions[t[0]]);
    for (std::uint32_t v : t) m.normals[v] += face;
    m.indices.insert(m.indices.end(), t.begin(), t.end());
  }
  for (Eigen::Vector3f& normal : m.normals) {
    const float length = normal.norm();
    normal = length > 0 ? Eigen::Vector3f(normal / length) : Eigen::Vector3f::UnitY();
  }
  return m;
}

// A prism of `sides` faces around each unbroken stretch spring, open at its ends (the next
// spring's tube continues it).
MeshData deformableTubes(const Deformable& d, int sides, Real radius) {
  MeshData m;
  const std::span<const Spring> springs = d.springs();
  for (std::size_t k = 0; k < springs.size(); ++k) {
    if (springs[k].kind != SpringKind::Stretch || d.isBroken(k)) continue;
    const Eigen::Vector3f a = d.position(springs[k].a).cast<float>();
    const Eigen::Vector3f b = d.position(springs[k].b).cast<float>();
    const Eigen::Vector3f axis = b - a;
    if (!(axis.norm() > 0)) continue;
    Vec3 u, v;
    planeBasis(axis.normalized().cast<Real>(), u, v);
    const auto first = std::uint32_t(m.positions.size());
    for (int j = 0; j < sides; ++j) {
      const double angle = 2 * std::numbers::pi * j / sides;
      const Eigen::Vector3f normal =
          (std::cos(angle) * u + std::sin(angle) * v).cast<float>().normalized();
      for (const Eigen::Vector3f& end : {a, b}) {
        m.positions.push_back(end + float(radius) * normal);
        m.normals.push_back(normal);
      }
    }
    for (int j = 0; j < sides; ++j) {
      const std::uint32_t a0 = first + 2 * std::uint32_t(j), b0 = a0 + 1;
      const std::uint32_t a1 = first + 2 * std::uint32_t((j + 1) % sides), b1 = a1 + 1;
      m.indices.insert(m.indices.end(), {a0, a1, b1, a0, b1, b0});
    }
  }
  return m;
}

}  // namespace

MeshData deformableMesh(const Deformable& d, int sides, Real tubeRadius) {
  return d.triangles().empty() ? deformableTubes(d, std::max(3, sides), tubeRadius)
                               : deformableSurface(d);
}

MeshData tessellate(const Shape& shape, const TessellationSettings& s) {
  const int seg = std::max(3, s.segments);
  switch (shape.type()) {
    case ShapeType::Plane:
      return plane(shape.get<Plane>(), s.planeHalfSize);
    case ShapeType::Sphere:
      return roundedCylinder(float(shape.get<Sphere>().radius), 0, seg);
    case ShapeType::Capsule: {
      const Capsule& c = shape.get<Capsule>();
      return roundedCylinder(float(c.radius), float(c.halfHeight), seg);
    }
    case ShapeType::Box:
      return box(shape.get<Box>().halfExtents);
    case ShapeType::Cylinder: {
      const Cylinder& c = shape.get<Cylinder>();
      return cylinder(float(c.radius), float(c.halfHeight), seg);
    }
    case ShapeType::Hull:
      return hull(shape.get<ConvexHull>());
    case ShapeType::Mesh:
      return triangleMesh(shape.get<TriangleMesh>());
    case ShapeType::HeightField:
      return heightField(shape.get<HeightField>());
    case ShapeType::Compound: {
      MeshData m;
      for (const CompoundChild& child : shape.get<Compound>().children())
        m.append(tessellate(child.shape, s), child.transform);
      return m;
    }
  }
  return {};
}

}  // namespace inertia::viewer
