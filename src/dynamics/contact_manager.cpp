#include "contact_manager.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>

#include "inertia/geometry/bounds.h"

namespace inertia::detail {

using Data = RigidBodyData;
using ShapePair = Data::ShapePair;

namespace {

// Items per chunk of a gather.
constexpr std::size_t kGatherChunk = 512;

// Appends to `out`, in index order, what emit(i, out) appends for each i in [0, n): in fixed
// chunks on the workers, each into its own buffer of `chunks`, joined in chunk order, so the
// result does not depend on the number of workers. In sequence, straight into `out`.
template <class T, class Emit>
void gatherInOrder(StepWorkers& workers, std::size_t n, std::vector<ChunkOf<T>>& chunks,
                   std::vector<T>& out, Emit emit) {
  out.clear();
  if (workers.threadCount() == 1) {
    for (std::size_t i = 0; i < n; ++i) emit(i, out);
    return;
  }
  const std::size_t count = (n + kGatherChunk - 1) / kGatherChunk;
  if (chunks.size() < count) chunks.resize(count);
  workers.parallelFor(count, 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t c = first; c < last; ++c) {
      std::vector<T>& items = chunks[c].items;
      items.clear();
      for (std::size_t i = c * kGatherChunk; i < std::min(n, (c + 1) * kGatherChunk); ++i)
        emit(i, items);
    }
  });
  for (std::size_t c = 0; c < count; ++c)
    out.insert(out.end(), chunks[c].items.begin(), chunks[c].items.end());
}

// The same with two outputs: emit(i, outA, outB).
template <class A, class B, class Emit>
void gatherInOrder(StepWorkers& workers, std::size_t n, std::vector<ChunkOf<A>>& chunksA,
                   std::vector<A>& outA, std::vector<ChunkOf<B>>& chunksB, std::vector<B>& outB,
                   Emit emit) {
  outA.clear();
  outB.clear();
  if (workers.threadCount() == 1) {
    for (std::size_t i = 0; i < n; ++i) emit(i, outA, outB);
    return;
  }
  const std::size_t count = (n + kGatherChunk - 1) / kGatherChunk;
  if (chunksA.size() < count) chunksA.resize(count);
  if (chunksB.size() < count) chunksB.resize(count);
  workers.parallelFor(count, 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t c = first; c < last; ++c) {
      chunksA[c].items.clear();
      chunksB[c].items.clear();
      for (std::size_t i = c * kGatherChunk; i < std::min(n, (c + 1) * kGatherChunk); ++i)
        emit(i, chunksA[c].items, chunksB[c].items);
    }
  });
  for (std::size_t c = 0; c < count; ++c) {
    outA.insert(outA.end(), chunksA[c].items.begin(), chunksA[c].items.end());
    outB.insert(outB.end(), chunksB[c].items.begin(), chunksB[c].items.end());
  }
}

// Per body, in parallel: the shapes' frames for the narrow phase, whether the body is
// continuous this step, and the new bounds of the proxies of awake bodies (swept over the
// step for a fast body, so that it meets what lies in its path) with whether each must move
// in the broad phase's trees.
void refreshFrames(Data& D, Real dt, const ContactTuning& tuning, StepWorkers& workers) {
  D.frames.resize(D.shapes.size());
  D.proxyBoxes.resize(D.shapes.size());
  D.proxyMoves.resize(D.shapes.size());
  workers.parallelFor(
      D.bodies.size(),
      [&](std::size_t first, std::size_t last) {
        for (std::uint32_t bi = std::uint32_t(first); bi < last; ++bi) {
          BodyRecord& b = D.bodies[bi];
          if (!b.alive) continue;
          b.fast = isBullet(b, dt, tuning);
          bool jointed = false;
          for (std::uint32_t ji : b.joints)
            jointed = jointed || (D.joints[ji].enabled && !D.joints[ji].collideConnected);
          for (std::uint32_t si : b.shapes)
            D.frames[si] = {D.shapePose(D.shapes[si]),
                            D.shapes[si].material,
                            D.shapes[si].generation,
                            bi,
                            b.generation,
                            D.shapes[si].collider.type(),
                            b.type,
                            b.awake,
                            b.fast,
                            jointed,
                            b.group,
                            D.shapes[si].filter,
                            D.shapes[si].radius};
          if (b.type == BodyType::Static || !b.awake) continue;
          const Vec3 displacement = b.v * dt;
          for (std::uint32_t si : b.shapes) {
            const ShapeRecord& sh = D.shapes[si];
            if (sh.proxy == BroadPhase::kNull) continue;
            Aabb box = worldBounds(sh.collider.shape(), D.frames[si].pose);
            if (b.fast) {
              const Real spin = b.w.norm() * b.extent * dt;
              box = box.merged({box.lower + displacement, box.upper + displacement}).inflated(spin);
            }
            box = box.inflated(tuning.speculativeDistance);
            D.proxyBoxes[si] = box;
            // The trees do not change until moveProxies: the test is safe here.
            D.proxyMoves[si] = !D.broadPhase.keeps(sh.proxy, box, displacement);
          }
        }
      },
      32);
}

// In sequence (the trees change): the proxies of awake bodies that left their fat box (found
// by refreshFrames on the workers) are reinserted and count as moved.
void moveProxies(Data& D, Real dt) {
  D.awakeProxies.clear();
  for (BodyRecord& b : D.bodies) {
    if (!b.alive || b.type == BodyType::Static || !b.awake) continue;
    for (std::uint32_t si : b.shapes) {
      const ShapeRecord& sh = D.shapes[si];
      if (sh.proxy == BroadPhase::kNull) continue;
      if (D.proxyMoves[si]) D.broadPhase.moveProxy(sh.proxy, D.proxyBoxes[si], b.v * dt);
      D.awakeProxies.push_back(sh.proxy);
    }
  }
  if (D.pairsDirty) {
    D.treePairs.clear();
    for (const ShapeRecord& sh : D.shapes)
      if (sh.alive && sh.proxy != BroadPhase::kNull && D.bodies[sh.body].type != BodyType::Static)
        D.broadPhase.touchProxy(sh.proxy);
    D.pairsDirty = false;
  }
}

// The broad phase's new pairs (BroadPhase::updatePairs, with the queries of the moved proxies
// on the workers), sorted.
void queryNewPairs(Data& D, StepWorkers& workers) {
  const std::span<const int> moved = D.broadPhase.movedProxies();
  gatherInOrder(
      workers, moved.size(), D.pairChunks, D.proxyPairs,
      [&](std::size_t i, std::vector<ProxyPair>& out) { D.broadPhase.queryPairs(moved[i], out); });
  D.broadPhase.clearMoved();
  std::sort(D.proxyPairs.begin(), D.proxyPairs.end());
}

// Warm start: each point takes last step's impulses by (shapes, sub-shapes, feature id), in
// one walk through both sorted lists per block of contacts, from the block's first key on;
// beside(D) on one worker meanwhile.
void matchWarmStart(Data& D, const ContactTuning& tuning, StepWorkers& workers,
                    void (*beside)(RigidBodyData&)) {
  const std::size_t count = D.contacts.size();
  workers.parallelForBeside(
      [&] { beside(D); }, count, workers.grainFor(count),
      [&](std::size_t first, std::size_t last) {
        auto previous =
            std::lower_bound(D.previous.begin(), D.previous.end(), contactKey(D.contacts[first]),
                             [](const ContactInfo& p, const auto& k) { return contactKey(p) < k; });
        for (std::size_t i = first; i < last; ++i) {
          ContactInfo& c = D.contacts[i];
          ContactExtra& e = D.extras[i];
          e.touching = false;
          for (int k = 0; k < c.manifold.pointCount; ++k)
            e.touching = e.touching || c.manifold.points[k].separation <= tuning.linearSlop;
          if (std::exchange(e.carried, false)) continue;
          const auto key = contactKey(c);
          while (previous != D.previous.end() && contactKey(*previous) < key) ++previous;
          const auto it = previous;
          if (it == D.previous.end() || contactKey(*it) != key || it->bodyA != c.bodyA) continue;
          const ContactExtra& pe =
              D.previousExtras[static_cast<std::size_t>(it - D.previous.begin())];
          bool carried = false;
          for (int k = 0; k < c.manifold.pointCount; ++k) {
            for (int j = 0; j < it->manifold.pointCount; ++j) {
              if (it->manifold.points[j].id != c.manifold.points[k].id) continue;
              c.normalImpulses[k] = it->normalImpulses[j];
              e.tangentImpulse[k] = pe.tangentImpulse[j];
              carried = true;
            }
          }
          if (carried) e.angularImpulse = pe.angularImpulse;
        }
      });
}

// The narrow phase's pairs sorted by shape index, each once, from three runs: the kept pairs,
// the new ones (both in proxy order, which follows the shape order unless proxies were
// recycled: usually sorted already) and the planes'. Each run is sorted when it is not, then
// they are merged into kept buffers (std::inplace_merge would allocate one every step; sorting
// the whole list every step cost 12% of the pile scene, and sorting the new and plane pairs
// as one run fell back to heap sort in the rain's waves of reinsertions).
void sortPairs(Data& D, std::size_t keptCount) {
  const auto sortRun = [](auto first, auto last) {
    if (!std::is_sorted(first, last)) std::sort(first, last);
  };
  const auto keptEnd = D.pairs.begin() + std::ptrdiff_t(keptCount);
  sortRun(D.pairs.begin(), keptEnd);
  sortRun(keptEnd, D.pairs.end());
  sortRun(D.planePairs.begin(), D.planePairs.end());
  D.mergedShapePairs.clear();
  std::merge(D.pairs.begin(), keptEnd, keptEnd, D.pairs.end(),
             std::back_inserter(D.mergedShapePairs));
  D.pairs.clear();
  std::merge(D.mergedShapePairs.begin(), D.mergedShapePairs.end(), D.planePairs.begin(),
             D.planePairs.end(), std::back_inserter(D.pairs));
  D.pairs.erase(std::unique(D.pairs.begin(), D.pairs.end()), D.pairs.end());
}

}  // namespace

void updateBroadPhase(RigidBodyData& D, Real dt, const ContactTuning& tuning,
                      StepWorkers& workers) {
  refreshFrames(D, dt, tuning, workers);
  moveProxies(D, dt);
  queryNewPairs(D, workers);
  // The pairs the narrow phase needs: of two bodies, one of them dynamic, one of them awake.
  auto addPair = [&](std::uint32_t a, std::uint32_t b, std::vector<ShapePair>& out) {
    if (a > b) std::swap(a, b);
    const Data::ShapeFrame& fa = D.frames[a];
    const Data::ShapeFrame& fb = D.frames[b];
    if (fa.body == fb.body) return;
    if (fa.bodyType != BodyType::Dynamic && fb.bodyType != BodyType::Dynamic) return;
    if (!fa.awake && !fb.awake) return;
    if (!shouldCollide(fa.filter, fb.filter)) return;
    // The links of one articulation collide with each other only with its self-collision,
    // and never with their parent.
    if (fa.group >= 0 && fa.group == fb.group &&
        !D.multibodies[std::size_t(fa.group)].membersCollide(D.bodies[fa.body].member,
                                                             D.bodies[fb.body].member))
      return;
    if (fa.jointed && fb.jointed && D.jointPrevents(fa.body, fb.body)) return;
    out.emplace_back(a, b);
  };
  // Last step's pairs whose fat boxes still overlap, and their shape pairs, in one pass; then
  // joined with the new candidates, whose shape pairs follow (a pair found again is in both,
  // once after the sort below).
  gatherInOrder(workers, D.treePairs.size(), D.pairChunks, D.mergedPairs, D.shapePairChunks,
                D.pairs,
                [&](std::size_t i, std::vector<ProxyPair>& kept, std::vector<ShapePair>& out) {
                  const ProxyPair p = D.treePairs[i];
                  if (!D.broadPhase.testOverlap(p.a, p.b)) return;
                  kept.push_back(p);
                  addPair(D.broadPhase.userData(p.a), D.broadPhase.userData(p.b), out);
                });
  const std::size_t treeCount = D.pairs.size();
  for (const ProxyPair& p : D.proxyPairs)
    addPair(D.broadPhase.userData(p.a), D.broadPhase.userData(p.b), D.pairs);
  D.treePairs.clear();
  std::set_union(D.mergedPairs.begin(), D.mergedPairs.end(), D.proxyPairs.begin(),
                 D.proxyPairs.end(), std::back_inserter(D.treePairs));
  // The planes (unbounded, not in the broad phase) against the awake bodies' proxies.
  const std::size_t moved = D.awakeProxies.size();
  gatherInOrder(workers, D.planes.size() * moved, D.shapePairChunks, D.planePairs,
                [&](std::size_t i, std::vector<ShapePair>& out) {
                  const std::uint32_t plane = D.planes[i / moved];
                  const int proxy = D.awakeProxies[i % moved];
                  const Plane& pl = *D.shapes[plane].collider.shape().getIf<Plane>();
                  const Transform& planePose = D.frames[plane].pose;
                  const Vec3 n = planePose.rotate(pl.normal);
                  const Real offset = pl.offset + n.dot(planePose.p);
                  const Aabb& fat = D.broadPhase.fatAabb(proxy);
                  const Vec3 c = Real(0.5) * (fat.lower + fat.upper);
                  const Vec3 e = Real(0.5) * (fat.upper - fat.lower);
                  if (n.dot(c) - offset - n.cwiseAbs().dot(e) <= 0)
                    addPair(plane, D.broadPhase.userData(proxy), out);
                });
  sortPairs(D, treeCount);
}

void updateContacts(RigidBodyData& D, Real dt, const ContactTuning& tuning, StepWorkers& workers,
                    void (*beside)(RigidBodyData&)) {
  const bool reuse = tuning.reuseDistance > 0 && tuning.reuseAngle > 0;
  const Real reuseDistance2 = tuning.reuseDistance * tuning.reuseDistance;
  const Real reuseCosine = std::cos(Real(0.5) * tuning.reuseAngle);  // |q . q'| = cos(angle / 2)
  // The lists of the step before last become this step's: the parallel join overwrites them
  // in place (constructing only what they lack), the sequential path clears and appends.
  std::swap(D.previous, D.contacts);
  std::swap(D.previousExtras, D.extras);
  // The pairs in fixed chunks (boundaries independent of the thread count), each collided into
  // its own buffers on the workers, then joined in chunk order: the same contacts in the same
  // order whatever the number of threads.
  constexpr std::size_t kPairChunk = 32;
  const std::size_t chunkCount = (D.pairs.size() + kPairChunk - 1) / kPairChunk;
  if (D.chunks.size() < chunkCount) D.chunks.resize(chunkCount);
  // Appends chunk `chunk`'s contacts to out.contacts and out.extras.
  auto collideChunk = [&](std::size_t chunk, NarrowOut out) {
    const std::size_t first = chunk * kPairChunk;
    const std::size_t last = std::min(first + kPairChunk, D.pairs.size());
    auto previous =
        std::lower_bound(D.previous.begin(), D.previous.end(),
                         std::make_tuple(D.pairs[first].first, D.pairs[first].second, 0u, 0u),
                         [](const ContactInfo& p, const auto& k) { return contactKey(p) < k; });
    for (std::size_t pi = first; pi < last; ++pi) {
      // Not a structured binding: the lambda below captures them (clang before 16 cannot).
      const auto a = std::get<0>(D.pairs[pi]), b = std::get<1>(D.pairs[pi]);
      const Data::ShapeFrame& fa = D.frames[a];
      const Data::ShapeFrame& fb = D.frames[b];
      ContactSettings cs;
      cs.speculativeDistance = tuning.speculativeDistance;
      if (fa.fast || fb.fast) {
        const BodyRecord& ba = D.bodies[fa.body];
        const BodyRecord& bb = D.bodies[fb.body];
        cs.speculativeDistance +=
            ((bb.v - ba.v).norm() + ba.w.norm() * ba.extent + bb.w.norm() * bb.extent) * dt;
      }
      // The shapes' bounding spheres farther apart than the speculative distance: no contact,
      // without the narrow phase. A third of a resting rain's box pairs whose fat boxes
      // overlap end here. (A plane's infinite radius never passes.)
      const Real reach = fa.radius + fb.radius + cs.speculativeDistance;
      if ((fb.pose.p - fa.pose.p).squaredNorm() > reach * reach) continue;
      const Transform& poseA = fa.pose;
      const Transform& poseB = fb.pose;
      // The pair's ids, made only for a pair that has a manifold.
      const auto newContact = [&]() -> ContactInfo& {
        ContactInfo& info = out.contacts.emplace_back();
        info.bodyA = {fa.body, fa.bodyGeneration};
        info.bodyB = {fb.body, fb.bodyGeneration};
        info.shapeA = {a, fa.generation};
        info.shapeB = {b, fb.generation};
        return info;
      };
      // A sphere's manifold is one point query (two spheres: their centres), cheaper than
      // carrying one along.
      const bool convex = singleManifold(fa.type) && singleManifold(fb.type);
      const bool cacheable = reuse && cs.speculativeDistance == tuning.speculativeDistance &&
                             convex && fa.type != ShapeType::Sphere && fb.type != ShapeType::Sphere;
      // B's pose in A's, computed only for a pair with last step's manifold or a new one (most
      // of a rain's candidate pairs have neither).
      const auto relativePose = [&] { return poseA.inverse() * poseB; };
      if (cacheable) {
        // Last step's manifold of this pair, if its features still hold. The pairs and last
        // step's contacts are both sorted by shapes: one walk through the latter per chunk.
        const auto key = std::make_tuple(a, b, 0u, 0u);
        while (previous != D.previous.end() && contactKey(*previous) < key) ++previous;
        const auto it = previous;
        if (it != D.previous.end() && contactKey(*it) == key &&
            it->bodyA == BodyId{fa.body, fa.bodyGeneration}) {
          const ContactExtra& pe =
              D.previousExtras[static_cast<std::size_t>(it - D.previous.begin())];
          const Transform relative = relativePose();
          if (pe.reusable && (relative.p - pe.relative.p).squaredNorm() < reuseDistance2 &&
              std::abs(relative.q.dot(pe.relative.q)) > reuseCosine) {
            ContactInfo& info = newContact();
            info.manifold = it->manifold;
            info.normalImpulses = it->normalImpulses;
            ContactManifold& m = info.manifold;
            // Up to nine vectors to rotate: as matrices, each costs less than a quaternion
            // rotation.
            const Mat3 rotationA = poseA.q.toRotationMatrix();
            const Mat3 rotationB = poseB.q.toRotationMatrix();
            m.normal = rotationA * pe.localNormal;
            for (int k = 0; k < m.pointCount; ++k) {
              ContactPoint& p = m.points[static_cast<std::size_t>(k)];
              p.pointA = rotationA * pe.localA[static_cast<std::size_t>(k)] + poseA.p;
              p.pointB = rotationB * pe.localB[static_cast<std::size_t>(k)] + poseB.p;
              p.separation = (p.pointB - p.pointA).dot(m.normal);
            }
            // Last step's record carries the manifold's frames and the impulses.
            out.extras.emplace_back(pe).reuse();
            continue;
          }
        }
      }
      const auto add = [&](const ContactManifold& m) {
        newContact().manifold = m;
        ContactExtra& e = out.extras.emplace_back();
        if (cacheable) {
          e.reusable = true;
          e.relative = relativePose();
          e.localNormal = poseA.q.conjugate() * m.normal;
          for (int k = 0; k < m.pointCount; ++k) {
            const ContactPoint& p = m.points[static_cast<std::size_t>(k)];
            e.localA[static_cast<std::size_t>(k)] = poseA.applyInverse(p.pointA);
            e.localB[static_cast<std::size_t>(k)] = poseB.applyInverse(p.pointB);
          }
        }
      };
      const Collider& ca = D.shapes[a].collider;
      const Collider& cb = D.shapes[b].collider;
      if (convex) {
        // One manifold at most, without the vector.
        ContactManifold m;
        if (collideConvex(ca, poseA, cb, poseB, cs, m) && m.pointCount > 0) add(m);
        continue;
      }
      out.manifolds.clear();
      collide(ca, poseA, cb, poseB, cs, out.manifolds);
      for (const ContactManifold& m : out.manifolds)
        if (m.pointCount > 0) add(m);
    }
  };
  if (workers.threadCount() > 1 && chunkCount > 1) {
    workers.parallelFor(
        chunkCount,
        [&](std::size_t first, std::size_t last) {
          for (std::size_t c = first; c < last; ++c) {
            NarrowChunk& chunk = D.chunks[c];
            chunk.contacts.clear();
            chunk.extras.clear();
            collideChunk(c, {chunk.contacts, chunk.extras, chunk.manifolds});
          }
        },
        4, 8);
    // Joined in chunk order: each chunk copies into its place.
    D.chunkOffsets.resize(chunkCount + 1);
    D.chunkOffsets[0] = 0;
    for (std::size_t c = 0; c < chunkCount; ++c)
      D.chunkOffsets[c + 1] = D.chunkOffsets[c] + D.chunks[c].contacts.size();
    D.contacts.resize(D.chunkOffsets[chunkCount]);
    D.extras.resize(D.chunkOffsets[chunkCount]);
    workers.parallelFor(
        chunkCount,
        [&](std::size_t first, std::size_t last) {
          for (std::size_t c = first; c < last; ++c) {
            const auto at = std::ptrdiff_t(D.chunkOffsets[c]);
            std::copy(D.chunks[c].contacts.begin(), D.chunks[c].contacts.end(),
                      D.contacts.begin() + at);
            std::copy(D.chunks[c].extras.begin(), D.chunks[c].extras.end(), D.extras.begin() + at);
          }
        },
        16);
  } else {
    // In sequence the chunks append straight to the step's lists, in the same order.
    D.contacts.clear();
    D.extras.clear();
    for (std::size_t c = 0; c < chunkCount; ++c)
      collideChunk(c, {D.contacts, D.extras, D.manifolds});
  }
  // Contacts between bodies that did not move (asleep or static) keep last step's state.
  for (std::size_t i = 0; i < D.previous.size(); ++i) {
    const ContactInfo& c = D.previous[i];
    // The cheap test first: most of last step's contacts have an awake body. (Body slots are
    // never freed, so the index is in range even for a destroyed body.)
    if (D.bodies[c.bodyA.index].awake || D.bodies[c.bodyB.index].awake) continue;
    if (!D.isValidShape(c.shapeA) || !D.isValidShape(c.shapeB)) continue;
    D.contacts.push_back(c);
    D.extras.push_back(D.previousExtras[i]);
  }
  // A deterministic order: by shapes, then sub-shapes. The pairs come sorted, so only the
  // kept contacts of resting bodies or a compound's manifolds can leave it unsorted.
  const auto byKey = [](const ContactInfo& x, const ContactInfo& y) {
    return contactKey(x) < contactKey(y);
  };
  if (!std::is_sorted(D.contacts.begin(), D.contacts.end(), byKey)) {
    D.order.resize(D.contacts.size());
    std::iota(D.order.begin(), D.order.end(), 0u);
    std::stable_sort(D.order.begin(), D.order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return byKey(D.contacts[x], D.contacts[y]);
    });
    D.sortedContacts.clear();
    D.sortedExtras.clear();
    for (std::uint32_t i : D.order) {
      D.sortedContacts.push_back(D.contacts[i]);
      D.sortedExtras.push_back(D.extras[i]);
    }
    D.contacts.swap(D.sortedContacts);
    D.extras.swap(D.sortedExtras);
  }
  matchWarmStart(D, tuning, workers, beside);
}

void reportContactEvents(RigidBodyData& D) {
  // 7. Contact events: pairs of shapes touching now and not before, and the reverse.
  auto touchingPairs = [](const std::vector<ContactInfo>& cs, const std::vector<ContactExtra>& es,
                          std::vector<std::size_t>& out) {
    out.clear();
    for (std::size_t i = 0; i < cs.size(); ++i) {
      if (!es[i].touching) continue;
      if (!out.empty() && cs[out.back()].shapeA == cs[i].shapeA &&
          cs[out.back()].shapeB == cs[i].shapeB)
        continue;
      out.push_back(i);
    }
  };
  std::vector<std::size_t>& now = D.touchingNow;
  std::vector<std::size_t>& before = D.touchingBefore;
  touchingPairs(D.contacts, D.extras, now);
  touchingPairs(D.previous, D.previousExtras, before);
  auto pairOf = [](const ContactInfo& c) { return pairKey(c.shapeA.index, c.shapeB.index); };
  auto event = [&](const ContactInfo& c, Real approach) {
    ContactEvent e;
    e.bodyA = c.bodyA;
    e.bodyB = c.bodyB;
    e.shapeA = c.shapeA;
    e.shapeB = c.shapeB;
    e.normal = c.manifold.normal;
    const ContactPoint& p = c.manifold.points[0];
    e.point = Real(0.5) * (p.pointA + p.pointB);
    e.approachSpeed = approach;
    return e;
  };
  std::size_t i = 0, j = 0;
  while (i < now.size() || j < before.size()) {
    const std::uint64_t a = i < now.size() ? pairOf(D.contacts[now[i]]) : ~std::uint64_t(0);
    const std::uint64_t b = j < before.size() ? pairOf(D.previous[before[j]]) : ~std::uint64_t(0);
    if (a == b) {
      ++i;
      ++j;
    } else if (a < b) {
      D.beginEvents.push_back(event(D.contacts[now[i]], D.extras[now[i]].approach));
      ++i;
    } else {
      const ContactInfo& c = D.previous[before[j]];
      if (D.isValidShape(c.shapeA) && D.isValidShape(c.shapeB)) D.endEvents.push_back(event(c, 0));
      ++j;
    }
  }
}

}  // namespace inertia::detail
