// Mass properties of shapes: volume, mass, centre of mass and inertia tensor.
#pragma once

#include <span>

#include "inertia/core/types.h"
#include "inertia/geometry/shapes.h"

namespace inertia {

/// Mass properties of a solid of uniform density, in the shape's local frame.
struct MassProperties {
  Real volume = 0;                   ///< Volume (m^3).
  Real mass = 0;                     ///< Mass (kg).
  Vec3 centerOfMass = Vec3::Zero();  ///< Centre of mass (m), local frame.
  Mat3 inertia = Mat3::Zero();       ///< Inertia tensor about the centre of mass (kg m^2),
                                     ///< local axes.
};

/// Mass properties for a uniform `density` (kg/m^3), which must be positive and finite.
/// Closed forms for the primitives; for hulls and closed meshes the divergence-theorem integrals
/// over a tetrahedron fan (Tonon 2004, equivalent to Mirtich 1996); for compounds the children
/// rotated and shifted, then summed by the parallel-axis theorem. Planes and height fields are
/// static only and throw InvalidArgument, as do compounds containing them and meshes that are
/// not closed and outward-oriented.
MassProperties massProperties(const Shape& shape, Real density);
MassProperties massProperties(const Sphere& sphere, Real density);
MassProperties massProperties(const Capsule& capsule, Real density);
MassProperties massProperties(const Box& box, Real density);
MassProperties massProperties(const Cylinder& cylinder, Real density);
MassProperties massProperties(const ConvexHull& hull, Real density);
MassProperties massProperties(const TriangleMesh& mesh, Real density);
MassProperties massProperties(const Compound& compound, Real density);

/// The mass properties of the same body moved by `xf`: centre xf.apply(c), inertia R I R^T.
MassProperties transformed(const MassProperties& props, const Transform& xf);

/// Parallel-axis (Huygens-Steiner) theorem: the inertia about a point displaced by `d` (m) from
/// the centre of mass, I + m ((d . d) E - d d^T).
Mat3 parallelAxis(const Mat3& inertiaAboutCom, Real mass, const Vec3& d);

/// The union of several bodies (expressed in one frame): masses and volumes add, the centre of
/// mass is the mass-weighted mean, inertias are shifted to it by the parallel-axis theorem and
/// added. Throws InvalidArgument for an empty list or zero total mass.
MassProperties combine(std::span<const MassProperties> parts);

}  // namespace inertia
