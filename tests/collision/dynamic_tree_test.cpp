#include "inertia/collision/dynamic_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "collision_test_util.h"
#include "inertia/core/error.h"
#include "../draws.h"

using namespace inertia;
using inertia::test::randomAabb;

namespace {

using Pairs = std::vector<std::pair<int, int>>;

// The oracle: every pair of live proxies with at least one in `moved` whose fat boxes overlap.
Pairs bruteForcePairs(const DynamicTree& tree, const std::vector<int>& live,
                      const std::set<int>& moved) {
  Pairs out;
  for (std::size_t a = 0; a < live.size(); ++a)
    for (std::size_t b = a + 1; b < live.size(); ++b) {
      const int i = live[a], j = live[b];
      if (!moved.count(i) && !moved.count(j)) continue;
      if (tree.fatAabb(i).overlaps(tree.fatAabb(j)))
        out.emplace_back(std::min(i, j), std::max(i, j));
    }
  std::sort(out.begin(), out.end());
  return out;
}

int heightBound(std::size_t n) {
  return static_cast<int>(3 * std::log2(static_cast<double>(std::max<std::size_t>(n, 1))) + 5);
}

}  // namespace

// keeps() answers what moveProxy would do without doing it: true exactly when moveProxy leaves
// the proxy as it is (returns false without throwing), for a box inside, one outside, and the
// inputs moveProxy refuses (non-finite or inverted boxes, a non-finite move).
TEST(DynamicTree, KeepsIsWhatMoveProxyWouldDo) {
  const Real inf = std::numeric_limits<Real>::infinity();
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Aabb start{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const Aabb inside{Vec3(Real(0.05), 0, 0), Vec3(Real(1.05), 1, 1)};  // within the margin
  const Aabb outside{Vec3(2, 0, 0), Vec3(3, 1, 1)};
  const Aabb inverted{Vec3(Real(0.5), 0, 0), Vec3(Real(0.4), 1, 1)};
  const Aabb notFinite{Vec3(0, 0, 0), Vec3(inf, 1, 1)};
  const Aabb notANumber{Vec3(nan, 0, 0), Vec3(1, 1, 1)};
  struct Case {
    Aabb box;
    Vec3 displacement;
  };
  const Case cases[] = {{inside, Vec3::Zero()},     {outside, Vec3::Zero()},
                        {inverted, Vec3::Zero()},   {notFinite, Vec3::Zero()},
                        {notANumber, Vec3::Zero()}, {inside, Vec3(nan, 0, 0)}};
  for (const Case& c : cases) {
    DynamicTree tree;
    const int id = tree.createProxy(start, 0);
    const bool keeps = tree.keeps(id, c.box, c.displacement);
    bool moved = true;
    try {
      moved = tree.moveProxy(id, c.box, c.displacement);
    } catch (const InvalidArgument&) {
    }
    EXPECT_EQ(keeps, !moved) << c.box.lower.transpose() << " .. " << c.box.upper.transpose();
  }
  DynamicTree tree;
  const int id = tree.createProxy(start, 0);
  EXPECT_TRUE(tree.keeps(id, inside, Vec3::Zero()));
  EXPECT_FALSE(tree.keeps(id, outside, Vec3::Zero()));
}

TEST(DynamicTree, PairsMatchBruteForceOverRandomUpdates) {
  std::mt19937 rng(7);
  DynamicTree tree({.margin = Real(0.1), .displacementMultiplier = Real(2)});
  std::vector<int> live;
  std::vector<Aabb> tight(0);  // indexed by proxy id (grown as needed)
  auto setTight = [&](int id, const Aabb& b) {
    if (tight.size() <= static_cast<std::size_t>(id)) tight.resize(id + 1);
    tight[id] = b;
  };
  for (int i = 0; i < 500; ++i) {
    const Aabb b = randomAabb(rng, 20, 1);
    const int id = tree.createProxy(b, static_cast<std::uint32_t>(1000 + i));
    setTight(id, b);
    live.push_back(id);
  }
  tree.validate();

  // All proxies "moved": the full pair set.
  Pairs pairs;
  tree.computePairs(live, pairs);
  EXPECT_EQ(pairs, bruteForcePairs(tree, live, std::set<int>(live.begin(), live.end())));
  std::size_t totalPairs = pairs.size(), reinserted = 0, stayed = 0;

  std::uniform_real_distribution<Real> step(Real(-0.3), Real(0.3)), unit(0, 1);
  for (int round = 0; round < 100; ++round) {
    std::set<int> moved;
    // Destroy a few.
    for (int k = 0; k < 10 && !live.empty(); ++k) {
      const std::size_t at = rng() % live.size();
      tree.destroyProxy(live[at]);
      live.erase(live.begin() + static_cast<std::ptrdiff_t>(at));
    }
    // Move everything: mostly small steps, sometimes teleports.
    for (const int id : live) {
      Vec3 d = inertia::test::draw3<Vec3>([&] { return step(rng); });
      if (unit(rng) < Real(0.02)) d *= 30;
      Aabb b{tight[id].lower + d, tight[id].upper + d};
      setTight(id, b);
      if (tree.moveProxy(id, b, d)) {
        moved.insert(id);
        ++reinserted;
      } else {
        ++stayed;
      }
      ASSERT_TRUE(tree.fatAabb(id).contains(b));
    }
    // Create a few (ids of destroyed proxies are reused).
    for (int k = 0; k < 10; ++k) {
      const Aabb b = randomAabb(rng, 20, 1);
      const int id = tree.createProxy(b, 7);
      setTight(id, b);
      live.push_back(id);
      moved.insert(id);
    }
    tree.validate();
    ASSERT_EQ(tree.proxyCount(), live.size());
    ASSERT_LE(tree.height(), heightBound(live.size()));

    const std::vector<int> movedList(moved.begin(), moved.end());
    tree.computePairs(movedList, pairs);
    ASSERT_EQ(pairs, bruteForcePairs(tree, live, moved)) << "round " << round;
    totalPairs += pairs.size();
  }
  // The scene must actually exercise both paths and produce pairs.
  EXPECT_GT(totalPairs, 1000u);
  EXPECT_GT(reinserted, 1000u);
  EXPECT_GT(stayed, 1000u);
  RecordProperty("pairsCompared", static_cast<int>(totalPairs));
  std::printf("pairs compared: %zu, reinserted %zu, stayed %zu, height %d (n = %zu)\n", totalPairs,
              reinserted, stayed, tree.height(), live.size());
}

TEST(DynamicTree, PairsAreIndependentOfInsertionOrder) {
  std::mt19937 rng(3);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 300; ++i) boxes.push_back(randomAabb(rng, 10, 1));
  DynamicTree forward;
  std::vector<int> ids;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    ids.push_back(forward.createProxy(boxes[i], static_cast<std::uint32_t>(i)));
  DynamicTree reversed;
  std::vector<int> revIds(boxes.size());
  for (int i = static_cast<int>(boxes.size()) - 1; i >= 0; --i)
    revIds[i] = reversed.createProxy(boxes[i], static_cast<std::uint32_t>(i));
  // Proxy ids are node indices and differ between the trees: compare in box indices.
  auto toBoxPairs = [&](const std::vector<int>& idOf, const Pairs& pairs) {
    std::vector<int> boxOf(2 * boxes.size(), -1);
    for (std::size_t i = 0; i < boxes.size(); ++i) boxOf[idOf[i]] = static_cast<int>(i);
    Pairs out;
    for (const auto& [x, y] : pairs)
      out.emplace_back(std::min(boxOf[x], boxOf[y]), std::max(boxOf[x], boxOf[y]));
    std::sort(out.begin(), out.end());
    return out;
  };
  Pairs a, b;
  forward.computePairs(ids, a);
  reversed.computePairs(revIds, b);
  EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
  EXPECT_TRUE(std::is_sorted(b.begin(), b.end()));
  EXPECT_GT(a.size(), 50u);
  EXPECT_EQ(toBoxPairs(ids, a), toBoxPairs(revIds, b));
  forward.validate();
  reversed.validate();

  // Same ids and fat boxes, different history (each proxy sent far away and back, in shuffled
  // order, so the tree's shape differs): identical output, element for element.
  DynamicTree shuffled;
  for (const Aabb& box : boxes) shuffled.createProxy(box, 0);
  // Index k of boxes has id ids[k] in both trees (same creation order, fresh node pools).
  std::vector<int> order(boxes.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::shuffle(order.begin(), order.end(), rng);
  const Vec3 far(100, 0, 0);
  for (const int k : order)
    shuffled.moveProxy(ids[k], Aabb{boxes[k].lower + far, boxes[k].upper + far}, Vec3::Zero());
  std::shuffle(order.begin(), order.end(), rng);
  for (const int k : order) EXPECT_TRUE(shuffled.moveProxy(ids[k], boxes[k], Vec3::Zero()));
  for (const int id : ids) ASSERT_EQ(shuffled.fatAabb(id).lower, forward.fatAabb(id).lower);
  shuffled.validate();
  Pairs c;
  shuffled.computePairs(ids, c);
  EXPECT_EQ(a, c);
}

TEST(DynamicTree, BoxQueriesMatchBruteForce) {
  std::mt19937 rng(11);
  DynamicTree tree;
  std::vector<int> live;
  for (int i = 0; i < 1000; ++i) live.push_back(tree.createProxy(randomAabb(rng, 30, 2), i));
  for (int i = 0; i < 200; i += 2) tree.destroyProxy(live[i]);
  live.erase(std::remove_if(live.begin(), live.end(), [&](int id) { return !tree.isProxy(id); }),
             live.end());
  tree.validate();
  std::size_t hits = 0;
  for (int q = 0; q < 300; ++q) {
    const Aabb box = randomAabb(rng, 30, 5);
    std::vector<int> got;
    tree.query(box, [&](int id) { got.push_back(id); });
    std::vector<int> want;
    for (const int id : live)
      if (tree.fatAabb(id).overlaps(box)) want.push_back(id);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, want);
    hits += got.size();
  }
  EXPECT_GT(hits, 300u);
  // Early stop: returning false after the first hit visits exactly one leaf.
  int visits = 0;
  tree.query(Aabb{Vec3::Constant(-100), Vec3::Constant(100)}, [&](int) {
    ++visits;
    return false;
  });
  EXPECT_EQ(visits, 1);
}

TEST(DynamicTree, RayCastsMatchBruteForce) {
  std::mt19937 rng(5);
  DynamicTree tree;
  std::vector<int> live;
  for (int i = 0; i < 800; ++i) live.push_back(tree.createProxy(randomAabb(rng, 20, 2), i));
  std::uniform_real_distribution<Real> c(-25, 25);
  std::size_t visited = 0, clippedHits = 0;
  for (int q = 0; q < 300; ++q) {
    const auto draw = [&] { return c(rng); };
    Ray ray{.origin = inertia::test::draw3<Vec3>(draw),
            .direction = inertia::test::draw3<Vec3>(draw),
            .maxFraction = Real(1)};
    if (q % 10 == 0) ray.direction.y() = 0;  // axis-parallel slabs
    if (q % 20 == 0) ray.direction.z() = 0;
    if (q % 3 == 0) ray.maxFraction = Real(0.5);  // a shortened segment

    // Without clipping: every leaf whose fat box the segment crosses, each once.
    std::vector<int> got;
    tree.rayCast(ray, [&](int id, Real maxFraction) {
      got.push_back(id);
      return maxFraction;
    });
    std::vector<int> want;
    for (const int id : live)
      if (segmentOverlapsAabb(tree.fatAabb(id), ray, ray.maxFraction)) want.push_back(id);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, want);
    visited += got.size();

    // With clipping to the entry fraction: the closest entry equals brute force.
    Real best = std::numeric_limits<Real>::infinity();
    tree.rayCast(ray, [&](int id, Real maxFraction) {
      Real entry = 0;
      EXPECT_TRUE(segmentOverlapsAabb(tree.fatAabb(id), ray, maxFraction, &entry));
      best = std::min(best, entry);
      return entry;
    });
    Real bruteBest = std::numeric_limits<Real>::infinity();
    for (const int id : live) {
      Real entry = 0;
      if (segmentOverlapsAabb(tree.fatAabb(id), ray, ray.maxFraction, &entry))
        bruteBest = std::min(bruteBest, entry);
    }
    ASSERT_EQ(best, bruteBest);
    if (std::isfinite(best)) ++clippedHits;
  }
  EXPECT_GT(visited, 150u);
  EXPECT_GT(clippedHits, 50u);
  std::printf("ray leaves visited: %zu, rays with a closest hit: %zu\n", visited, clippedHits);
}

TEST(DynamicTree, SlabTestHandCases) {
  const Aabb box{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  Real entry = -1;
  EXPECT_TRUE(segmentOverlapsAabb(
      box, Ray{.origin = Vec3(-1, 0.5, 0.5), .direction = Vec3(4, 0, 0)}, 1, &entry));
  EXPECT_NEAR(entry, 0.25, 1e-6);
  // Too short to reach the box.
  EXPECT_FALSE(segmentOverlapsAabb(
      box, Ray{.origin = Vec3(-1, 0.5, 0.5), .direction = Vec3(4, 0, 0)}, Real(0.2)));
  // Parallel to a slab but outside it.
  EXPECT_FALSE(
      segmentOverlapsAabb(box, Ray{.origin = Vec3(-1, 2, 0.5), .direction = Vec3(4, 0, 0)}, 1));
  // Starting inside: entry 0.
  EXPECT_TRUE(segmentOverlapsAabb(
      box, Ray{.origin = Vec3(0.5, 0.5, 0.5), .direction = Vec3(0, 0, 1)}, 1, &entry));
  EXPECT_EQ(entry, 0);
  // Pointing away.
  EXPECT_FALSE(
      segmentOverlapsAabb(box, Ray{.origin = Vec3(2, 0.5, 0.5), .direction = Vec3(1, 0, 0)}, 1));
  // Negative max fraction and a zero direction outside: nothing.
  EXPECT_FALSE(
      segmentOverlapsAabb(box, Ray{.origin = Vec3(0.5, 0.5, 0.5), .direction = Vec3(1, 0, 0)}, -1));
  EXPECT_FALSE(
      segmentOverlapsAabb(box, Ray{.origin = Vec3(2, 2, 2), .direction = Vec3::Zero()}, 1));
}

TEST(DynamicTree, HeightStaysLogarithmicForRandomAndSortedInsertions) {
  std::mt19937 rng(1);
  const int n = 4096;
  DynamicTree random;
  for (int i = 0; i < n; ++i) random.createProxy(randomAabb(rng, 100, 1), i);
  random.validate();
  EXPECT_LE(random.height(), heightBound(n));

  // Sorted along a line: the worst case for an unbalanced tree (it would degenerate to a list).
  DynamicTree sorted({.margin = 0, .displacementMultiplier = 0});
  std::vector<int> sortedIds;
  for (int i = 0; i < n; ++i)
    sortedIds.push_back(
        sorted.createProxy(Aabb{Vec3(Real(i), 0, 0), Vec3(Real(i) + Real(0.5), 1, 1)}, i));
  sorted.validate();
  EXPECT_LE(sorted.height(), heightBound(n));
  const int sortedHeight = sorted.height();

  // Destroying half (every other) keeps it balanced and consistent.
  for (int i = 0; i < n; i += 2) sorted.destroyProxy(sortedIds[i]);
  sorted.validate();
  EXPECT_LE(sorted.height(), heightBound(n / 2));
  std::printf("n = %d: height random %d, sorted %d, sorted after halving %d (bound %d)\n", n,
              random.height(), sortedHeight, sorted.height(), heightBound(n));
}

TEST(DynamicTree, ForEachNodeVisitsEveryNodeParentsFirst) {
  std::mt19937 rng(3);
  DynamicTree tree;
  std::vector<Aabb> fat;
  for (int i = 0; i < 300; ++i) {
    const int id = tree.createProxy(randomAabb(rng, 50, 1), std::uint32_t(i));
    fat.push_back(tree.fatAabb(id));
  }
  // A full binary tree over n leaves has 2n - 1 nodes; the first is the root.
  std::vector<std::pair<Aabb, int>> nodes;
  tree.forEachNode([&](const Aabb& box, int height) { nodes.emplace_back(box, height); });
  ASSERT_EQ(nodes.size(), 2 * fat.size() - 1);
  EXPECT_EQ(nodes[0].second, tree.height());
  // Parents before children (pre-order): replaying the sequence, each node is a child of the
  // innermost open node, lower than it and inside its box; inner nodes open two child slots.
  struct Open {
    Aabb box;
    int height, slots;
  };
  std::vector<Open> open;
  int leaves = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const auto& [box, height] = nodes[k];
    if (k > 0) {
      ASSERT_FALSE(open.empty()) << "node " << k << " after the tree ended";
      EXPECT_LT(height, open.back().height);
      EXPECT_TRUE(open.back().box.contains(box));
      if (--open.back().slots == 0) open.pop_back();
    }
    if (height > 0) {
      open.push_back({box, height, 2});
      continue;
    }
    ++leaves;  // a leaf's box is a proxy's fat box
    EXPECT_TRUE(std::any_of(fat.begin(), fat.end(), [&](const Aabb& f) {
      return f.lower == box.lower && f.upper == box.upper;
    }));
  }
  EXPECT_TRUE(open.empty());
  EXPECT_EQ(leaves, int(fat.size()));
}

TEST(DynamicTree, SmallMovesStayInsideTheFatBox) {
  DynamicTree tree({.margin = Real(0.2), .displacementMultiplier = Real(4)});
  const Aabb b{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const int id = tree.createProxy(b, 42);
  const int other = tree.createProxy(Aabb{Vec3(5, 5, 5), Vec3(6, 6, 6)}, 43);
  EXPECT_EQ(tree.userData(id), 42u);
  EXPECT_EQ(tree.userData(other), 43u);
  const Aabb fat = tree.fatAabb(id);
  EXPECT_TRUE(fat.contains(b.inflated(Real(0.2))));
  const Vec3 d(Real(0.1), Real(-0.15), Real(0.05));
  EXPECT_FALSE(tree.moveProxy(id, Aabb{b.lower + d, b.upper + d}, d));
  EXPECT_EQ(tree.fatAabb(id).lower, fat.lower);  // unchanged
  // A larger move leaves the fat box: reinserted, with the box stretched along +x by 4 * 0.5.
  const Vec3 big(Real(0.5), 0, 0);
  EXPECT_TRUE(tree.moveProxy(id, Aabb{b.lower + big, b.upper + big}, big));
  EXPECT_NEAR(tree.fatAabb(id).upper.x(), 1.5 + 0.2 + 2.0, 1e-5);
  EXPECT_NEAR(tree.fatAabb(id).lower.x(), 0.5 - 0.2, 1e-5);
  EXPECT_EQ(tree.userData(id), 42u);
  tree.validate();
}

TEST(DynamicTree, FreedIdsAreReusedAndEmptyTreeWorks) {
  DynamicTree tree;
  EXPECT_EQ(tree.height(), 0);
  EXPECT_EQ(tree.proxyCount(), 0u);
  tree.validate();
  int calls = 0;
  tree.query(Aabb{Vec3::Constant(-1), Vec3::Constant(1)}, [&](int) { ++calls; });
  tree.rayCast(Ray{}, [&](int, Real f) {
    ++calls;
    return f;
  });
  EXPECT_EQ(calls, 0);
  const int a = tree.createProxy(Aabb{Vec3::Zero(), Vec3::Ones()}, 1);
  tree.destroyProxy(a);
  tree.validate();
  const int b = tree.createProxy(Aabb{Vec3::Zero(), Vec3::Ones()}, 2);
  EXPECT_EQ(a, b);  // first created, first freed: the free list hands it back
  tree.validate();
}

TEST(DynamicTree, BadInputThrows) {
  DynamicTree tree;
  const Real inf = std::numeric_limits<Real>::infinity();
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(tree.createProxy(Aabb{Vec3(1, 0, 0), Vec3(0, 1, 1)}, 0), InvalidArgument);
  EXPECT_THROW(tree.createProxy(Aabb{Vec3(0, 0, 0), Vec3(inf, 1, 1)}, 0), InvalidArgument);
  EXPECT_THROW(tree.createProxy(Aabb{Vec3(nan, 0, 0), Vec3(1, 1, 1)}, 0), InvalidArgument);
  EXPECT_THROW(tree.createProxy(Aabb::empty(), 0), InvalidArgument);
  const int a = tree.createProxy(Aabb{Vec3::Zero(), Vec3::Ones()}, 1);
  const int b = tree.createProxy(Aabb{Vec3::Ones(), Vec3::Constant(2)}, 1);
  EXPECT_THROW(tree.moveProxy(a, Aabb{Vec3(nan, 0, 0), Vec3(1, 1, 1)}, Vec3::Zero()),
               InvalidArgument);
  EXPECT_THROW(tree.moveProxy(a, Aabb{Vec3::Zero(), Vec3::Ones()}, Vec3(inf, 0, 0)),
               InvalidArgument);
  // b's parent is an internal node: not a proxy.
  const int internal = std::max(a, b) + 1;
  EXPECT_THROW(tree.destroyProxy(internal), InvalidArgument);
  EXPECT_THROW(tree.destroyProxy(-1), InvalidArgument);
  EXPECT_THROW(tree.destroyProxy(1000), InvalidArgument);
  tree.destroyProxy(a);
  EXPECT_THROW(tree.destroyProxy(a), InvalidArgument);  // double destroy
  EXPECT_THROW(tree.fatAabb(a), InvalidArgument);
  EXPECT_THROW(tree.userData(a), InvalidArgument);
  const int moved[] = {a};
  Pairs pairs;
  EXPECT_THROW(tree.computePairs(moved, pairs), InvalidArgument);
  EXPECT_THROW(DynamicTree({.margin = -1}), InvalidArgument);
  EXPECT_THROW(DynamicTree({.margin = nan}), InvalidArgument);
  EXPECT_THROW(DynamicTree({.margin = Real(0.1), .displacementMultiplier = inf}), InvalidArgument);
  tree.validate();
}
