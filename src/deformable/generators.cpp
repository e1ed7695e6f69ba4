#include "inertia/deformable/generators.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "inertia/core/error.h"

namespace inertia {

namespace {

using Index = std::uint32_t;

void checkCommon(const char* who, Real mass, const SpringStiffness& k, Real damping) {
  const std::string w(who);
  require(std::isfinite(mass) && mass > 0, w + ": mass must be finite and > 0 (kg)");
  const std::pair<Real, const char*> parts[] = {
      {k.stretch, "stretch"}, {k.shear, "shear"}, {k.bend, "bend"}};
  for (const auto& [value, name] : parts)
    require(std::isfinite(value) && value >= 0,
            w + ": stiffness." + name + " must be finite and >= 0 (N/m)");
  require(std::isfinite(damping) && damping >= 0, w + ": damping must be finite and >= 0 (N s/m)");
}

void checkPose(const char* who, const Transform& pose) {
  require(pose.p.allFinite() && pose.q.coeffs().allFinite() &&
              std::fabs(pose.q.norm() - 1) < Real(1e-3),
          std::string(who) + ": pose must be finite with a unit quaternion");
}

// A spring at rest between a and b, skipped when it has no stiffness (bend 0: no bend springs).
void addSpring(MassSpringModel& m, Index a, Index b, Real k, Real c, SpringKind kind) {
  if (k <= 0 && c <= 0) return;
  m.springs.push_back({a, b, (m.positions[a] - m.positions[b]).norm(), k, c, kind});
}

void spreadMass(MassSpringModel& m, Real total) {
  m.masses.assign(m.positions.size(), total / Real(m.positions.size()));
}

}  // namespace

MassSpringModel rope(const RopeSettings& s) {
  checkCommon("RopeSettings", s.mass, s.stiffness, s.damping);
  require(s.from.allFinite() && s.to.allFinite(), "RopeSettings: from and to must be finite");
  require(s.segments >= 1 && s.segments <= 1000000, "RopeSettings: segments must be in 1..1000000");
  require((s.to - s.from).norm() > 0, "RopeSettings: from and to must differ");
  MassSpringModel m;
  for (int i = 0; i <= s.segments; ++i)
    m.positions.push_back(s.from + (s.to - s.from) * (Real(i) / Real(s.segments)));
  spreadMass(m, s.mass);
  const Index n = Index(m.positions.size());
  for (Index i = 0; i + 1 < n; ++i)
    addSpring(m, i, i + 1, s.stiffness.stretch, s.damping, SpringKind::Stretch);
  for (Index i = 0; i + 2 < n; ++i)
    addSpring(m, i, i + 2, s.stiffness.bend, s.damping, SpringKind::Bend);
  return m;
}

MassSpringModel hair(const HairSettings& s) {
  checkCommon("HairSettings", s.mass, s.stiffness, s.damping);
  checkPose("HairSettings", s.pose);
  require(std::isfinite(s.radius) && s.radius > 0, "HairSettings: radius must be finite and > 0 (m)");
  require(std::isfinite(s.length) && s.length > 0, "HairSettings: length must be finite and > 0 (m)");
  const Real pi = std::acos(Real(-1));
  require(std::isfinite(s.capAngle) && s.capAngle > 0 && s.capAngle <= pi,
          "HairSettings: capAngle must be in (0, pi] (rad)");
  require(s.strands >= 1 && s.strands <= 1000000, "HairSettings: strands must be in 1..1000000");
  require(s.segments >= 1 && s.segments <= 10000, "HairSettings: segments must be in 1..10000");
  const Real goldenAngle = pi * (3 - std::sqrt(Real(5)));
  const Real capHeight = 1 - std::cos(s.capAngle);  // of the unit sphere's cap: area 2 pi h
  MassSpringModel m;
  const Index perStrand = Index(s.segments + 1);
  for (int k = 0; k < s.strands; ++k) {
    const Real y = 1 - capHeight * (Real(k) + Real(0.5)) / Real(s.strands);
    const Real ring = std::sqrt(std::max(Real(0), 1 - y * y)), phi = goldenAngle * Real(k);
    const Vec3 normal = s.pose.q * Vec3(ring * std::cos(phi), y, ring * std::sin(phi));
    const Vec3 root = s.pose.p + s.radius * normal;
    m.pinned.push_back(Index(m.positions.size()));
    for (int i = 0; i <= s.segments; ++i)
      m.positions.push_back(root + (s.length * Real(i) / Real(s.segments)) * normal);
  }
  spreadMass(m, s.mass);
  for (Index first = 0; first < m.positions.size(); first += perStrand) {
    for (Index i = first; i + 1 < first + perStrand; ++i)
      addSpring(m, i, i + 1, s.stiffness.stretch, s.damping, SpringKind::Stretch);
    for (Index i = first; i + 2 < first + perStrand; ++i)
      addSpring(m, i, i + 2, s.stiffness.bend, s.damping, SpringKind::Bend);
  }
  return m;
}

MassSpringModel cloth(const ClothSettings& s) {
  checkCommon("ClothSettings", s.mass, s.stiffness, s.damping);
  checkPose("ClothSettings", s.pose);
  require(std::isfinite(s.size[0]) && s.size[0] > 0 && std::isfinite(s.size[1]) && s.size[1] > 0,
          "ClothSettings: size must be finite and > 0 (m)");
  require(s.resolution[0] >= 1 && s.resolution[1] >= 1 && s.resolution[0] <= 4096 &&
              s.resolution[1] <= 4096,
          "ClothSettings: resolution must be in 1..4096 along each side");
  const int nx = s.resolution[0], nz = s.resolution[1];
  MassSpringModel m;
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i)
      m.positions.push_back(s.pose.apply(Vec3(s.size[0] * (Real(i) / Real(nx) - Real(0.5)), 0,
                                              s.size[1] * (Real(j) / Real(nz) - Real(0.5)))));
  spreadMass(m, s.mass);
  const auto id = [nx](int i, int j) { return Index(i + j * (nx + 1)); };
  const SpringStiffness& k = s.stiffness;
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i) {
      if (i < nx) addSpring(m, id(i, j), id(i + 1, j), k.stretch, s.damping, SpringKind::Stretch);
      if (j < nz) addSpring(m, id(i, j), id(i, j + 1), k.stretch, s.damping, SpringKind::Stretch);
      if (i < nx && j < nz) {
        addSpring(m, id(i, j), id(i + 1, j + 1), k.shear, s.damping, SpringKind::Shear);
        addSpring(m, id(i + 1, j), id(i, j + 1), k.shear, s.damping, SpringKind::Shear);
        // Counter-clockwise seen from +y: z x x = +y.
        m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
        m.triangles.push_back({id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
      }
      if (i + 2 <= nx) addSpring(m, id(i, j), id(i + 2, j), k.bend, s.damping, SpringKind::Bend);
      if (j + 2 <= nz) addSpring(m, id(i, j), id(i, j + 2), k.bend, s.damping, SpringKind::Bend);
    }
  return m;
}

namespace {

// The springs of a lattice with `nodes` vertices per axis, from each present vertex (i, j, l)
// to the present neighbours ahead of it (so each pair once): stretch along the axes, shear on the
// face and body diagonals, bend skipping one along the axes. id(i, j, l) is the model's index.
template <class Present, class Id>
void latticeSprings(MassSpringModel& m, const std::array<int, 3>& nodes, const Present& present,
                    const Id& id, const SpringStiffness& k, Real damping) {
  const auto there = [&](int i, int j, int l) {
    return i >= 0 && j >= 0 && l >= 0 && i < nodes[0] && j < nodes[1] && l < nodes[2] &&
           present(i, j, l);
  };
  for (int l = 0; l < nodes[2]; ++l)
    for (int j = 0; j < nodes[1]; ++j)
      for (int i = 0; i < nodes[0]; ++i) {
        if (!present(i, j, l)) continue;
        for (int dl = -1; dl <= 1; ++dl)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              // Neighbours ahead: the first non-zero offset (in l, j, i order) is positive.
              const int first = dl != 0 ? dl : (dj != 0 ? dj : di);
              if (first <= 0 || !there(i + di, j + dj, l + dl)) continue;
              const bool axis = std::abs(di) + std::abs(dj) + std::abs(dl) == 1;
              addSpring(m, id(i, j, l), id(i + di, j + dj, l + dl), axis ? k.stretch : k.shear,
                        damping, axis ? SpringKind::Stretch : SpringKind::Shear);
              if (axis && there(i + 2 * di, j + 2 * dj, l + 2 * dl))
                addSpring(m, id(i, j, l), id(i + 2 * di, j + 2 * dj, l + 2 * dl), k.bend, damping,
                          SpringKind::Bend);
            }
      }
}

// The six faces of the lattice as triangles, counter-clockwise seen from outside.
void latticeFaces(MassSpringModel& m, const std::array<int, 3>& r) {
  const auto id = [&r](const std::array<int, 3>& c) {
    return Index(c[0] + (r[0] + 1) * (c[1] + (r[1] + 1) * c[2]));
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;  // (u, w, axis) right-handed
    for (int side = 0; side < 2; ++side)
      for (int a = 0; a < r[u]; ++a)
        for (int b = 0; b < r[w]; ++b) {
          std::array<int, 3> c00{}, c10{}, c01{}, c11{};
          for (auto* c : {&c00, &c10, &c01, &c11}) (*c)[axis] = side * r[axis];
          c00[u] = a, c00[w] = b;
          c10[u] = a + 1, c10[w] = b;
          c01[u] = a, c01[w] = b + 1;
          c11[u] = a + 1, c11[w] = b + 1;
          // u x w = +axis: counter-clockwise (c00, c10, c11) faces +axis; reversed on side 0.
          if (side == 1) {
            m.triangles.push_back({id(c00), id(c10), id(c11)});
            m.triangles.push_back({id(c00), id(c11), id(c01)});
          } else {
            m.triangles.push_back({id(c00), id(c11), id(c10)});
            m.triangles.push_back({id(c00), id(c01), id(c11)});
          }
        }
  }
}

}  // namespace

MassSpringModel softBox(const SoftBoxSettings& s) {
  checkCommon("SoftBoxSettings", s.mass, s.stiffness, s.damping);
  checkPose("SoftBoxSettings", s.pose);
  require(s.halfExtents.allFinite() && (s.halfExtents.array() > 0).all(),
          "SoftBoxSettings: halfExtents must be finite and > 0 (m)");
  for (int r : s.resolution)
    require(r >= 1 && r <= 256, "SoftBoxSettings: resolution must be in 1..256 per axis");
  const std::array<int, 3>& r = s.resolution;
  MassSpringModel m;
  for (int l = 0; l <= r[2]; ++l)
    for (int j = 0; j <= r[1]; ++j)
      for (int i = 0; i <= r[0]; ++i) {
        const Vec3 t(Real(i) / Real(r[0]), Real(j) / Real(r[1]), Real(l) / Real(r[2]));
        m.positions.push_back(
            s.pose.apply((2 * t.array() - 1).matrix().cwiseProduct(s.halfExtents)));
      }
  spreadMass(m, s.mass);
  latticeSprings(
      m, {r[0] + 1, r[1] + 1, r[2] + 1}, [](int, int, int) { return true; },
      [&r](int i, int j, int l) { return Index(i + (r[0] + 1) * (j + (r[1] + 1) * l)); },
      s.stiffness, s.damping);
  latticeFaces(m, r);
  return m;
}

namespace {

// On a closed surface's triangles: a stretch spring on each edge and a bend spring between the
// two vertices opposite it, each edge once (in the order of the edges' vertex pairs).
void surfaceSprings(MassSpringModel& m, const SpringStiffness& k, Real damping) {
  std::map<std::pair<Index, Index>, std::array<Index, 2>> opposite;
  for (const auto& f : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const Index a = f[e], b = f[(e + 1) % 3], c = f[(e + 2) % 3];
      auto& o = opposite[std::minmax(a, b)];
      o[a < b ? 0 : 1] = c;  // the face where the edge runs a -> b with a < b comes first
    }
  for (const auto& [edge, o] : opposite) {
    addSpring(m, edge.first, edge.second, k.stretch, damping, SpringKind::Stretch);
    addSpring(m, o[0], o[1], k.bend, damping, SpringKind::Bend);
  }
}

// The icosahedron's unit vertices and faces (counter-clockwise seen from outside), then each
// triangle split in four with its edge midpoints pushed out to the unit sphere.
void icosphere(int subdivisions, std::vector<Vec3>& points,
               std::vector<std::array<Index, 3>>& faces) {
  const Real t = (1 + std::sqrt(Real(5))) / 2;
  points = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : points) p.normalize();
  faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
           {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
           {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<Index, Index>, Index> midpoints;
    const auto mid = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = midpoints.try_emplace(key, Index(points.size()));
      if (added) points.push_back((points[a] + points[b]).normalized());
      return it->second;
    };
    std::vector<std::array<Index, 3>> next;
    for (const auto& f : faces) {
      const Index ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    faces = std::move(next);
  }
}

}  // namespace

MassSpringModel softSphere(const SoftSphereSettings& s) {
  checkCommon("SoftSphereSettings", s.mass, s.stiffness, s.damping);
  checkPose("SoftSphereSettings", s.pose);
  require(std::isfinite(s.radius) && s.radius > 0,
          "SoftSphereSettings: radius must be finite and > 0 (m)");
  require(s.subdivisions >= 0 && s.subdivisions <= 5,
          "SoftSphereSettings: subdivisions must be in 0..5");
  std::vector<Vec3> unit;
  MassSpringModel m;
  icosphere(s.subdivisions, unit, m.triangles);
  for (const Vec3& p : unit) m.positions.push_back(s.pose.apply(s.radius * p));
  const Index centre = Index(m.positions.size());
  m.positions.push_back(s.pose.p);
  spreadMass(m, s.mass);
  surfaceSprings(m, s.stiffness, s.damping);
  for (Index i = 0; i < centre; ++i)
    addSpring(m, centre, i, s.stiffness.stretch, s.damping, SpringKind::Stretch);
  return m;
}

namespace {

// Which cell centres of a grid over `box` (n cells per axis) lie inside the closed mesh: per row
// of cells along x, the x where a line through the row's centres crosses each triangle (the line
// moved off the centres by a ten-thousandth of a cell in y and z, so that it misses the
// triangles' shared edges and vertices of meshes aligned with the grid), sorted; a centre is
// inside when an odd number of crossings lie before it.
std::vector<std::uint8_t> insideCells(const TriangleMesh& mesh, const Aabb& box,
                                      const std::array<int, 3>& n) {
  const Vec3 cell = (box.upper - box.lower).cwiseQuotient(Vec3(Real(n[0]), Real(n[1]), Real(n[2])));
  std::vector<std::uint8_t> inside(std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]), 0);
  std::vector<double> crossings;
  const auto& v = mesh.vertices();
  for (int l = 0; l < n[2]; ++l)
    for (int j = 0; j < n[1]; ++j) {
      const double y = double(box.lower.y()) + double(cell.y()) * (j + 0.5 + 1.23e-4);
      const double z = double(box.lower.z()) + double(cell.z()) * (l + 0.5 + 2.71e-4);
      crossings.clear();
      for (const Triangle& t : mesh.triangles()) {
        // The line (x, y, z): barycentric weights of (y, z) in the triangle's yz projection.
        const Eigen::Vector3d a = v[t[0]].cast<double>(), b = v[t[1]].cast<double>(),
                              c = v[t[2]].cast<double>();
        const double d = (b.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (b.z() - a.z());
        if (d == 0) continue;  // the triangle is edge-on to the line
        const double wb = ((y - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (z - a.z())) / d;
        const double wc = ((b.y() - a.y()) * (z - a.z()) - (y - a.y()) * (b.z() - a.z())) / d;
        if (wb < 0 || wc < 0 || wb + wc > 1) continue;
        crossings.push_back(a.x() + wb * (b.x() - a.x()) + wc * (c.x() - a.x()));
      }
      std::sort(crossings.begin(), crossings.end());
      std::size_t before = 0;
      for (int i = 0; i < n[0]; ++i) {
        const double x = double(box.lower.x()) + double(cell.x()) * (i + 0.5);
        while (before < crossings.size() && crossings[before] < x) ++before;
        inside[std::size_t(i + n[0] * (j + n[1] * l))] = before % 2;
      }
    }
  return inside;
}

// The `ties` lattice vertices nearest to p (ties broken by index): shells of cells of growing
// Chebyshev radius around p's cell, until no closer vertex can lie farther out.
std::vector<Index> nearestLattice(const Vec3& p, const Aabb& box, const std::array<int, 3>& n,
                                  const std::vector<Index>& ids, const std::vector<Vec3>& positions,
                                  int ties) {
  const Vec3 cell = (box.upper - box.lower).cwiseQuotient(Vec3(Real(n[0]), Real(n[1]), Real(n[2])));
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a)
    c[std::size_t(a)] = std::clamp(int(std::floor((p[a] - box.lower[a]) / cell[a])), 0, n[std::size_t(a)] - 1);
  std::vector<std::pair<Real, Index>> found;
  const Real step = cell.minCoeff();
  const int widest = std::max({n[0], n[1], n[2]});
  for (int r = 0; r <= widest; ++r) {
    for (int l = c[2] - r; l <= c[2] + r; ++l)
      for (int j = c[1] - r; j <= c[1] + r; ++j)
        for (int i = c[0] - r; i <= c[0] + r; ++i) {
          if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(l - c[2])}) != r) continue;
          if (i < 0 || j < 0 || l < 0 || i >= n[0] || j >= n[1] || l >= n[2]) continue;
          const Index id = ids[std::size_t(i + n[0] * (j + n[1] * l))];
          if (id != TriangleMesh::kNone) found.push_back({(positions[id] - p).norm(), id});
        }
    std::sort(found.begin(), found.end());
    // A vertex in shell r + 1 or beyond is at least (r + 1 / 2) cells away.
    if (int(found.size()) >= ties && found[std::size_t(ties - 1)].first <= (Real(r) + Real(0.5)) * step)
      break;
  }
  std::vector<Index> nearest;
  for (int k = 0; k < ties && k < int(found.size()); ++k) nearest.push_back(found[std::size_t(k)].second);
  return nearest;
}

}  // namespace

MassSpringModel softMesh(const SoftMeshSettings& s) {
  checkCommon("SoftMeshSettings", s.mass, s.stiffness, s.damping);
  checkPose("SoftMeshSettings", s.pose);
  require(s.mesh != nullptr, "SoftMeshSettings: mesh must be given");
  require(s.resolution >= 1 && s.resolution <= 64, "SoftMeshSettings: resolution must be in 1..64");
  require(s.ties >= 1 && s.ties <= 8, "SoftMeshSettings: ties must be in 1..8");
  const TriangleMesh& mesh = *s.mesh;
  require(mesh.isClosed(),
          "SoftMeshSettings: the mesh must be closed (every edge shared by two faces that run it in "
          "opposite directions)");
  double volume = 0;  // sum of a . (b x c) / 6 over the faces: > 0 when they face outwards
  for (const Triangle& t : mesh.triangles())
    volume += mesh.vertices()[t[0]].cast<double>().dot(
                  mesh.vertices()[t[1]].cast<double>().cross(mesh.vertices()[t[2]].cast<double>())) /
              6;
  require(volume > 0, "SoftMeshSettings: the mesh's faces turn inwards (its volume comes out "
                      "negative); they must be counter-clockwise seen from outside");
  const Aabb box = mesh.bounds();
  const Vec3 extent = box.upper - box.lower;
  const Real side = extent.maxCoeff() / Real(s.resolution);
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a) n[std::size_t(a)] = std::max(1, int(std::lround(extent[a] / side)));
  const std::vector<std::uint8_t> inside = insideCells(mesh, box, n);

  MassSpringModel m;
  m.positions = mesh.vertices();
  m.triangles = mesh.triangles();
  const Vec3 cell = extent.cwiseQuotient(Vec3(Real(n[0]), Real(n[1]), Real(n[2])));
  std::vector<Index> ids(inside.size(), TriangleMesh::kNone);
  for (int l = 0; l < n[2]; ++l)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t c = std::size_t(i + n[0] * (j + n[1] * l));
        if (!inside[c]) continue;
        ids[c] = Index(m.positions.size());
        m.positions.push_back(box.lower + cell.cwiseProduct(Vec3(Real(i), Real(j), Real(l)) +
                                                            Vec3::Constant(Real(0.5))));
      }
  require(m.positions.size() > mesh.vertices().size(),
          "SoftMeshSettings: no lattice cell centre lies inside the mesh; raise resolution");
  surfaceSprings(m, s.stiffness, s.damping);
  latticeSprings(
      m, n, [&](int i, int j, int l) { return inside[std::size_t(i + n[0] * (j + n[1] * l))] != 0; },
      [&](int i, int j, int l) { return ids[std::size_t(i + n[0] * (j + n[1] * l))]; }, s.stiffness,
      s.damping);
  for (Index v = 0; v < Index(mesh.vertices().size()); ++v)
    for (Index tie : nearestLattice(m.positions[v], box, n, ids, m.positions, s.ties))
      addSpring(m, v, tie, s.stiffness.stretch, s.damping, SpringKind::Stretch);
  for (Vec3& p : m.positions) p = s.pose.apply(p);
  spreadMass(m, s.mass);
  return m;
}

}  // namespace inertia
