// collide(): the [ShapeType][ShapeType] table of pair functions (Box2D v3's manifold table).
// One function per unordered pair, A the lower ShapeType; the other order runs the same
// function with the shapes swapped and flips what it appended.
#include "inertia/collision/contact.h"

#include <array>
#include <utility>

#include "contact_pairs.h"
#include "mesh_contacts.h"

namespace inertia {

namespace detail {

void flipManifold(ContactManifold& m) {
  m.normal = -m.normal;
  for (int k = 0; k < m.pointCount; ++k) {
    ContactPoint& p = m.points[std::size_t(k)];
    std::swap(p.pointA, p.pointB);
    p.id = (p.id >> 16) | (p.id << 16);
  }
  std::swap(m.subShapeA, m.subShapeB);
}

}  // namespace detail

namespace {

using PairFn = void (*)(const Collider& a, const Transform& poseA, const Collider& b,
                        const Transform& poseB, const ContactSettings& settings,
                        std::vector<ContactManifold>& out);

template <detail::ConvexPairFn F>
void appendConvex(const Collider& a, const Transform& poseA, const Collider& b,
                  const Transform& poseB, const ContactSettings& settings,
                  std::vector<ContactManifold>& out) {
  ContactManifold m;
  if (F(a, poseA, b, poseB, settings, m)) out.push_back(m);
}

void none(const Collider&, const Transform&, const Collider&, const Transform&,
          const ContactSettings&, std::vector<ContactManifold>&) {}
bool noneConvex(const Collider&, const Transform&, const Collider&, const Transform&,
                const ContactSettings&, ContactManifold&) {
  return false;
}

// A pair's function, and for two convex shapes the one-manifold function it wraps.
struct Entry {
  PairFn many = none;
  detail::ConvexPairFn one = noneConvex;

  constexpr Entry() = default;
  constexpr Entry(PairFn f) : many(f) {}  // implicit: `set(a, b, f)` for the other pairs
};
template <detail::ConvexPairFn F>
constexpr Entry convex() {
  Entry e;
  e.many = appendConvex<F>;
  e.one = F;
  return e;
}

constexpr int kN = kShapeTypeCount;
using Table = std::array<std::array<Entry, kN>, kN>;

constexpr Table makeTable() {
  using enum ShapeType;
  Table t{};  // every pair is set below
  const auto set = [&t](ShapeType a, ShapeType b, Entry f) { t[int(a)][int(b)] = f; };
  set(Plane, Plane, none);  // two static half-spaces
  set(Plane, Sphere, convex<detail::collidePlaneSphere>());
  set(Plane, Capsule, convex<detail::collidePlaneCapsule>());
  set(Plane, Box, convex<detail::collidePlaneBox>());
  set(Plane, Cylinder, convex<detail::collidePlaneCylinder>());
  set(Plane, Hull, convex<detail::collidePlaneHull>());
  set(Plane, HeightField, none);  // both static
  for (ShapeType b : {Capsule, Box, Cylinder, Hull})
    set(Sphere, b, convex<detail::collideSphereConvex>());
  set(Sphere, Sphere, convex<detail::collideSpheres>());
  set(Capsule, Capsule, convex<detail::collideCapsules>());
  set(Capsule, Box, convex<detail::collideCapsulePolyhedron>());
  set(Capsule, Hull, convex<detail::collideCapsulePolyhedron>());
  set(Capsule, Cylinder, convex<detail::collideCylinderConvex>());
  set(Box, Box, convex<detail::collidePolyhedronPair>());
  set(Box, Hull, convex<detail::collidePolyhedronPair>());
  set(Hull, Hull, convex<detail::collidePolyhedronPair>());
  set(Box, Cylinder, convex<detail::collideCylinderConvex>());
  set(Cylinder, Cylinder, convex<detail::collideCylinderConvex>());
  set(Cylinder, Hull, convex<detail::collideCylinderConvex>());
  set(HeightField, HeightField, none);  // both static
  set(Plane, Mesh, none);                // both static
  set(Mesh, HeightField, none);          // both static
  for (ShapeType a : {Sphere, Capsule, Box, Cylinder, Hull}) {
    set(a, Mesh, detail::collideConvexMesh);
    set(a, HeightField, detail::collideConvexHeightField);
  }
  set(Mesh, Mesh, detail::collideMeshes);
  for (ShapeType a : {Plane, Sphere, Capsule, Box, Cylinder, Hull, Mesh, HeightField})
    set(a, Compound, detail::collideWithCompound);
  set(Compound, Compound, detail::collideCompounds);
  return t;
}

constexpr Table kTable = makeTable();

}  // namespace

void collide(const Collider& a, const Transform& poseA, const Collider& b,
             const Transform& poseB, const ContactSettings& settings,
             std::vector<ContactManifold>& out) {
  const int ta = int(a.type()), tb = int(b.type());
  if (ta <= tb) {
    kTable[std::size_t(ta)][std::size_t(tb)].many(a, poseA, b, poseB, settings, out);
    return;
  }
  const std::size_t first = out.size();
  kTable[std::size_t(tb)][std::size_t(ta)].many(b, poseB, a, poseA, settings, out);
  for (std::size_t k = first; k < out.size(); ++k) detail::flipManifold(out[k]);
}

bool collideConvex(const Collider& a, const Transform& poseA, const Collider& b,
                   const Transform& poseB, const ContactSettings& settings, ContactManifold& out) {
  const int ta = int(a.type()), tb = int(b.type());
  if (ta <= tb) return kTable[std::size_t(ta)][std::size_t(tb)].one(a, poseA, b, poseB, settings, out);
  if (!kTable[std::size_t(tb)][std::size_t(ta)].one(b, poseB, a, poseA, settings, out)) return false;
  detail::flipManifold(out);
  return true;
}

}  // namespace inertia
