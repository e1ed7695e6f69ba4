// A shape prepared for queries: the shape plus the acceleration structures it needs.
#pragma once

#include <memory>
#include <vector>

#include "inertia/geometry/shapes.h"

namespace inertia {

class MeshBvh;  // the static AABB tree over a mesh's triangles (collision/mesh_bvh.h)

/// A Shape together with what the collision layer needs to query it quickly: a BVH over a
/// mesh's triangles, colliders of a compound's children. Built once (explicitly: building a
/// mesh's BVH costs O(n log n)), immutable, cheap to copy (shared). Bodies and particle
/// obstacles hold Colliders; queries take them.
class Collider {
 public:
  explicit Collider(Shape shape);
  ~Collider();
  Collider(const Collider&);
  Collider& operator=(const Collider&);
  Collider(Collider&&) noexcept;
  Collider& operator=(Collider&&) noexcept;

  const Shape& shape() const { return shape_; }
  ShapeType type() const { return shape_.type(); }

  /// The BVH of a mesh shape (built by the constructor); nullptr for other shapes. Height
  /// fields need no tree: ray casts walk the grid cells along the ray (a 2D DDA) and point
  /// queries search the cells around the point.
  const MeshBvh* meshBvh() const;
  /// The colliders of a compound's children, in the compound's order (empty otherwise).
  const std::vector<Collider>& children() const;

 private:
  struct Accel;
  Shape shape_;
  std::shared_ptr<const Accel> accel_;
};

}  // namespace inertia
