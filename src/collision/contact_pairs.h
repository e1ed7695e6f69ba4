// Internal: the pair functions of collide()'s [ShapeType][ShapeType] table, and the
// triangle-versus-convex entry the mesh and height-field pairs are built on.
//
// A convex pair function writes one manifold (world frame, normal from A to B) and returns
// whether the pair is within settings.speculativeDistance. Each unordered pair has one function,
// with A the shape of the lower ShapeType; collide() calls it with the arguments swapped for the
// other order and flips the result (flipManifold).
#pragma once

#include <vector>

#include "inertia/collision/contact.h"

namespace inertia::detail {

using ConvexPairFn = bool (*)(const Collider& a, const Transform& poseA, const Collider& b,
                              const Transform& poseB, const ContactSettings& settings,
                              ContactManifold& m);

/// The manifold seen from the other side: normal negated, pointA and pointB exchanged, the
/// halves of each id (A's feature << 16 | B's feature) exchanged, sub-shapes exchanged.
void flipManifold(ContactManifold& m);

// plane_contacts.cpp: the support features of the shape below the plane (A = plane).
bool collidePlaneSphere(const Collider&, const Transform&, const Collider&, const Transform&,
                        const ContactSettings&, ContactManifold&);
bool collidePlaneCapsule(const Collider&, const Transform&, const Collider&, const Transform&,
                         const ContactSettings&, ContactManifold&);
bool collidePlaneBox(const Collider&, const Transform&, const Collider&, const Transform&,
                     const ContactSettings&, ContactManifold&);
bool collidePlaneCylinder(const Collider&, const Transform&, const Collider&, const Transform&,
                          const ContactSettings&, ContactManifold&);
bool collidePlaneHull(const Collider&, const Transform&, const Collider&, const Transform&,
                      const ContactSettings&, ContactManifold&);

// sphere_contacts.cpp: the closest point of B to the sphere's centre (queryPoint), one point.
bool collideSphereConvex(const Collider&, const Transform&, const Collider&, const Transform&,
                         const ContactSettings&, ContactManifold&);
/// Two spheres: the same manifold as collideSphereConvex, from the centres alone.
bool collideSpheres(const Collider&, const Transform&, const Collider&, const Transform&,
                    const ContactSettings&, ContactManifold&);

// capsule_contacts.cpp
bool collideCapsules(const Collider&, const Transform&, const Collider&, const Transform&,
                     const ContactSettings&, ContactManifold&);
/// Capsule (A) against a box or hull (B).
bool collideCapsulePolyhedron(const Collider&, const Transform&, const Collider&,
                              const Transform&, const ContactSettings&, ContactManifold&);

// polyhedron_contacts.cpp (via polyhedron.h): box-box, box-hull, hull-hull.
bool collidePolyhedronPair(const Collider&, const Transform&, const Collider&, const Transform&,
                           const ContactSettings&, ContactManifold&);

// cylinder_contacts.cpp: GJK/EPA for the normal, then the supporting features clipped.
/// A cylinder and any convex shape other than a sphere, in either order (sphere-cylinder goes
/// through collideSphereConvex; plane-cylinder through collidePlaneCylinder).
bool collideCylinderConvex(const Collider&, const Transform&, const Collider&, const Transform&,
                           const ContactSettings&, ContactManifold&);

/// Rim points of a cylinder's cap polygon in cylinderSupportFeature().
inline constexpr int kCylinderRimPoints = 16;
/// |sine| of the angle within which a direction counts as along a cylinder's axis (the cap is
/// the supporting feature) or perpendicular to it (the side segment).
inline constexpr Real kCylinderFeatureSine = Real(0.05);
/// The supporting feature of the cylinder in local direction `d` (the points maximising
/// d . x), in its local frame: the cap as kCylinderRimPoints rim points at fixed angles when d
/// is within kCylinderFeatureSine of the axis, the side segment (2 points) when d is that close
/// to perpendicular, else the single rim point. Writes the points and a feature key for each
/// into the arrays (capacity kCylinderRimPoints); returns their count.
int cylinderSupportFeature(const Cylinder& cylinder, const Vec3& d, Vec3* points,
                           std::uint32_t* features);

/// The manifold between the triangle `tri` (shape A; two-sided, vertices in the frame `pose`
/// maps `convex` into, e.g. a mesh's local frame) and the convex collider `convex` (B: sphere,
/// capsule, box, cylinder or hull) at `pose`; the manifold is in that same frame. Runs the same
/// routines as the convex pairs (the triangle as a flat polyhedron for the SAT and clipping; a
/// GJK triangle proxy for cylinders). Returns false, leaving `out` unspecified, when they are
/// farther apart than settings.speculativeDistance or `convex` is not convex. Feature ids of
/// the triangle: vertex k, edge k (from vertex k to k + 1), face 0 (front) / 1 (back).
bool collideTriangle(const Vec3 (&tri)[3], const Collider& convex, const Transform& pose,
                     const ContactSettings& settings, ContactManifold& out);

}  // namespace inertia::detail
