#include "inertia/deformable/generators.h"

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
  require(std::isfinite(k.stretch) && k.stretch >= 0 && std::isfinite(k.shear) && k.shear >= 0 &&
              std::isfinite(k.bend) && k.bend >= 0,
          w + ": stiffness values must be finite and >= 0 (N/m)");
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

// The lattice's springs from vertex (i, j, l) to its neighbours ahead of it, so each pair once.
void latticeSprings(MassSpringModel& m, const std::array<int, 3>& r, const SoftBoxSettings& s) {
  const auto inside = [&r](int i, int j, int l) {
    return i >= 0 && j >= 0 && l >= 0 && i <= r[0] && j <= r[1] && l <= r[2];
  };
  const auto id = [&r](int i, int j, int l) {
    return Index(i + (r[0] + 1) * (j + (r[1] + 1) * l));
  };
  const SpringStiffness& k = s.stiffness;
  for (int l = 0; l <= r[2]; ++l)
    for (int j = 0; j <= r[1]; ++j)
      for (int i = 0; i <= r[0]; ++i)
        for (int dl = -1; dl <= 1; ++dl)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              // Neighbours ahead: the first non-zero offset (in l, j, i order) is positive.
              const int first = dl != 0 ? dl : (dj != 0 ? dj : di);
              if (first <= 0 || !inside(i + di, j + dj, l + dl)) continue;
              const int axes = std::abs(di) + std::abs(dj) + std::abs(dl);
              const bool axis = axes == 1;
              addSpring(m, id(i, j, l), id(i + di, j + dj, l + dl), axis ? k.stretch : k.shear,
                        s.damping, axis ? SpringKind::Stretch : SpringKind::Shear);
              if (axis && inside(i + 2 * di, j + 2 * dj, l + 2 * dl))
                addSpring(m, id(i, j, l), id(i + 2 * di, j + 2 * dj, l + 2 * dl), k.bend, s.damping,
                          SpringKind::Bend);
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
  latticeSprings(m, r, s);
  latticeFaces(m, r);
  return m;
}

namespace {

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
  // Each surface edge once (from the face where it runs a -> b with a < b), its opposite vertices.
  std::map<std::pair<Index, Index>, std::array<Index, 2>> opposite;
  for (const auto& f : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const Index a = f[e], b = f[(e + 1) % 3], c = f[(e + 2) % 3];
      auto& o = opposite[std::minmax(a, b)];
      o[a < b ? 0 : 1] = c;
    }
  const SpringStiffness& k = s.stiffness;
  for (const auto& [edge, o] : opposite) {
    addSpring(m, edge.first, edge.second, k.stretch, s.damping, SpringKind::Stretch);
    addSpring(m, o[0], o[1], k.bend, s.damping, SpringKind::Bend);
  }
  for (Index i = 0; i < centre; ++i)
    addSpring(m, centre, i, k.stretch, s.damping, SpringKind::Stretch);
  return m;
}

}  // namespace inertia
