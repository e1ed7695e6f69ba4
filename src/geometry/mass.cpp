// Mass properties: closed forms for the primitives, tetrahedron integrals for polyhedra,
// parallel-axis sums for compounds.
#include "inertia/geometry/mass.h"

#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>

#include "inertia/core/error.h"
#include "polyhedron_mass.h"

namespace inertia {
namespace {

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;
constexpr double kPi = std::numbers::pi;

void requireDensity(Real density) {
  require(std::isfinite(density) && density > 0,
          "density must be positive and finite (kg/m^3), got " + std::to_string(density));
}

// Packs double-precision results into Real.
MassProperties make(double volume, double density, const Vec3d& com, const Mat3d& unitInertia) {
  MassProperties p;
  p.volume = Real(volume);
  p.mass = Real(volume * density);
  p.centerOfMass = com.cast<Real>();
  p.inertia = (density * unitInertia).cast<Real>();
  return p;
}

MassProperties fromIntegrals(const detail::PolyhedronIntegrals& in, double density) {
  return make(in.volume(), density, in.centroid(), in.unitInertia());
}

}  // namespace

// Solid ball: V = 4/3 pi r^3, I = 2/5 m r^2 on every axis.
MassProperties massProperties(const Sphere& sphere, Real density) {
  validate(sphere);
  requireDensity(density);
  const double r = sphere.radius;
  const double v = 4.0 / 3.0 * kPi * r * r * r;
  return make(v, density, Vec3d::Zero(), Mat3d::Identity() * (0.4 * v * r * r));
}

// Solid box of sides a = 2hx, b = 2hy, c = 2hz: I_xx = m/12 (b^2 + c^2) = m/3 (hy^2 + hz^2).
MassProperties massProperties(const Box& box, Real density) {
  validate(box);
  requireDensity(density);
  const Vec3d h = box.halfExtents.cast<double>();
  const double v = 8.0 * h.prod();
  const Vec3d h2 = h.cwiseProduct(h);
  const Vec3d diag(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y());
  return make(v, density, Vec3d::Zero(), Mat3d(diag.asDiagonal()) * (v / 3.0));
}

// Solid cylinder of height h = 2 halfHeight, axis y: I_yy = m r^2 / 2,
// I_xx = I_zz = m/12 (3 r^2 + h^2).
MassProperties massProperties(const Cylinder& cylinder, Real density) {
  validate(cylinder);
  requireDensity(density);
  const double r = cylinder.radius, h = 2.0 * double(cylinder.halfHeight);
  const double v = kPi * r * r * h;
  const double across = v * (3 * r * r + h * h) / 12.0;
  return make(v, density, Vec3d::Zero(), Vec3d(across, v * r * r / 2.0, across).asDiagonal());
}

// Capsule = cylinder (radius r, height h = 2 halfHeight) + two hemispheres. A hemisphere of
// mass m_h has I = 2/5 m_h r^2 about any axis through the centre of its flat face; its own
// centre of mass lies 3r/8 from that face. Shifting to the centre of mass (parallel-axis
// theorem, subtract) and then out to the capsule's centre at distance h/2 + 3r/8 (add):
//   I_perp = m_h (2/5 r^2 - (3r/8)^2 + (h/2 + 3r/8)^2) = m_h (2/5 r^2 + h^2/4 + 3 h r / 8).
// The axial moment is 2/5 m_h r^2 per hemisphere.
MassProperties massProperties(const Capsule& capsule, Real density) {
  validate(capsule);
  requireDensity(density);
  const double r = capsule.radius, h = 2.0 * double(capsule.halfHeight);
  const double vCyl = kPi * r * r * h;
  const double vHemi = 2.0 / 3.0 * kPi * r * r * r;
  const double axial = vCyl * r * r / 2.0 + 2.0 * vHemi * 0.4 * r * r;
  const double across = vCyl * (3 * r * r + h * h) / 12.0 +
                        2.0 * vHemi * (0.4 * r * r + h * h / 4.0 + 3.0 * h * r / 8.0);
  return make(vCyl + 2.0 * vHemi, density, Vec3d::Zero(),
              Vec3d(across, axial, across).asDiagonal());
}

MassProperties massProperties(const ConvexHull& hull, Real density) {
  requireDensity(density);
  detail::PolyhedronIntegrals in(hull.interiorPoint().cast<double>());
  const auto& v = hull.vertices();
  for (std::size_t f = 0; f < hull.faces().size(); ++f) {
    // Fan-triangulate the (convex, counter-clockwise) face loop from its first vertex.
    const auto loop = hull.faceEdges(f);
    const Vec3d a = v[loop[0].origin].cast<double>();
    for (std::size_t i = 1; i + 1 < loop.size(); ++i)
      in.addTriangle(a, v[loop[i].origin].cast<double>(), v[loop[i + 1].origin].cast<double>());
  }
  return fromIntegrals(in, density);
}

MassProperties massProperties(const TriangleMesh& mesh, Real density) {
  requireDensity(density);
  require(mesh.isClosed(),
          "TriangleMesh: mass properties need a closed, consistently oriented mesh (every edge "
          "shared by exactly two triangles in opposite directions); this mesh is not");
  const auto& v = mesh.vertices();
  // Reference point: the centre of the bounds, near the body so the signed volumes cancel little.
  detail::PolyhedronIntegrals in(mesh.bounds().center().cast<double>());
  for (const Triangle& t : mesh.triangles())
    in.addTriangle(v[t[0]].cast<double>(), v[t[1]].cast<double>(), v[t[2]].cast<double>());
  require(in.volume() > 0,
          "TriangleMesh: the mesh is inside out (its triangles face inwards: negative volume)");
  return fromIntegrals(in, density);
}

MassProperties massProperties(const Compound& compound, Real density) {
  requireDensity(density);
  std::vector<MassProperties> parts;
  parts.reserve(compound.children().size());
  for (const CompoundChild& child : compound.children())
    parts.push_back(transformed(massProperties(child.shape, density), child.transform));
  return combine(parts);
}

MassProperties massProperties(const Shape& shape, Real density) {
  return shape.visit([&](const auto& s) -> MassProperties {
    using S = std::decay_t<decltype(s)>;
    if constexpr (std::is_same_v<S, Plane> || std::is_same_v<S, HeightField>) {
      throw InvalidArgument(std::string("a ") + shapeTypeName(shape.type()) +
                            " has no mass: it is for static bodies only");
    } else {
      return massProperties(s, density);
    }
  });
}

MassProperties transformed(const MassProperties& props, const Transform& xf) {
  MassProperties out = props;
  const Mat3 r = xf.q.toRotationMatrix();
  out.centerOfMass = xf.apply(props.centerOfMass);
  out.inertia = r * props.inertia * r.transpose();
  return out;
}

Mat3 parallelAxis(const Mat3& inertiaAboutCom, Real mass, const Vec3& d) {
  return inertiaAboutCom + mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
}

MassProperties combine(std::span<const MassProperties> parts) {
  require(!parts.empty(), "combine: no mass properties to combine");
  double mass = 0, volume = 0;
  Vec3d moment = Vec3d::Zero();
  for (const MassProperties& p : parts) {
    mass += p.mass;
    volume += p.volume;
    moment += double(p.mass) * p.centerOfMass.cast<double>();
  }
  require(mass > 0, "combine: the total mass is zero");
  const Vec3d com = moment / mass;
  Mat3d inertia = Mat3d::Zero();
  for (const MassProperties& p : parts) {
    const Vec3d d = p.centerOfMass.cast<double>() - com;
    inertia += p.inertia.cast<double>() +
               double(p.mass) * (d.squaredNorm() * Mat3d::Identity() - d * d.transpose());
  }
  MassProperties out;
  out.volume = Real(volume);
  out.mass = Real(mass);
  out.centerOfMass = com.cast<Real>();
  out.inertia = inertia.cast<Real>();
  return out;
}

}  // namespace inertia
