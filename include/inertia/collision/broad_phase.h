// The broad phase: two dynamic AABB trees, one for static proxies and one for kinematic and
// dynamic ones (Box2D v3 keeps one tree per body type; Bullet's btDbvtBroadphase a fixed and a
// dynamic set). Only proxies whose fat box changed since the last updatePairs ("moved": created,
// or moved out of their fat box) are queried, against both trees, so static geometry costs
// nothing per step while nothing near it moves, and a resting dynamic proxy costs nothing either.
//
// Pairs always involve a dynamic proxy: static-static, static-kinematic and kinematic-kinematic
// pairs are never reported (as in Box2D). updatePairs reports the pairs whose fat boxes overlap
// and of which at least one proxy moved, i.e. the candidates new since the last call; a contact
// manager keeps them until their fat boxes separate (testOverlap).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "inertia/collision/dynamic_tree.h"
#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"

namespace inertia {

/// How a proxy's body moves; decides its tree and which pairs it forms.
enum class ProxyType : std::uint8_t {
  Static,     ///< Never (or rarely) moves; in the static tree; pairs only with dynamic proxies.
  Kinematic,  ///< Moved by the user; pairs only with dynamic proxies.
  Dynamic,    ///< Moved by the solver; pairs with everything.
};

/// A candidate pair of proxies, a < b.
struct ProxyPair {
  int a = -1;  ///< The smaller proxy id.
  int b = -1;  ///< The larger proxy id.
  friend bool operator==(const ProxyPair&, const ProxyPair&) = default;
  friend auto operator<=>(const ProxyPair&, const ProxyPair&) = default;
};

/// Settings of a broad phase, filled with designated initialisers.
struct BroadPhaseSettings {
  /// Settings of both trees: fat-box margin (m) and displacement multiplier.
  DynamicTreeSettings tree = {};
};

/// The broad phase (see the file comment). Proxy ids are small integers, stable while the
/// proxy lives and reused after it is destroyed (lowest free id first is not promised; the
/// same sequence of calls gives the same ids). Not thread-safe for mutation; concurrent const
/// queries are fine.
class BroadPhase {
 public:
  static constexpr int kNull = -1;  ///< The null proxy id.

  BroadPhase() : BroadPhase(BroadPhaseSettings{}) {}
  explicit BroadPhase(const BroadPhaseSettings& settings);

  /// Adds a proxy for the object bounds `box` (m, finite, lower <= upper) of the given type,
  /// carrying `userData`; it counts as moved. Returns its id.
  int createProxy(const Aabb& box, ProxyType type, std::uint32_t userData = 0);
  /// Removes a proxy (also from the moved set). Throws InvalidArgument for a dead id.
  void destroyProxy(int id);
  /// Updates a proxy to the object bounds `box` (m) after a move by `displacement` (m). It
  /// counts as moved only when `box` left its fat box (the tree then reinserts it); returns
  /// whether it did.
  bool moveProxy(int id, const Aabb& box, const Vec3& displacement = Vec3::Zero());
  /// True when moveProxy(id, box, displacement) would neither change the proxy nor throw
  /// (DynamicTree::keeps). Const: concurrent calls are fine while nothing moves.
  bool keeps(int id, const Aabb& box, const Vec3& displacement = Vec3::Zero()) const;
  /// Changes a proxy's type, moving it between the trees when needed; it counts as moved.
  void setType(int id, ProxyType type);

  /// Fills `pairs` with every pair (see the file comment) whose fat boxes overlap and of which
  /// at least one proxy moved since the last call, each once, sorted by (a, b): the output
  /// depends on the ids, types and fat boxes only, not on the trees' shapes or the history of
  /// other proxies. Then clears the moved set. Allocation-free once `pairs` and the internal
  /// buffers have grown.
  void updatePairs(std::vector<ProxyPair>& pairs);

  /// The proxies moved since the last updatePairs or clearMoved, in the order they moved.
  std::span<const int> movedProxies() const { return moved_; }
  /// Appends the pairs of the moved proxy `id` that updatePairs reports, but for those whose
  /// other proxy also moved and has a smaller id: over all moved proxies, each pair once (in
  /// no particular order). Const: queries for different proxies may run concurrently, which
  /// is how a caller spreads updatePairs over threads (then clearMoved and sort).
  void queryPairs(int id, std::vector<ProxyPair>& pairs) const;
  /// Clears the moved set, as updatePairs does after its queries.
  void clearMoved();
  /// Counts a live proxy as moved: the next update reports all its pairs again.
  void touchProxy(int id);

  /// True when the fat boxes of two live proxies overlap (touching counts).
  bool testOverlap(int a, int b) const { return fatAabb(a).overlaps(fatAabb(b)); }
  /// Fat box of a live proxy (m): its object bounds grown by the margin and the motion.
  const Aabb& fatAabb(int id) const {
    requireProxy(id, "BroadPhase::fatAabb");
    const Proxy& p = proxies_[std::size_t(id)];
    return trees_[treeOf(p.type)].fatAabb(p.treeId);
  }
  /// The type of a live proxy.
  ProxyType type(int id) const {
    requireProxy(id, "BroadPhase::type");
    return proxies_[std::size_t(id)].type;
  }
  /// The user value of a live proxy.
  std::uint32_t userData(int id) const {
    requireProxy(id, "BroadPhase::userData");
    return proxies_[std::size_t(id)].userData;
  }
  /// True when `id` names a live proxy.
  bool isProxy(int id) const {
    return id >= 0 && id < static_cast<int>(proxies_.size()) && proxies_[id].treeId != kNull;
  }
  /// Number of live proxies.
  std::size_t proxyCount() const { return proxyCount_; }
  /// Number of proxies moved since the last updatePairs.
  std::size_t movedCount() const { return moved_.size(); }
  /// The static and the kinematic/dynamic tree (their user data are proxy ids).
  const DynamicTree& staticTree() const { return trees_[0]; }
  const DynamicTree& dynamicTree() const { return trees_[1]; }

  /// Calls f(id) for every proxy, in both trees, whose fat box overlaps `box` (m). If f returns
  /// bool, false stops the query.
  template <class F>
  void query(const Aabb& box, F&& f) const;

  /// Casts the segment `ray` (m) through both trees: f(id, maxFraction) is called for every
  /// proxy whose fat box the segment crosses, and returns a Real as DynamicTree::rayCast's
  /// callback does: 0 stops, a value in (0, maxFraction) clips the segment (for the closest hit,
  /// return the fraction of your exact hit), anything else (maxFraction for all hits, negative
  /// to ignore the proxy) continues. The clipped fraction carries from one tree to the other.
  template <class F>
  void rayCast(const Ray& ray, F&& f) const;

  /// The closest hit along `ray`: hit(id, ray) returns the fraction in [0, ray.maxFraction] at
  /// which the segment meets the proxy's object, or a negative value for a miss. Returns
  /// {id, fraction} of the smallest fraction (ties: the first found), or nothing.
  template <class Hit>
  std::optional<std::pair<int, Real>> rayCastClosest(const Ray& ray, Hit&& hit) const;

  /// Checks both trees and the proxy table; throws std::logic_error on a violation. For tests.
  void validate() const;

 private:
  struct Proxy {
    int treeId = kNull;  ///< Leaf in trees_[tree], kNull while free.
    int nextFree = kNull;
    std::uint32_t userData = 0;
    ProxyType type = ProxyType::Static;
    bool moved = false;
  };
  static int treeOf(ProxyType t) { return t == ProxyType::Static ? 0 : 1; }
  // Inline, with the throw out of line: the accessors run per candidate pair.
  void requireProxy(int id, const char* what) const {
    if (!isProxy(id)) [[unlikely]]
      throwNotAProxy(id, what);
  }
  [[noreturn]] static void throwNotAProxy(int id, const char* what);
  void markMoved(int id);

  DynamicTree trees_[2];
  Real margin_ = 0;
  std::vector<Proxy> proxies_;
  std::vector<int> moved_;
  int freeList_ = kNull;
  std::size_t proxyCount_ = 0;
};

template <class F>
void BroadPhase::query(const Aabb& box, F&& f) const {
  for (const DynamicTree& tree : trees_) {
    bool stop = false;
    tree.query(box, [&](int leaf) {
      const int id = static_cast<int>(tree.userData(leaf));
      if constexpr (std::is_same_v<decltype(f(id)), bool>) {
        stop = !f(id);
        return !stop;
      } else {
        f(id);
        return true;
      }
    });
    if (stop) return;
  }
}

template <class F>
void BroadPhase::rayCast(const Ray& ray, F&& f) const {
  Ray clipped = ray;
  for (const DynamicTree& tree : trees_) {
    bool stop = false;
    tree.rayCast(clipped, [&](int leaf, Real maxFraction) -> Real {
      const Real value = f(static_cast<int>(tree.userData(leaf)), maxFraction);
      if (value == 0) {
        stop = true;
      } else if (value > 0 && value < clipped.maxFraction) {
        clipped.maxFraction = value;
      }
      return value;
    });
    if (stop) return;
  }
}

template <class Hit>
std::optional<std::pair<int, Real>> BroadPhase::rayCastClosest(const Ray& ray, Hit&& hit) const {
  std::optional<std::pair<int, Real>> best;
  rayCast(ray, [&](int id, Real maxFraction) -> Real {
    const Real s = hit(id, ray);
    if (!(s >= 0) || s > maxFraction) return -1;
    if (!best || s < best->second) best = std::pair<int, Real>(id, s);
    // A hit at fraction 0 is as close as it gets: stop.
    return s;
  });
  return best;
}

}  // namespace inertia
