// Manifolds with compounds: collide() on each child near the other shape, the child's pose
// composed with the compound's, the piece recorded in the manifold's sub-shape key.
#include <bit>

#include "inertia/geometry/bounds.h"
#include "mesh_contacts.h"

namespace inertia::detail {

std::uint32_t compoundSubShape(std::uint32_t child, std::uint32_t childCount,
                               std::uint32_t inner) {
  const int bits = childCount > 1 ? std::bit_width(childCount - 1) : 0;
  return child | (inner << bits);
}

void collideWithCompound(const Collider& a, const Transform& poseA, const Collider& b,
                         const Transform& poseB, const ContactSettings& settings,
                         std::vector<ContactManifold>& out) {
  const Compound& compound = b.shape().get<Compound>();
  const auto& children = b.children();
  const std::uint32_t count = std::uint32_t(children.size());
  const Aabb boundsA = worldBounds(a.shape(), poseA).inflated(settings.speculativeDistance);
  for (std::uint32_t k = 0; k < count; ++k) {
    const Transform pose = poseB * compound.children()[k].transform;
    if (!worldBounds(children[k].shape(), pose).overlaps(boundsA)) continue;
    const std::size_t first = out.size();
    collide(a, poseA, children[k], pose, settings, out);
    for (std::size_t i = first; i < out.size(); ++i)
      out[i].subShapeB = compoundSubShape(k, count, out[i].subShapeB);
  }
}

void collideCompounds(const Collider& a, const Transform& poseA, const Collider& b,
                      const Transform& poseB, const ContactSettings& settings,
                      std::vector<ContactManifold>& out) {
  const Compound& compound = a.shape().get<Compound>();
  const auto& children = a.children();
  const std::uint32_t count = std::uint32_t(children.size());
  const Aabb boundsB = worldBounds(b.shape(), poseB).inflated(settings.speculativeDistance);
  for (std::uint32_t k = 0; k < count; ++k) {
    const Transform pose = poseA * compound.children()[k].transform;
    if (!worldBounds(children[k].shape(), pose).overlaps(boundsB)) continue;
    const std::size_t first = out.size();
    collide(children[k], pose, b, poseB, settings, out);
    for (std::size_t i = first; i < out.size(); ++i)
      out[i].subShapeA = compoundSubShape(k, count, out[i].subShapeA);
  }
}

}  // namespace inertia::detail
