// Broad phase over a static and a kinematic/dynamic DynamicTree with a move buffer (Box2D v3's
// b2BroadPhase: per-type trees, pairs found by querying only the moved proxies).
#include "inertia/collision/broad_phase.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "inertia/core/error.h"

namespace inertia {

BroadPhase::BroadPhase(const BroadPhaseSettings& settings)
    : trees_{DynamicTree(settings.tree), DynamicTree(settings.tree)},
      margin_(settings.tree.margin) {}

void BroadPhase::throwNotAProxy(int id, const char* what) {
  throw InvalidArgument(std::string(what) + ": id " + std::to_string(id) + " is not a live proxy");
}

void BroadPhase::markMoved(int id) {
  if (proxies_[id].moved) return;
  proxies_[id].moved = true;
  moved_.push_back(id);
}

int BroadPhase::createProxy(const Aabb& box, ProxyType type, std::uint32_t userData) {
  int id;
  if (freeList_ != kNull) {
    id = freeList_;
    freeList_ = proxies_[id].nextFree;
  } else {
    id = static_cast<int>(proxies_.size());
    proxies_.emplace_back();
  }
  // The tree validates the box; on a throw the id goes back to the free list.
  try {
    proxies_[id].treeId = trees_[treeOf(type)].createProxy(box, static_cast<std::uint32_t>(id));
  } catch (...) {
    proxies_[id] = Proxy{};
    proxies_[id].nextFree = freeList_;
    freeList_ = id;
    throw;
  }
  Proxy& p = proxies_[id];
  p.nextFree = kNull;
  p.userData = userData;
  p.type = type;
  p.moved = false;
  markMoved(id);
  ++proxyCount_;
  return id;
}

void BroadPhase::destroyProxy(int id) {
  requireProxy(id, "BroadPhase::destroyProxy");
  Proxy& p = proxies_[id];
  trees_[treeOf(p.type)].destroyProxy(p.treeId);
  if (p.moved) moved_.erase(std::find(moved_.begin(), moved_.end(), id));
  p = Proxy{};
  p.nextFree = freeList_;
  freeList_ = id;
  --proxyCount_;
}

bool BroadPhase::moveProxy(int id, const Aabb& box, const Vec3& displacement) {
  requireProxy(id, "BroadPhase::moveProxy");
  const Proxy& p = proxies_[id];
  if (!trees_[treeOf(p.type)].moveProxy(p.treeId, box, displacement)) return false;
  markMoved(id);
  return true;
}

bool BroadPhase::keeps(int id, const Aabb& box, const Vec3& displacement) const {
  requireProxy(id, "BroadPhase::keeps");
  const Proxy& p = proxies_[id];
  return trees_[treeOf(p.type)].keeps(p.treeId, box, displacement);
}

void BroadPhase::setType(int id, ProxyType type) {
  requireProxy(id, "BroadPhase::setType");
  Proxy& p = proxies_[id];
  const int from = treeOf(p.type), to = treeOf(type);
  if (from != to) {
    // The fat box minus the margin still contains the object's box (the fat box is at least
    // the object's box grown by the margin); reinsertion grows it by the margin again.
    const Aabb inner = trees_[from].fatAabb(p.treeId).inflated(-margin_);
    trees_[from].destroyProxy(p.treeId);
    p.treeId = trees_[to].createProxy(inner, static_cast<std::uint32_t>(id));
  }
  p.type = type;
  markMoved(id);
}

void BroadPhase::queryPairs(int m, std::vector<ProxyPair>& pairs) const {
  requireProxy(m, "BroadPhase::queryPairs");
  const Proxy& pm = proxies_[m];
  const ProxyType tm = pm.type;
  const Aabb& box = trees_[treeOf(tm)].fatAabb(pm.treeId);
  // A pair of two moved proxies is reported by the query of the smaller id.
  auto add = [&](int o) {
    if (proxies_[o].moved && o < m) return;
    pairs.push_back(m < o ? ProxyPair{m, o} : ProxyPair{o, m});
  };
  const DynamicTree& movingTree = trees_[1];
  movingTree.query(box, [&](int leaf) {
    const int o = static_cast<int>(movingTree.userData(leaf));
    if (o == m) return;
    if (tm != ProxyType::Dynamic && proxies_[o].type != ProxyType::Dynamic) return;
    add(o);
  });
  // Only dynamic proxies pair with static ones; a moved static proxy found its dynamic
  // partners in the query above.
  if (tm == ProxyType::Dynamic) {
    const DynamicTree& staticTree = trees_[0];
    staticTree.query(box, [&](int leaf) { add(static_cast<int>(staticTree.userData(leaf))); });
  }
}

void BroadPhase::clearMoved() {
  for (const int m : moved_) proxies_[m].moved = false;
  moved_.clear();
}

void BroadPhase::touchProxy(int id) {
  requireProxy(id, "BroadPhase::touchProxy");
  markMoved(id);
}

void BroadPhase::updatePairs(std::vector<ProxyPair>& pairs) {
  pairs.clear();
  for (const int m : moved_) queryPairs(m, pairs);
  clearMoved();
  // Each pair was added once; sorting makes the order independent of the trees' shapes and
  // of the order of moves.
  std::sort(pairs.begin(), pairs.end());
}

void BroadPhase::validate() const {
  auto check = [](bool ok, const std::string& what) {
    if (!ok) throw std::logic_error("BroadPhase::validate: " + what);
  };
  trees_[0].validate();
  trees_[1].validate();
  std::size_t live = 0, movedFlags = 0;
  for (int id = 0; id < static_cast<int>(proxies_.size()); ++id) {
    const Proxy& p = proxies_[id];
    if (p.treeId == kNull) continue;
    ++live;
    const DynamicTree& tree = trees_[treeOf(p.type)];
    check(tree.isProxy(p.treeId), "proxy " + std::to_string(id) + " has no leaf");
    check(tree.userData(p.treeId) == static_cast<std::uint32_t>(id),
          "leaf of proxy " + std::to_string(id) + " points elsewhere");
    if (p.moved) ++movedFlags;
  }
  check(live == proxyCount_, "live count differs from proxyCount");
  check(trees_[0].proxyCount() + trees_[1].proxyCount() == live, "tree leaves differ from proxies");
  check(movedFlags == moved_.size(), "moved flags differ from the move buffer");
  for (const int id : moved_) check(isProxy(id) && proxies_[id].moved, "stale move buffer entry");
}

}  // namespace inertia
