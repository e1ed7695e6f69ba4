#include "islands.h"

#include <algorithm>
#include <numeric>

namespace inertia::detail {

void buildIslands(RigidBodyData& D) {
  const std::uint32_t bodyCount = static_cast<std::uint32_t>(D.bodies.size());
  // 3. Islands: union-find over contacts between dynamic bodies; one awake body (or a moving
  // kinematic body touching it) keeps its whole island awake.
  D.island.resize(bodyCount);
  std::iota(D.island.begin(), D.island.end(), 0u);
  D.islandAwake.assign(bodyCount, 0);
  for (const ContactInfo& c : D.contacts) {
    const BodyRecord& ba = D.bodies[c.bodyA.index];
    const BodyRecord& bb = D.bodies[c.bodyB.index];
    if (ba.type == BodyType::Dynamic && bb.type == BodyType::Dynamic) {
      const std::uint32_t ra = findRoot(D.island, c.bodyA.index);
      const std::uint32_t rb = findRoot(D.island, c.bodyB.index);
      if (ra != rb) D.island[std::max(ra, rb)] = std::min(ra, rb);
    }
  }
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    const BodyRecord& b = D.bodies[bi];
    if (b.alive && b.type == BodyType::Dynamic && b.awake)
      D.islandAwake[findRoot(D.island, bi)] = 1;
  }
  for (const ContactInfo& c : D.contacts) {
    const BodyRecord& ba = D.bodies[c.bodyA.index];
    const BodyRecord& bb = D.bodies[c.bodyB.index];
    auto moving = [](const BodyRecord& k) {
      return k.type == BodyType::Kinematic && k.awake && (!k.v.isZero() || !k.w.isZero());
    };
    if (moving(ba) && bb.type == BodyType::Dynamic)
      D.islandAwake[findRoot(D.island, c.bodyB.index)] = 1;
    if (moving(bb) && ba.type == BodyType::Dynamic)
      D.islandAwake[findRoot(D.island, c.bodyA.index)] = 1;
  }
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (!b.alive || b.type != BodyType::Dynamic || b.awake) continue;
    if (D.islandAwake[findRoot(D.island, bi)]) D.wake(b);
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
      Real& m = D.islandSleep[findRoot(D.island, bi)];
      m = std::min(m, b.sleepTime);
    }
    for (const ContactInfo& c : D.contacts) {  // touching a moving kinematic body: stay awake
      for (auto [k, o] :
           {std::pair{c.bodyA.index, c.bodyB.index}, std::pair{c.bodyB.index, c.bodyA.index}}) {
        const BodyRecord& kin = D.bodies[k];
        if (kin.type == BodyType::Kinematic && (!kin.v.isZero() || !kin.w.isZero()) &&
            D.bodies[o].type == BodyType::Dynamic)
          D.islandSleep[findRoot(D.island, o)] = 0;
      }
    }
    for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
      BodyRecord& b = D.bodies[bi];
      if (!b.alive || b.type != BodyType::Dynamic || !b.awake) continue;
      if (D.islandSleep[findRoot(D.island, bi)] >= tuning.timeToSleep) {
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
