// Internal: convex pieces in world space and the distance machinery over them: GJK (distance
// between cores), EPA (penetration of cores) and their combination with the radii.
//
// How to use it (contact generation, meshes, height fields):
//
//   detail::ConvexProxy a = detail::ConvexProxy::fromCollider(colliderA, poseA);
//   detail::ConvexProxy t = detail::ConvexProxy::triangle(p0, p1, p2);   // world points
//   detail::ConvexSeparation s = detail::separation(a, t);
//   // s.distance < 0: overlapping by -s.distance; s.normal points from a to t (unit);
//   // s.pointA / s.pointB lie on the rounded surfaces (core point +- radius * normal).
//
// Lower level: gjk(a, b) gives the closest points of the *cores* (radius ignored) and the final
// simplex; epa(a, b, gjkResult.simplex) gives the penetration of the cores when gjk reports
// them overlapping; shapeCast(a, translationA, b, tolerance) sweeps a proxy by a translation.
// Proxies are plain values: move one by adding to `points` and `position`. A proxy borrows a hull
// from its Collider: keep the Collider alive. Nothing here allocates or throws (fromCollider throws
// for non-convex shapes).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "inertia/collision/collider.h"
#include "inertia/core/types.h"

namespace inertia::detail {

/// A convex piece in world space: a core (point, segment, box, cylinder, hull or triangle)
/// swept by a ball of `radius` (m). Spheres are points with a radius, capsules are segments with
/// a radius; the other cores have radius 0 (a caller may add a skin radius to any of them).
struct ConvexProxy {
  enum class Core : std::uint8_t { Point, Segment, Triangle, Box, Cylinder, Hull };

  Core core = Core::Point;
  /// World points of the Point (1), Segment (2) and Triangle (3) cores (m).
  std::array<Vec3, 3> points{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  /// Local -> world of the Box, Cylinder and Hull cores: x_world = rotation * x + position.
  Mat3 rotation = Mat3::Identity();
  Vec3 position = Vec3::Zero();
  Vec3 halfExtents = Vec3::Zero();   ///< Box half extents (m).
  Real cylinderRadius = 0;           ///< Cylinder radius (m).
  Real halfHeight = 0;               ///< Cylinder half height along local y (m).
  const ConvexHull* hull = nullptr;  ///< Hull core, borrowed from the Collider's Shape.
  Real radius = 0;                   ///< Rounding radius added to the core (m), >= 0.

  /// The proxy of a sphere, capsule, box, cylinder or hull collider at `pose`; throws
  /// InvalidArgument for any other shape.
  static ConvexProxy fromCollider(const Collider& collider, const Transform& pose);
  static ConvexProxy point(const Vec3& p, Real radius = 0);
  static ConvexProxy segment(const Vec3& a, const Vec3& b, Real radius = 0);
  /// A triangle from three world points (m); may be degenerate (a sliver or a point).
  static ConvexProxy triangle(const Vec3& a, const Vec3& b, const Vec3& c, Real radius = 0);

  /// Support point of the core in world direction d (need not be unit): argmax_x d . x.
  Vec3 support(const Vec3& d) const;
  /// A point of the core (its centre or centroid), used to seed the search (m, world).
  Vec3 centre() const;
};

/// One vertex of a GJK simplex: support points of A and B and w = a - b, a point of the
/// Minkowski difference A - B of the cores.
struct SimplexVertex {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

/// The support point of A - B in direction d: A's support along d less B's along -d.
SimplexVertex supportVertex(const ConvexProxy& a, const ConvexProxy& b, const Vec3& d);

/// Up to four affinely independent vertices and the barycentric weights of the point of their
/// hull closest to the origin (the weights sum to 1).
struct Simplex {
  std::array<SimplexVertex, 4> v{};
  std::array<Real, 4> lambda{};
  int count = 0;
};

/// The result of gjk() on the cores.
struct GjkResult {
  Real distance = 0;           ///< Distance between the cores (m), >= 0.
  Vec3 pointA = Vec3::Zero();  ///< Closest point on A's core (m, world).
  Vec3 pointB = Vec3::Zero();  ///< Closest point on B's core (m, world).
  Simplex simplex;             ///< The final simplex (input to epa() when overlapping).
  int iterations = 0;          ///< Support evaluations made.
  /// True when the cores intersect: the origin lies in the simplex (count 4) or the distance
  /// fell below the absolute tolerance (kGjkAbsoluteTolerance scaled by the shapes' size).
  bool overlapping = false;
};

/// Iteration cap of GJK; convex polytopes converge in far fewer steps, curved cores stop on
/// the relative tolerance first.
inline constexpr int kGjkMaxIterations = 64;

/// Distance between the cores of a and b by GJK (Gilbert, Johnson and Keerthi 1988) with the
/// signed-volume distance sub-algorithm (Montanari, Petrinic and Barbieri, "Improving the GJK
/// algorithm for faster and more reliable distance queries between convex objects", ACM TOG
/// 2017). Stops when the lower bound v . w / |v| is within a relative tolerance of |v|, when
/// |v| stops decreasing (no progress, as rounding sets in), or after kGjkMaxIterations.
/// `guess` (optional, non-zero): an estimate of the normal from A to B (e.g. last frame's),
/// seeds the first search direction; by default the direction between the cores' centres.
GjkResult gjk(const ConvexProxy& a, const ConvexProxy& b, const Vec3& guess = Vec3::Zero());

/// Penetration of two overlapping cores.
struct EpaResult {
  Real depth = 0;               ///< Core penetration depth (m), >= 0.
  Vec3 normal = Vec3::UnitY();  ///< Unit, from A to B: moving B by depth * normal separates them.
  Vec3 pointA = Vec3::Zero();   ///< Deepest point of A's core (m, world).
  Vec3 pointB = Vec3::Zero();   ///< Deepest point of B's core; pointA - pointB = depth * normal.
  int iterations = 0;
  /// False when the face or vertex cap was hit before the tolerance was met (the result is
  /// then the best face found, still finite).
  bool converged = true;
};

/// Penetration depth of overlapping cores by the expanding polytope algorithm (van den Bergen,
/// "Proximity queries and penetration depth computation on 3D game objects", GDC 2001; the
/// same in his book, 2003, ch. 4.3). Starts from GJK's final simplex; simplices of 1-3 points
/// are blown up to a tetrahedron by support queries, and flat Minkowski differences (a segment
/// against a segment, a triangle against a point) give depth 0 with the normal of their plane.
/// Fixed-capacity buffers (no allocation), never NaN.
EpaResult epa(const ConvexProxy& a, const ConvexProxy& b, const Simplex& simplex);

/// Signed separation of two rounded convex pieces.
struct ConvexSeparation {
  /// Signed distance (m): the gap when positive, minus the penetration depth when negative.
  Real distance = 0;
  Vec3 normal = Vec3::UnitY();  ///< Unit, from A to B (world).
  Vec3 pointA = Vec3::Zero();   ///< On A's rounded surface (m, world).
  Vec3 pointB = Vec3::Zero();   ///< On B's rounded surface (m, world).
  int gjkIterations = 0;
  int epaIterations = 0;  ///< 0 when EPA was not needed.
};

/// GJK on the cores, then the radii: distance = core distance - radii (no EPA needed while the
/// cores are apart, even when the rounded shapes overlap); EPA when the cores overlap.
ConvexSeparation separation(const ConvexProxy& a, const ConvexProxy& b,
                            const Vec3& guess = Vec3::Zero());

/// The result of shapeCast().
struct CastResult {
  Real fraction = 0;            ///< Of the translation, in [0, 1]; 0 for an initial overlap.
  Vec3 normal = Vec3::UnitY();  ///< Unit, from A (moved to the hit) to B (world).
  Vec3 pointA = Vec3::Zero();   ///< On A's rounded surface, A at the hit (m, world).
  Vec3 pointB = Vec3::Zero();   ///< On B's rounded surface (m, world).
  int iterations = 0;
};

/// Casts a translated by `translationA` (m) against b: the least fraction at which the rounded
/// shapes come within `tolerance` (m, > 0) of touching, by GJK ray casting (van den Bergen,
/// "Ray casting against general convex objects with application to continuous collision
/// detection", 2004) with the radii as in Box2D's b2ShapeCast. Conservative: at the returned
/// fraction the shapes are apart by 0 .. tolerance (up to rounding); a pair already within
/// tolerance hits at 0. Nothing when A's path misses B.
std::optional<CastResult> shapeCast(const ConvexProxy& a, const Vec3& translationA,
                                    const ConvexProxy& b, Real tolerance);

/// The closest point to the origin of the hull of simplex.v[0..count) by signed volumes
/// (Montanari 2017): reduces `simplex` to the smallest sub-simplex holding that point and sets
/// its weights. Exposed for the shape cast and for tests.
Vec3 closestToOrigin(Simplex& simplex);
/// closestToOrigin() with the signed volumes wider than Real (double for float, long double
/// for double): for a thin simplex whose volumes lose their sign in Real (gjk() takes it when
/// Real makes no progress).
Vec3 closestToOriginWide(Simplex& simplex);

}  // namespace inertia::detail
