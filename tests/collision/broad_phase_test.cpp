// The broad phase against brute force: pairs over many random updates (moving, static,
// kinematic, created and destroyed proxies, type changes), the incremental pair set a contact
// manager keeps, determinism under different histories, AABB queries and ray casts.
#include "inertia/collision/broad_phase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <set>
#include <vector>

#include "collision_test_util.h"
#include "inertia/core/error.h"
#include "../draws.h"

using namespace inertia;
using inertia::test::randomAabb;

namespace {

using ProxyPairs = std::vector<ProxyPair>;

ProxyType randomType(std::mt19937& rng) {
  const unsigned r = rng() % 10;
  return r < 2 ? ProxyType::Static : r < 3 ? ProxyType::Kinematic : ProxyType::Dynamic;
}

bool pairable(const BroadPhase& bp, int i, int j) {
  return bp.type(i) == ProxyType::Dynamic || bp.type(j) == ProxyType::Dynamic;
}

// The oracle: every pair of live proxies, at least one dynamic, fat boxes overlapping, and
// (unless `moved` is null) at least one of them in `moved`.
ProxyPairs bruteForceOverlaps(const BroadPhase& bp, const std::vector<int>& live,
                              const std::set<int>* moved) {
  struct Entry {
    int id;
    Aabb box;
    bool dynamic, moved;
  };
  std::vector<Entry> e;
  for (const int id : live)
    e.push_back({id, bp.fatAabb(id), bp.type(id) == ProxyType::Dynamic,
                 moved == nullptr || moved->count(id) > 0});
  ProxyPairs out;
  for (std::size_t a = 0; a < e.size(); ++a)
    for (std::size_t b = a + 1; b < e.size(); ++b) {
      if (!(e[a].moved || e[b].moved) || !(e[a].dynamic || e[b].dynamic)) continue;
      if (e[a].box.overlaps(e[b].box))
        out.push_back({std::min(e[a].id, e[b].id), std::max(e[a].id, e[b].id)});
    }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

// 100 rounds over ~600 proxies (20 % static, 10 % kinematic): each round destroys 8, moves the
// non-static ones (small steps, 2 % teleports), moves a static one now and then, changes a
// type, creates 8. The reported pairs equal brute force over the moved proxies, and the pair
// set a contact manager keeps (drop pairs whose fat boxes separated, add the reported ones)
// equals brute force over all proxies: reporting only moved proxies loses nothing. Odd rounds
// find the pairs by queryPairs per moved proxy instead of updatePairs.
TEST(BroadPhase, PairsMatchBruteForceOverRandomUpdates) {
  std::mt19937 rng(3);
  BroadPhase bp({.tree = {.margin = Real(0.1), .displacementMultiplier = Real(2)}});
  std::vector<int> live;
  std::vector<Aabb> tight;
  auto setTight = [&](int id, const Aabb& b) {
    if (tight.size() <= static_cast<std::size_t>(id)) tight.resize(id + 1);
    tight[id] = b;
  };
  std::set<int> moved;
  auto create = [&] {
    const Aabb b = randomAabb(rng, 15, 1);
    const int id = bp.createProxy(b, randomType(rng), static_cast<std::uint32_t>(rng()));
    setTight(id, b);
    live.push_back(id);
    moved.insert(id);
  };
  for (int i = 0; i < 600; ++i) create();
  ProxyPairs pairs, kept;
  bp.updatePairs(pairs);
  EXPECT_EQ(pairs, bruteForceOverlaps(bp, live, &moved));
  kept = pairs;
  moved.clear();
  EXPECT_EQ(bp.movedCount(), 0u);

  std::uniform_real_distribution<Real> step(Real(-0.3), Real(0.3)), unit(0, 1);
  std::size_t reported = 0, staticMoves = 0, typeChanges = 0;
  for (int round = 0; round < 100; ++round) {
    for (int k = 0; k < 8; ++k) {
      const std::size_t at = rng() % live.size();
      bp.destroyProxy(live[at]);
      moved.erase(live[at]);
      live.erase(live.begin() + static_cast<std::ptrdiff_t>(at));
    }
    for (const int id : live) {
      const bool isStatic = bp.type(id) == ProxyType::Static;
      if (isStatic && unit(rng) > Real(0.01)) continue;
      Vec3 d = inertia::test::draw3<Vec3>([&] { return step(rng); });
      if (unit(rng) < Real(0.02)) d *= 30;
      const Aabb b{tight[id].lower + d, tight[id].upper + d};
      setTight(id, b);
      if (bp.moveProxy(id, b, d)) {
        moved.insert(id);
        staticMoves += isStatic;
      }
      ASSERT_TRUE(bp.fatAabb(id).contains(b));
    }
    if (round % 5 == 0) {
      const int id = live[rng() % live.size()];
      bp.setType(id, randomType(rng));
      moved.insert(id);
      ++typeChanges;
      ASSERT_TRUE(bp.fatAabb(id).contains(tight[id]));
    }
    for (int k = 0; k < 8; ++k) create();
    bp.validate();
    ASSERT_EQ(bp.movedCount(), moved.size());

    if (round % 2 == 0) {
      bp.updatePairs(pairs);
    } else {
      // As a caller spreading the queries over threads does: one query per moved proxy, in
      // any order, then the moved set cleared and the pairs sorted.
      pairs.clear();
      const std::vector<int> movedNow(bp.movedProxies().begin(), bp.movedProxies().end());
      for (auto it = movedNow.rbegin(); it != movedNow.rend(); ++it) bp.queryPairs(*it, pairs);
      bp.clearMoved();
      std::sort(pairs.begin(), pairs.end());
    }
    ASSERT_EQ(pairs, bruteForceOverlaps(bp, live, &moved)) << "round " << round;
    ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
    reported += pairs.size();
    moved.clear();

    // The contact manager's view: keep live pairs whose fat boxes still overlap, add new ones.
    const std::set<int> liveSet(live.begin(), live.end());
    std::erase_if(kept, [&](const ProxyPair& p) {
      return !liveSet.count(p.a) || !liveSet.count(p.b) || !pairable(bp, p.a, p.b) ||
             !bp.testOverlap(p.a, p.b);
    });
    ProxyPairs merged;
    std::set_union(kept.begin(), kept.end(), pairs.begin(), pairs.end(),
                   std::back_inserter(merged));
    kept = merged;
    ASSERT_EQ(kept, bruteForceOverlaps(bp, live, nullptr)) << "round " << round;
  }
  EXPECT_GT(reported, 1000u);
  EXPECT_GT(staticMoves, 10u);
  std::printf(
      "pairs reported %zu, kept at the end %zu, static moves %zu, type changes %zu, "
      "proxies %zu (static tree %zu, dynamic tree %zu)\n",
      reported, kept.size(), staticMoves, typeChanges, bp.proxyCount(),
      bp.staticTree().proxyCount(), bp.dynamicTree().proxyCount());
}

// Static-static, static-kinematic and kinematic-kinematic pairs are never reported; dynamic
// proxies pair with everything. With nothing moved, nothing is reported (and no tree queried).
TEST(BroadPhase, PairRulesByType) {
  BroadPhase bp;
  const Aabb box = Aabb::fromCenterHalfExtents(Vec3::Zero(), Vec3::Constant(1));
  const int s1 = bp.createProxy(box, ProxyType::Static);
  const int s2 = bp.createProxy(box, ProxyType::Static);
  const int k1 = bp.createProxy(box, ProxyType::Kinematic);
  const int k2 = bp.createProxy(box, ProxyType::Kinematic);
  const int d1 = bp.createProxy(box, ProxyType::Dynamic);
  ProxyPairs pairs;
  bp.updatePairs(pairs);
  EXPECT_EQ(pairs, (ProxyPairs{{s1, d1}, {s2, d1}, {k1, d1}, {k2, d1}}));
  bp.updatePairs(pairs);
  EXPECT_TRUE(pairs.empty());
  // A small move inside the fat box is not a move.
  EXPECT_FALSE(
      bp.moveProxy(d1, Aabb::fromCenterHalfExtents(Vec3::Constant(Real(0.05)), Vec3::Constant(1))));
  EXPECT_EQ(bp.movedCount(), 0u);
  // A moved static proxy finds its dynamic partner only.
  EXPECT_TRUE(
      bp.moveProxy(s1, Aabb::fromCenterHalfExtents(Vec3(Real(0.5), 0, 0), Vec3::Constant(1))));
  bp.updatePairs(pairs);
  EXPECT_EQ(pairs, (ProxyPairs{{s1, d1}}));
  // Destroying a moved proxy removes it from the move buffer.
  bp.setType(k2, ProxyType::Dynamic);
  bp.destroyProxy(k2);
  EXPECT_EQ(bp.movedCount(), 0u);
  bp.validate();
  EXPECT_THROW(bp.destroyProxy(k2), InvalidArgument);
  EXPECT_THROW(bp.fatAabb(-1), InvalidArgument);
  EXPECT_THROW(bp.createProxy(Aabb::empty(), ProxyType::Dynamic), InvalidArgument);
  bp.validate();
}

// The same proxies (ids, types, fat boxes) reached through different histories: one broad
// phase creates them in place; the other creates them far away, adds and removes unrelated
// proxies, then moves them into place in a shuffled order (different tree shapes). The pairs
// are identical.
TEST(BroadPhase, PairsIndependentOfHistory) {
  std::mt19937 rng(9);
  const int n = 400;
  std::vector<Aabb> boxes;
  std::vector<ProxyType> types;
  for (int i = 0; i < n; ++i) {
    boxes.push_back(randomAabb(rng, 10, 1));
    types.push_back(randomType(rng));
  }
  BroadPhase a, b;
  for (int i = 0; i < n; ++i) ASSERT_EQ(a.createProxy(boxes[i], types[i]), i);
  const Aabb far = Aabb::fromCenterHalfExtents(Vec3(1000, 0, 0), Vec3::Constant(1));
  for (int i = 0; i < n; ++i) ASSERT_EQ(b.createProxy(far, types[i]), i);
  std::vector<int> extra;
  for (int i = 0; i < 100; ++i)
    extra.push_back(b.createProxy(randomAabb(rng, 10, 1), randomType(rng)));
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  ProxyPairs pa, pb;
  b.updatePairs(pb);  // flush the creation moves
  for (const int i : order) ASSERT_TRUE(b.moveProxy(i, boxes[i]));
  for (const int id : extra) b.destroyProxy(id);
  a.updatePairs(pa);
  b.updatePairs(pb);
  EXPECT_GT(pa.size(), 100u);
  EXPECT_EQ(pa, pb);
  for (int i = 0; i < n; ++i) ASSERT_EQ(a.fatAabb(i).lower, b.fatAabb(i).lower);
  std::printf("pairs %zu; tree heights %d/%d vs %d/%d\n", pa.size(), a.staticTree().height(),
              a.dynamicTree().height(), b.staticTree().height(), b.dynamicTree().height());
}

// AABB queries and ray casts over both trees against brute force: the query set, all proxies
// whose fat boxes a segment crosses, and the closest hit on the proxies' object boxes.
TEST(BroadPhase, QueriesAndRayCastsMatchBruteForce) {
  std::mt19937 rng(21);
  BroadPhase bp;
  std::vector<Aabb> tight;
  for (int i = 0; i < 500; ++i) {
    tight.push_back(randomAabb(rng, 20, 2));
    ASSERT_EQ(bp.createProxy(tight.back(), randomType(rng), 7), i);
  }
  const int n = static_cast<int>(tight.size());
  std::size_t hits = 0, closestHits = 0;
  for (int q = 0; q < 200; ++q) {
    const Aabb box = randomAabb(rng, 20, 4);
    std::set<int> got, want;
    bp.query(box, [&](int id) { got.insert(id); });
    for (int i = 0; i < n; ++i)
      if (bp.fatAabb(i).overlaps(box)) want.insert(i);
    ASSERT_EQ(got, want);
    int visits = 0;
    bp.query(box, [&](int) { return ++visits < 1; });
    ASSERT_EQ(visits, want.empty() ? 0 : 1);  // false stops the query at once

    std::uniform_real_distribution<Real> u(-25, 25);
    const auto draw = [&] { return u(rng); };
    const Vec3 origin = inertia::test::draw3<Vec3>(draw), direction = inertia::test::draw3<Vec3>(draw);
    Ray ray{origin, direction, Real(1)};
    std::set<int> all, wantAll;
    bp.rayCast(ray, [&](int id, Real maxFraction) {
      all.insert(id);
      return maxFraction;
    });
    for (int i = 0; i < n; ++i)
      if (segmentOverlapsAabb(bp.fatAabb(i), ray, ray.maxFraction)) wantAll.insert(i);
    ASSERT_EQ(all, wantAll);
    hits += all.size();

    auto hitTight = [&](int id, const Ray& r) {
      Real s = -1;
      return segmentOverlapsAabb(tight[id], r, r.maxFraction, &s) ? s : Real(-1);
    };
    const auto closest = bp.rayCastClosest(ray, hitTight);
    Real best = -1;
    for (int i = 0; i < n; ++i) {
      const Real s = hitTight(i, ray);
      if (s >= 0 && (best < 0 || s < best)) best = s;
    }
    ASSERT_EQ(closest.has_value(), best >= 0);
    if (closest) {
      EXPECT_EQ(closest->second, best);
      EXPECT_EQ(hitTight(closest->first, ray), best);
      ++closestHits;
    }
  }
  EXPECT_GT(hits, 100u);
  EXPECT_GT(closestHits, 50u);
}
