// Collider: a shape plus its acceleration structures (a mesh's BVH, a compound's children).
#include "inertia/collision/collider.h"

#include "inertia/collision/mesh_bvh.h"

namespace inertia {

struct Collider::Accel {
  std::unique_ptr<const MeshBvh> bvh;
  std::vector<Collider> children;
};

Collider::Collider(Shape shape) : shape_(std::move(shape)) {
  if (const auto* mesh = shape_.getIf<TriangleMesh>()) {
    auto accel = std::make_shared<Accel>();
    accel->bvh = std::make_unique<const MeshBvh>(*mesh);
    accel_ = std::move(accel);
  } else if (const auto* compound = shape_.getIf<Compound>()) {
    auto accel = std::make_shared<Accel>();
    accel->children.reserve(compound->children().size());
    for (const CompoundChild& child : compound->children())
      accel->children.emplace_back(child.shape);
    accel_ = std::move(accel);
  }
}

Collider::~Collider() = default;
Collider::Collider(const Collider&) = default;
Collider& Collider::operator=(const Collider&) = default;
Collider::Collider(Collider&&) noexcept = default;
Collider& Collider::operator=(Collider&&) noexcept = default;

const MeshBvh* Collider::meshBvh() const { return accel_ ? accel_->bvh.get() : nullptr; }

const std::vector<Collider>& Collider::children() const {
  static const std::vector<Collider> kNone;
  return accel_ ? accel_->children : kNone;
}

}  // namespace inertia
