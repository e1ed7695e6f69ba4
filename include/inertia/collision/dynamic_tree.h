// A dynamic AABB tree over moving objects: the broad phase for bodies of mixed sizes. A binary
// bounding-volume hierarchy in the style of Box2D's b2DynamicTree and Bullet's btDbvt: nodes live
// in one flat array with a free list, leaves hold "fat" boxes (the object's box inflated by a
// margin and stretched along its displacement) so that small motions need no tree update.
// Insertion descends by the surface-area heuristic (Catto's cost: the area of the new parent
// plus the increase inherited by the ancestors); AVL-style rotations keep the height logarithmic.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "inertia/collision/queries.h"
#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"

namespace inertia {

/// True when the segment ray.origin + s * ray.direction, s in [0, maxFraction], meets `box`
/// (boundaries included), by the slab test (Kay and Kajiya 1986). On a hit and when `entry` is
/// not null, *entry is the smallest such s. Axes with a zero direction component need the origin
/// inside that slab.
inline bool segmentOverlapsAabb(const Aabb& box, const Ray& ray, Real maxFraction,
                                Real* entry = nullptr) {
  if (!(maxFraction >= 0)) return false;
  Real tMin = 0;
  Real tMax = maxFraction;
  for (int k = 0; k < 3; ++k) {
    const Real o = ray.origin[k];
    const Real d = ray.direction[k];
    if (d == 0) {
      if (o < box.lower[k] || o > box.upper[k]) return false;
      continue;
    }
    const Real inv = Real(1) / d;
    Real t1 = (box.lower[k] - o) * inv;
    Real t2 = (box.upper[k] - o) * inv;
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > tMin) tMin = t1;
    if (t2 < tMax) tMax = t2;
    if (tMin > tMax) return false;
  }
  if (entry != nullptr) *entry = tMin;
  return true;
}

/// Settings of a dynamic tree, filled with designated initialisers.
struct DynamicTreeSettings {
  /// Distance (m, >= 0, finite) by which a leaf's fat box exceeds the object's box on each side.
  Real margin = Real(0.1);
  /// Factor (>= 0, finite) by which a displacement passed to moveProxy (m) stretches the fat box
  /// in the direction of motion (Box2D's aabbMultiplier), predicting the next few steps.
  Real displacementMultiplier = Real(4);
};

/// A dynamic AABB tree (see the file comment). Proxy ids are node indices: stable while the
/// proxy lives and reused after it is destroyed. Queries allocate nothing after warm-up (a
/// fixed stack on the call stack, spilling to the heap only for trees deeper than 64).
/// Not thread-safe for concurrent mutation; concurrent const queries are fine.
class DynamicTree {
 public:
  static constexpr int kNull = -1;  ///< The null node / proxy id.

  DynamicTree() : DynamicTree(DynamicTreeSettings{}) {}
  explicit DynamicTree(const DynamicTreeSettings& settings);

  /// Adds a leaf for the object bounds `box` (m, finite, lower <= upper) carrying `userData`;
  /// its fat box is `box` inflated by the margin. Returns the proxy id.
  int createProxy(const Aabb& box, std::uint32_t userData);
  /// Removes a proxy. Throws InvalidArgument for an id that is not a live proxy.
  void destroyProxy(int id);
  /// Updates a proxy to the object bounds `box` (m) after a move by `displacement` (m, finite).
  /// When `box` still lies inside the fat box nothing changes and it returns false; otherwise
  /// the leaf gets a new fat box (inflated by the margin, stretched by multiplier*displacement),
  /// is reinserted and it returns true.
  bool moveProxy(int id, const Aabb& box, const Vec3& displacement);
  /// True when moveProxy(id, box, displacement) would neither change the proxy nor throw: a
  /// finite box with lower <= upper inside the fat box, after a finite displacement. Const: a
  /// caller may test many proxies concurrently and move only the others.
  bool keeps(int id, const Aabb& box, const Vec3& displacement) const;

  /// The fat box of a live proxy (m). Inline, as the world reads it for every pair every step.
  const Aabb& fatAabb(int id) const {
    requireProxy(id, "DynamicTree::fatAabb");
    return nodes_[static_cast<std::size_t>(id)].box;
  }
  /// The user value of a live proxy.
  std::uint32_t userData(int id) const {
    requireProxy(id, "DynamicTree::userData");
    return nodes_[static_cast<std::size_t>(id)].userData;
  }
  /// True when `id` names a live proxy.
  bool isProxy(int id) const {
    return id >= 0 && id < static_cast<int>(nodes_.size()) && nodes_[id].isLeaf();
  }

  /// Calls f(id) for every proxy whose fat box overlaps `box` (touching counts). If f returns
  /// bool, false stops the query.
  template <class F>
  void query(const Aabb& box, F&& f) const;

  /// Visits the proxies whose fat boxes the segment `ray` crosses (slab test), calling
  /// f(id, maxFraction) with the current max fraction. f returns a Real: 0 stops the cast, a
  /// value in (0, maxFraction) clips the segment to it (farther boxes are then skipped), anything
  /// else (the same value, or a negative one to ignore this proxy) continues unchanged.
  template <class F>
  void rayCast(const Ray& ray, F&& f) const;

  /// Fills `pairs` with every pair of distinct proxies whose fat boxes overlap and of which at
  /// least one is in `moved` (live proxy ids), each pair once as (smaller id, larger id), sorted:
  /// the output depends only on the fat boxes and ids, not on the tree's shape or history.
  void computePairs(std::span<const int> moved, std::vector<std::pair<int, int>>& pairs) const;

  /// Calls f(box, height) for every node of the tree, parents before their children (height 0
  /// for the leaves, whose box is the fat box): for drawing and inspecting the hierarchy.
  template <class F>
  void forEachNode(F&& f) const {
    if (root_ == kNull) return;
    Stack stack;
    stack.push(root_);
    while (!stack.empty()) {
      const Node& node = nodes_[stack.pop()];
      f(node.box, node.height);
      if (!node.isLeaf()) {
        stack.push(node.child2);
        stack.push(node.child1);
      }
    }
  }

  /// Height of the tree: 0 for a single leaf (and for the empty tree).
  int height() const { return root_ == kNull ? 0 : nodes_[root_].height; }
  /// Number of live proxies.
  std::size_t proxyCount() const { return proxyCount_; }
  /// Checks the structure (parent / child links, boxes containing their children, heights,
  /// leaf count, free list) and throws std::logic_error on a violation. O(n); for tests.
  void validate() const;

 private:
  struct Node {
    Aabb box;            ///< Fat box for leaves, union of the children otherwise (m).
    int parent = kNull;  ///< Parent node, or the next free node while on the free list.
    int child1 = kNull;  ///< First child (kNull for leaves).
    int child2 = kNull;  ///< Second child (kNull for leaves).
    int height = -1;     ///< 0 for leaves, 1 + max of children, -1 while free.
    std::uint32_t userData = 0;

    bool isLeaf() const { return height == 0; }
  };

  // A depth-first stack with a fixed inline buffer: no allocation unless deeper than kInline.
  class Stack {
   public:
    void push(int v) {
      if (size_ < kInline) {
        inline_[size_++] = v;
      } else {
        spill_.push_back(v);
      }
    }
    bool empty() const { return size_ == 0; }
    int pop() {
      if (!spill_.empty()) {
        const int v = spill_.back();
        spill_.pop_back();
        return v;
      }
      return inline_[--size_];
    }

   private:
    static constexpr int kInline = 64;
    std::array<int, kInline> inline_{};
    int size_ = 0;
    std::vector<int> spill_;
  };

  int allocateNode();
  void freeNode(int id);
  void insertLeaf(int leaf);
  void removeLeaf(int leaf);
  int balance(int a);
  void requireProxy(int id, const char* what) const {
    if (!isProxy(id)) [[unlikely]]
      throwNotAProxy(id, what);
  }
  [[noreturn]] static void throwNotAProxy(int id, const char* what);

  DynamicTreeSettings settings_;
  std::vector<Node> nodes_;
  int root_ = kNull;
  int freeList_ = kNull;
  std::size_t proxyCount_ = 0;
};

template <class F>
void DynamicTree::query(const Aabb& box, F&& f) const {
  if (root_ == kNull) return;
  Stack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const int id = stack.pop();
    const Node& node = nodes_[id];
    if (!node.box.overlaps(box)) continue;
    if (node.isLeaf()) {
      if constexpr (std::is_same_v<decltype(f(id)), bool>) {
        if (!f(id)) return;
      } else {
        f(id);
      }
    } else {
      stack.push(node.child1);
      stack.push(node.child2);
    }
  }
}

template <class F>
void DynamicTree::rayCast(const Ray& ray, F&& f) const {
  if (root_ == kNull) return;
  Real maxFraction = ray.maxFraction;
  Stack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const int index = stack.pop();
    const Node& node = nodes_[index];
    if (!segmentOverlapsAabb(node.box, ray, maxFraction)) continue;
    if (node.isLeaf()) {
      const Real value = f(index, maxFraction);
      if (value == 0) return;
      if (value > 0 && value < maxFraction) maxFraction = value;
    } else {
      stack.push(node.child1);
      stack.push(node.child2);
    }
  }
}

}  // namespace inertia
