// Dynamic AABB tree: SAH insertion (Catto, Box2D v2.4 InsertLeaf cost), AVL-style rotations
// (Box2D v2.3 Balance), flat node pool with a free list.
#include "inertia/collision/dynamic_tree.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "inertia/core/error.h"

namespace inertia {

namespace {

bool isFinite(const Vec3& v) { return v.allFinite(); }

// The checks run per move in the broad phase: messages are built only on failure.
void requireBox(const Aabb& box, const char* what) {
  if (!isFinite(box.lower) || !isFinite(box.upper))
    throw InvalidArgument(std::string(what) + ": box must be finite");
  if (!box.isValid()) throw InvalidArgument(std::string(what) + ": box needs lower <= upper");
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::logic_error("DynamicTree::validate: " + what);
}

}  // namespace

DynamicTree::DynamicTree(const DynamicTreeSettings& settings) : settings_(settings) {
  require(std::isfinite(settings.margin) && settings.margin >= 0,
          "DynamicTree: margin must be finite and >= 0");
  require(std::isfinite(settings.displacementMultiplier) && settings.displacementMultiplier >= 0,
          "DynamicTree: displacementMultiplier must be finite and >= 0");
}

int DynamicTree::allocateNode() {
  int id;
  if (freeList_ != kNull) {
    id = freeList_;
    freeList_ = nodes_[id].parent;
  } else {
    // Amortised growth of the one array; no per-node allocation.
    id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
  }
  Node& n = nodes_[id];
  n = Node{};
  return id;
}

void DynamicTree::freeNode(int id) {
  Node& n = nodes_[id];
  n = Node{};
  n.height = -1;
  n.parent = freeList_;
  freeList_ = id;
}

void DynamicTree::throwNotAProxy(int id, const char* what) {
  throw InvalidArgument(std::string(what) + ": id " + std::to_string(id) + " is not a live proxy");
}

int DynamicTree::createProxy(const Aabb& box, std::uint32_t userData) {
  requireBox(box, "DynamicTree::createProxy");
  const int id = allocateNode();
  Node& n = nodes_[id];
  n.box = box.inflated(settings_.margin);
  n.height = 0;
  n.userData = userData;
  insertLeaf(id);
  ++proxyCount_;
  return id;
}

void DynamicTree::destroyProxy(int id) {
  requireProxy(id, "DynamicTree::destroyProxy");
  removeLeaf(id);
  freeNode(id);
  --proxyCount_;
}

bool DynamicTree::moveProxy(int id, const Aabb& box, const Vec3& displacement) {
  requireProxy(id, "DynamicTree::moveProxy");
  requireBox(box, "DynamicTree::moveProxy");
  if (!isFinite(displacement))
    throw InvalidArgument("DynamicTree::moveProxy: displacement must be finite");
  if (nodes_[id].box.contains(box)) return false;

  // Predict motion: stretch the fat box along the displacement, on its leading side only.
  Aabb fat = box.inflated(settings_.margin);
  const Vec3 d = settings_.displacementMultiplier * displacement;
  fat.lower += d.cwiseMin(Vec3::Zero());
  fat.upper += d.cwiseMax(Vec3::Zero());

  removeLeaf(id);
  nodes_[id].box = fat;
  insertLeaf(id);
  return true;
}

bool DynamicTree::keeps(int id, const Aabb& box, const Vec3& displacement) const {
  requireProxy(id, "DynamicTree::keeps");
  return isFinite(box.lower) && isFinite(box.upper) && box.isValid() && isFinite(displacement) &&
         nodes_[id].box.contains(box);
}

void DynamicTree::insertLeaf(int leaf) {
  if (root_ == kNull) {
    root_ = leaf;
    nodes_[leaf].parent = kNull;
    return;
  }

  // Greedy descent by the surface-area heuristic (Catto, "Dynamic Bounding Volume Hierarchies",
  // GDC 2019): pairing the leaf with node N costs area(N u L) for the new parent, and every
  // ancestor's area grows by the inherited amount area(N u L) - area(N).
  const Aabb leafBox = nodes_[leaf].box;
  int index = root_;
  while (!nodes_[index].isLeaf()) {
    const Node& node = nodes_[index];
    const Real area = node.box.surfaceArea();
    const Real combinedArea = node.box.merged(leafBox).surfaceArea();
    // Cost of making a new parent for this node and the leaf.
    const Real cost = 2 * combinedArea;
    // Minimum cost pushed down to the children.
    const Real inheritance = 2 * (combinedArea - area);

    auto childCost = [&](int c) {
      const Node& child = nodes_[c];
      const Real merged = child.box.merged(leafBox).surfaceArea();
      return child.isLeaf() ? merged + inheritance : merged - child.box.surfaceArea() + inheritance;
    };
    const Real cost1 = childCost(node.child1);
    const Real cost2 = childCost(node.child2);
    if (cost < cost1 && cost < cost2) break;
    index = cost1 < cost2 ? node.child1 : node.child2;
  }

  const int sibling = index;
  const int oldParent = nodes_[sibling].parent;
  const int newParent = allocateNode();  // may reallocate nodes_: no references held across it
  {
    Node& p = nodes_[newParent];
    p.parent = oldParent;
    p.box = leafBox.merged(nodes_[sibling].box);
    p.height = nodes_[sibling].height + 1;
    p.child1 = sibling;
    p.child2 = leaf;
  }
  if (oldParent != kNull) {
    Node& op = nodes_[oldParent];
    (op.child1 == sibling ? op.child1 : op.child2) = newParent;
  } else {
    root_ = newParent;
  }
  nodes_[sibling].parent = newParent;
  nodes_[leaf].parent = newParent;

  // Refit and rebalance the ancestors.
  index = nodes_[leaf].parent;
  while (index != kNull) {
    index = balance(index);
    Node& n = nodes_[index];
    n.height = 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height);
    n.box = nodes_[n.child1].box.merged(nodes_[n.child2].box);
    index = n.parent;
  }
}

void DynamicTree::removeLeaf(int leaf) {
  if (leaf == root_) {
    root_ = kNull;
    return;
  }
  const int parent = nodes_[leaf].parent;
  const int grandParent = nodes_[parent].parent;
  const int sibling = nodes_[parent].child1 == leaf ? nodes_[parent].child2 : nodes_[parent].child1;
  nodes_[leaf].parent = kNull;

  if (grandParent == kNull) {
    root_ = sibling;
    nodes_[sibling].parent = kNull;
    freeNode(parent);
    return;
  }
  // The sibling takes the parent's place; refit and rebalance upwards.
  Node& gp = nodes_[grandParent];
  (gp.child1 == parent ? gp.child1 : gp.child2) = sibling;
  nodes_[sibling].parent = grandParent;
  freeNode(parent);

  int index = grandParent;
  while (index != kNull) {
    index = balance(index);
    Node& n = nodes_[index];
    n.height = 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height);
    n.box = nodes_[n.child1].box.merged(nodes_[n.child2].box);
    index = n.parent;
  }
}

// AVL-style rotation (as Box2D v2.3's b2DynamicTree::Balance): if the children of A differ in
// height by more than one, the taller child C (or B) is promoted to A's place, A keeps the
// shorter grandchild and C keeps the taller one. Returns the index of the subtree's new root.
//
//   A(B, C(F, G))  ->  C(A(B, G), F)   when F is the taller of F, G.
int DynamicTree::balance(int iA) {
  Node& A = nodes_[iA];
  if (A.isLeaf() || A.height < 2) return iA;
  const int iB = A.child1;
  const int iC = A.child2;
  const int diff = nodes_[iC].height - nodes_[iB].height;

  auto replaceInParent = [&](int oldChild, int newChild, int parent) {
    if (parent == kNull) {
      root_ = newChild;
      return;
    }
    Node& p = nodes_[parent];
    (p.child1 == oldChild ? p.child1 : p.child2) = newChild;
  };

  if (diff > 1) {
    // Rotate C up.
    Node& B = nodes_[iB];
    Node& C = nodes_[iC];
    const int iF = C.child1;
    const int iG = C.child2;
    Node& F = nodes_[iF];
    Node& G = nodes_[iG];
    C.child1 = iA;
    C.parent = A.parent;
    A.parent = iC;
    replaceInParent(iA, iC, C.parent);
    const bool fTaller = F.height > G.height;
    const int keep = fTaller ? iF : iG;  // stays under C
    const int give = fTaller ? iG : iF;  // moves under A
    C.child2 = keep;
    A.child2 = give;
    nodes_[give].parent = iA;
    A.box = B.box.merged(nodes_[give].box);
    A.height = 1 + std::max(B.height, nodes_[give].height);
    C.box = A.box.merged(nodes_[keep].box);
    C.height = 1 + std::max(A.height, nodes_[keep].height);
    return iC;
  }
  if (diff < -1) {
    // Rotate B up (mirror image).
    Node& B = nodes_[iB];
    Node& C = nodes_[iC];
    const int iD = B.child1;
    const int iE = B.child2;
    Node& D = nodes_[iD];
    Node& E = nodes_[iE];
    B.child1 = iA;
    B.parent = A.parent;
    A.parent = iB;
    replaceInParent(iA, iB, B.parent);
    const bool dTaller = D.height > E.height;
    const int keep = dTaller ? iD : iE;
    const int give = dTaller ? iE : iD;
    B.child2 = keep;
    A.child1 = give;
    nodes_[give].parent = iA;
    A.box = C.box.merged(nodes_[give].box);
    A.height = 1 + std::max(C.height, nodes_[give].height);
    B.box = A.box.merged(nodes_[keep].box);
    B.height = 1 + std::max(A.height, nodes_[keep].height);
    return iB;
  }
  return iA;
}

void DynamicTree::computePairs(std::span<const int> moved,
                               std::vector<std::pair<int, int>>& pairs) const {
  pairs.clear();
  for (const int id : moved) {
    requireProxy(id, "DynamicTree::computePairs");
    const Aabb& box = nodes_[id].box;
    query(box, [&](int other) {
      if (other != id) pairs.emplace_back(std::min(id, other), std::max(id, other));
    });
  }
  // Pairs of two moved proxies were found twice; sorting also makes the order independent of
  // the tree's shape.
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

void DynamicTree::validate() const {
  const int capacity = static_cast<int>(nodes_.size());
  std::vector<char> seen(nodes_.size(), 0);
  std::size_t leaves = 0;
  int reachable = 0;

  if (root_ != kNull) {
    check(root_ >= 0 && root_ < capacity, "root out of range");
    check(nodes_[root_].parent == kNull, "root has a parent");
    std::vector<int> stack{root_};
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      check(!seen[i], "node " + std::to_string(i) + " reached twice");
      seen[i] = 1;
      ++reachable;
      const Node& n = nodes_[i];
      check(n.height >= 0, "free node " + std::to_string(i) + " in the tree");
      if (n.height == 0) {
        check(n.child1 == kNull && n.child2 == kNull, "leaf with children");
        check(n.box.isValid(), "leaf with an invalid box");
        ++leaves;
        continue;
      }
      for (const int c : {n.child1, n.child2}) {
        check(c >= 0 && c < capacity, "child out of range");
        check(nodes_[c].parent == i, "child's parent link broken at " + std::to_string(c));
        check(n.box.contains(nodes_[c].box), "box does not contain child " + std::to_string(c));
        stack.push_back(c);
      }
      check(n.height == 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height),
            "inconsistent height at " + std::to_string(i));
    }
  }
  check(leaves == proxyCount_, "leaf count differs from proxyCount");

  int freeCount = 0;
  for (int i = freeList_; i != kNull; i = nodes_[i].parent) {
    check(i >= 0 && i < capacity, "free list out of range");
    check(!seen[i], "free list node " + std::to_string(i) + " reached twice or in the tree");
    seen[i] = 1;
    check(nodes_[i].height == -1, "free list node not marked free");
    ++freeCount;
  }
  check(reachable + freeCount == capacity, "nodes leaked: neither in the tree nor free");
}

}  // namespace inertia
