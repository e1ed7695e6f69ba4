#include "islands.h"

#include <algorithm>
#include <numeric>

#include "rigid_body_data.h"

namespace inertia::detail {

void groupConstraints(std::span<const GraphEdge> edges, std::size_t bodyCount,
                      ConstraintIslands& out) {
  out.sets.reset(bodyCount);
  for (const GraphEdge& e : edges)
    if (e.bodyA >= 0 && e.bodyB >= 0)
      out.sets.unite(std::uint32_t(e.bodyA), std::uint32_t(e.bodyB));
  // Islands numbered by their first constraint; a counting sort keeps each island's order.
  out.islandOfRoot.assign(bodyCount, -1);
  out.offsets.assign(1, 0);
  out.constraints.resize(edges.size());
  auto islandOf = [&](const GraphEdge& e) -> std::int32_t& {
    return out.islandOfRoot[out.sets.find(std::uint32_t(e.bodyA >= 0 ? e.bodyA : e.bodyB))];
  };
  for (const GraphEdge& e : edges) {
    if (e.bodyA < 0 && e.bodyB < 0) continue;
    std::int32_t& island = islandOf(e);
    if (island < 0) {
      island = std::int32_t(out.offsets.size() - 1);
      out.offsets.push_back(0);
    }
    ++out.offsets[std::size_t(island) + 1];
  }
  std::partial_sum(out.offsets.begin(), out.offsets.end(), out.offsets.begin());
  out.constraints.resize(out.offsets.back());
  // Each island's next free place, from its start (the offsets shifted by one).
  std::vector<std::uint32_t>& next = out.next;
  next.assign(out.offsets.begin(), out.offsets.end() - 1);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const GraphEdge& e = edges[k];
    if (e.bodyA < 0 && e.bodyB < 0) continue;
    out.constraints[next[std::size_t(islandOf(e))]++] = std::uint32_t(k);
  }
}

namespace {

// Calls f(a, b) with the body slots of every edge of the constraint graph: each contact and
// each enabled joint (a joint to the world links nothing).
template <class F>
void forEachLink(const RigidBodyData& D, F f) {
  for (const ContactInfo& c : D.contacts) f(c.bodyA.index, c.bodyB.index);
  for (const JointRecord& j : D.joints)
    if (j.alive && j.enabled && j.bodyA != kWorldBody) f(j.bodyA, j.bodyB);
}

}  // namespace

void buildIslands(RigidBodyData& D) {
  const std::uint32_t bodyCount = static_cast<std::uint32_t>(D.bodies.size());
  // Union-find over contacts between dynamic bodies; one awake body (or a moving kinematic
  // body touching it) keeps its whole island awake.
  D.island.reset(bodyCount);
  D.islandAwake.assign(bodyCount, 0);
  forEachLink(D, [&](std::uint32_t a, std::uint32_t b) {
    if (D.bodies[a].type == BodyType::Dynamic && D.bodies[b].type == BodyType::Dynamic)
      D.island.unite(a, b);
  });
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    const BodyRecord& b = D.bodies[bi];
    if (b.alive && b.type == BodyType::Dynamic && b.awake) D.islandAwake[D.island.find(bi)] = 1;
  }
  forEachLink(D, [&](std::uint32_t a, std::uint32_t b) {
    const BodyRecord& ba = D.bodies[a];
    const BodyRecord& bb = D.bodies[b];
    auto moving = [](const BodyRecord& k) {
      return k.type == BodyType::Kinematic && k.awake && (!k.v.isZero() || !k.w.isZero());
    };
    if (moving(ba) && bb.type == BodyType::Dynamic) D.islandAwake[D.island.find(b)] = 1;
    if (moving(bb) && ba.type == BodyType::Dynamic) D.islandAwake[D.island.find(a)] = 1;
  });
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (!b.alive || b.type != BodyType::Dynamic || b.awake) continue;
    if (D.islandAwake[D.island.find(bi)]) D.wake(b);
  }
}

void sleepIslands(RigidBodyData& D, const DynamicsSettings& s) {
  const std::uint32_t bodyCount = static_cast<std::uint32_t>(D.bodies.size());
  const ContactTuning& tuning = s.contact;
  // Islands whose every body has rested long enough fall asleep together.
  if (s.sleeping) {
    D.islandSleep.assign(bodyCount, std::numeric_limits<Real>::infinity());
    for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
      const BodyRecord& b = D.bodies[bi];
      if (!b.alive || b.type != BodyType::Dynamic) continue;
      Real& m = D.islandSleep[D.island.find(bi)];
      m = std::min(m, b.sleepTime);
    }
    // Touching or jointed to a moving kinematic body: stay awake.
    forEachLink(D, [&](std::uint32_t a, std::uint32_t b) {
      for (auto [k, o] : {std::pair{a, b}, std::pair{b, a}}) {
        const BodyRecord& kin = D.bodies[k];
        if (kin.type == BodyType::Kinematic && (!kin.v.isZero() || !kin.w.isZero()) &&
            D.bodies[o].type == BodyType::Dynamic)
          D.islandSleep[D.island.find(o)] = 0;
      }
    });
    for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
      BodyRecord& b = D.bodies[bi];
      if (!b.alive || b.type != BodyType::Dynamic || !b.awake) continue;
      if (D.islandSleep[D.island.find(bi)] >= tuning.timeToSleep) {
        b.awake = false;
        b.v.setZero();
        b.w.setZero();
      }
    }
  }
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (b.alive && b.type == BodyType::Kinematic) b.awake = !b.v.isZero() || !b.w.isZero();
  }
}

}  // namespace inertia::detail
