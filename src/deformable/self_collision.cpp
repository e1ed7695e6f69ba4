// The self-collision stage of a deformable's step, and collisions between deformables, after
// Bridson, Fedkiw and Anderson ("Robust treatment of collisions, contact and friction for cloth
// animation", SIGGRAPH 2002). The stage works on each vertex's mean velocity over the step,
// u = (x1 - x0) / h, moving every point linearly from x0 to x0 + h u:
//  1. proximity: a vertex within the thickness of a triangle at the step's start gets an
//     inelastic repulsion impulse so that it moves away by at least a tenth of the overlap;
//  2. collisions: vertex-triangle and edge-edge pairs whose straight motions meet (the
//     coplanarity cubic of collision/continuous_triangle) get an inelastic impulse that leaves
//     them separating; repeated up to kPasses times while any remains;
//  3. fail-safe impact zones (after Provot 1997 and Bridson et al. 7.4, simplified to
//     translation): vertices of pairs that still collide are merged into zones, each moved
//     with its mean (momentum-conserving) velocity, or held still when it holds a pinned
//     vertex, until no pair collides. A zone moves rigidly, so its own pairs cannot cross;
//     zones only grow, so this ends, at worst with everything moving as one.
// Impulses are shared by the vertices' masses with the contact's barycentric weights (pinned
// vertices have no inverse mass). The changes of u are added to the velocities, and
// x1 = x0 + h u. Candidate pairs come from the collision layer's dynamic AABB trees over the
// features' swept boxes, kept between calls in a DeformableCollisionCache and moved only when a
// box leaves its fat box. Each pass gathers its candidates and sorts them, so the impulses are
// applied in one order whatever the trees' shape (snapshots and thread counts agree).
#include <algorithm>

#include "core/union_find.h"
#include "deformable/scratch.h"
#include "inertia/collision/continuous_triangle.h"
#include "inertia/collision/dynamic_tree.h"
#include "inertia/collision/triangle.h"

namespace inertia {

namespace {

constexpr int kPasses = 8;              // collision passes before impact zones
constexpr int kZoneRounds = 1000;       // bound on the impact zones' loop (each round merges)
constexpr Real kRepulsion = Real(0.1);  // fraction of the overlap undone per step (Bridson)

}  // namespace

namespace detail {

// All vertices of the deformables taking part, in one numbering.
struct CollisionStage {
  Real h = 0, thickness = 0;
  std::vector<Vec3> x0, u;
  std::vector<Real> inverseMass;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint32_t, 2>> edges;
  Aabb swept(std::span<const std::uint32_t> vertices, Real margin) const {
    Aabb box{x0[vertices[0]], x0[vertices[0]]};
    for (std::uint32_t i : vertices) {
      const Vec3 end = x0[i] + h * u[i];
      box.lower = box.lower.cwiseMin(x0[i]).cwiseMin(end);
      box.upper = box.upper.cwiseMax(x0[i]).cwiseMax(end);
    }
    return box.inflated(margin);
  }
  LinearMotion motion(std::uint32_t i) const { return {x0[i], x0[i] + h * u[i]}; }
};

// A pass's candidate pairs: (vertex, triangle) and (edge, edge) whose swept boxes, each
// inflated by half the thickness, overlap (every pair that comes within the thickness over the
// step: repulsion's and the continuous tests' reach), features sharing no vertex; each edge
// pair once, lower index first.
struct CollisionCandidates {
  std::vector<std::array<std::uint32_t, 2>> vertexTriangle, edgeEdge;
};

}  // namespace detail

namespace {

using Stage = detail::CollisionStage;
using Candidates = detail::CollisionCandidates;

// An inelastic impulse along n on the points sum c_k x_k (c the contact's weights), bringing
// their relative normal velocity sum c_k u_k . n up to `target`. False when nothing can move.
bool push(Stage& s, std::span<const std::uint32_t> ids, std::span<const Real> c, const Vec3& n,
          Real target) {
  Real vn = 0, w = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    vn += c[k] * s.u[ids[k]].dot(n);
    w += c[k] * c[k] * s.inverseMass[ids[k]];
  }
  if (!(vn < target) || !(w > 0)) return false;
  const Real j = (target - vn) / w;
  for (std::size_t k = 0; k < ids.size(); ++k)
    s.u[ids[k]] += (c[k] * j * s.inverseMass[ids[k]]) * n;
  return true;
}

bool shares(const std::array<std::uint32_t, 3>& t, std::uint32_t i) {
  return t[0] == i || t[1] == i || t[2] == i;
}
bool shares(const std::array<std::uint32_t, 2>& a, const std::array<std::uint32_t, 2>& b) {
  return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

// Barycentric coordinates of p, a point of the triangle (a, b, c) (Ericson 3.4), least-squares
// for a sliver; always finite.
Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const Real d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const Real d20 = v2.dot(v0), d21 = v2.dot(v1), det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return Vec3(1, 0, 0);
  const Real v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
  return Vec3(1 - v - w, v, w);
}

}  // namespace

struct DeformableCollisionCache::Impl {
  Stage stage;
  std::vector<Vec3> before;
  std::vector<std::uint32_t> offsets;
  // The features' swept boxes (exact, this pass, inflated by half the thickness) and their
  // proxies in trees whose fat boxes add a quarter of it; rebuilt when the features or the
  // thickness change.
  DynamicTree triangleTree, edgeTree;
  std::vector<int> triangleProxies, edgeProxies;
  std::vector<Aabb> triangleBoxes, edgeBoxes;
  Real thickness = -1;  // the trees were built for
  Candidates candidates;
  // The impact zones' union-find and sums.
  detail::UnionFind zones;
  std::vector<Vec3> momentum;
  std::vector<Real> mass;
  std::vector<std::uint8_t> held, zone;
};

DeformableCollisionCache::DeformableCollisionCache() : impl_(std::make_unique<Impl>()) {}
DeformableCollisionCache::~DeformableCollisionCache() = default;
DeformableCollisionCache::DeformableCollisionCache(const DeformableCollisionCache&)
    : impl_(std::make_unique<Impl>()) {}
DeformableCollisionCache& DeformableCollisionCache::operator=(const DeformableCollisionCache&) {
  impl_ = std::make_unique<Impl>();
  return *this;
}
DeformableCollisionCache::DeformableCollisionCache(DeformableCollisionCache&&) noexcept = default;
DeformableCollisionCache& DeformableCollisionCache::operator=(DeformableCollisionCache&&) noexcept =
    default;

namespace {

using Cache = DeformableCollisionCache::Impl;

// Every feature's swept box; a box that left its fat box is moved in its tree, and one whose
// fat box has grown far larger than it (a fast step's sweep, now at rest) is inserted afresh, so
// that fat boxes shrink again (all are inserted afresh when the features or the thickness
// changed).
template <class Feature>
void updateTree(const Stage& s, std::span<const Feature> features, bool rebuild, DynamicTree& tree,
                std::vector<int>& proxies, std::vector<Aabb>& boxes) {
  boxes.resize(features.size());
  if (rebuild) proxies.clear();
  for (std::size_t k = 0; k < features.size(); ++k) {
    boxes[k] = s.swept(features[k], s.thickness / 2);
    if (rebuild) {
      proxies.push_back(tree.createProxy(boxes[k], std::uint32_t(k)));
    } else if (!boxes[k].inflated(s.thickness).contains(tree.fatAabb(proxies[k]))) {
      tree.destroyProxy(proxies[k]);
      proxies[k] = tree.createProxy(boxes[k], std::uint32_t(k));
    } else {
      tree.moveProxy(proxies[k], boxes[k], Vec3::Zero());
    }
  }
}

void updateTrees(Cache& c, bool withEdges) {
  const Stage& s = c.stage;
  const bool rebuild = c.thickness != s.thickness ||
                       c.triangleProxies.size() != s.triangles.size() ||
                       c.edgeProxies.size() != s.edges.size();
  if (rebuild) {
    const DynamicTreeSettings fat{.margin = s.thickness / 4, .displacementMultiplier = 0};
    c.triangleTree = DynamicTree(fat);
    c.edgeTree = DynamicTree(fat);
    c.thickness = s.thickness;
  }
  updateTree<std::array<std::uint32_t, 3>>(s, s.triangles, rebuild, c.triangleTree,
                                           c.triangleProxies, c.triangleBoxes);
  if (withEdges || rebuild)
    updateTree<std::array<std::uint32_t, 2>>(s, s.edges, rebuild, c.edgeTree, c.edgeProxies,
                                             c.edgeBoxes);
}

// The pass's candidates, sorted (see the file comment). Repulsion needs no edge pairs.
const Candidates& gatherCandidates(Cache& c, bool withEdges) {
  updateTrees(c, withEdges);
  const Stage& s = c.stage;
  Candidates& out = c.candidates;
  out.vertexTriangle.clear();
  out.edgeEdge.clear();
  for (std::uint32_t i = 0; i < s.x0.size(); ++i) {
    const std::uint32_t one[] = {i};
    const Aabb box = s.swept(one, s.thickness / 2);
    c.triangleTree.query(box, [&](int id) {
      const std::uint32_t t = c.triangleTree.userData(id);
      if (c.triangleBoxes[t].overlaps(box) && !shares(s.triangles[t], i))
        out.vertexTriangle.push_back({i, t});
    });
  }
  if (withEdges)
    for (std::uint32_t e = 0; e < s.edges.size(); ++e)
      c.edgeTree.query(c.edgeBoxes[e], [&](int id) {
        const std::uint32_t other = c.edgeTree.userData(id);
        if (other > e && c.edgeBoxes[other].overlaps(c.edgeBoxes[e]) &&
            !shares(s.edges[e], s.edges[other]))
          out.edgeEdge.push_back({e, other});
      });
  std::sort(out.vertexTriangle.begin(), out.vertexTriangle.end());
  std::sort(out.edgeEdge.begin(), out.edgeEdge.end());
  return out;
}

// Stage 1: repulsion at the start's proximities (vertex-triangle).
void repel(Cache& cache) {
  Stage& s = cache.stage;
  for (const auto [i, t] : gatherCandidates(cache, false).vertexTriangle) {
    const auto& tri = s.triangles[t];
    const TriangleClosest q =
        closestPointOnTriangle(s.x0[i], s.x0[tri[0]], s.x0[tri[1]], s.x0[tri[2]]);
    const Vec3 d = s.x0[i] - q.point;
    const Real distance = d.norm();
    if (!(distance < s.thickness) || !(distance > 0)) continue;
    const Vec3 w = barycentric(q.point, s.x0[tri[0]], s.x0[tri[1]], s.x0[tri[2]]);
    const std::uint32_t ids[] = {i, tri[0], tri[1], tri[2]};
    const Real c[] = {1, -w[0], -w[1], -w[2]};
    push(s, ids, c, d / distance, kRepulsion * (s.thickness - distance) / s.h);
  }
}

// The pairs whose motions over the step meet, each handed to f(ids, weights, normal).
template <class F>
void forEachCollision(Cache& cache, F&& f) {
  const Stage& s = cache.stage;
  const ContinuousTriangleSettings ccd{.thickness = Real(1e-3) * s.thickness};
  const Candidates& candidates = gatherCandidates(cache, true);
  for (const auto [i, t] : candidates.vertexTriangle) {
    const auto& tri = s.triangles[t];
    const auto hit = vertexFaceContinuous(s.motion(i), s.motion(tri[0]), s.motion(tri[1]),
                                          s.motion(tri[2]), ccd);
    if (!hit) continue;
    const std::array<std::uint32_t, 4> ids = {i, tri[0], tri[1], tri[2]};
    const Vec3& w = hit->barycentric;
    f(ids, std::array<Real, 4>{1, -w[0], -w[1], -w[2]}, hit->normal);
  }
  for (const auto [a, b] : candidates.edgeEdge) {
    const auto& ea = s.edges[a];
    const auto& eb = s.edges[b];
    const auto hit = edgeEdgeContinuous(s.motion(ea[0]), s.motion(ea[1]), s.motion(eb[0]),
                                        s.motion(eb[1]), ccd);
    if (!hit) continue;
    const std::array<std::uint32_t, 4> ids = {ea[0], ea[1], eb[0], eb[1]};
    f(ids, std::array<Real, 4>{1 - hit->s, hit->s, -(1 - hit->u), -hit->u}, hit->normal);
  }
}

// Stage 2: impulses until no pair collides or the passes run out; true when none is left.
bool resolveImpacts(Cache& cache) {
  Stage& s = cache.stage;
  const Real separating = kRepulsion * s.thickness / s.h;
  for (int pass = 0; pass < kPasses; ++pass) {
    bool any = false;
    forEachCollision(cache, [&](const auto& ids, const auto& c, const Vec3& n) {
      any = true;
      push(s, ids, c, n, separating);
    });
    if (!any) return true;
  }
  return false;
}

// Stage 3: impact zones moving as one (see the file comment).
void impactZones(Cache& cache) {
  Stage& s = cache.stage;
  const std::size_t n = s.x0.size();
  detail::UnionFind& zones = cache.zones;
  zones.reset(n);
  for (int round = 0; round < kZoneRounds; ++round) {
    bool merged = false;
    forEachCollision(cache, [&](const auto& ids, const auto&, const Vec3&) {
      for (std::uint32_t k : ids) merged = zones.unite(ids[0], k) || merged;
    });
    // None left, or only pairs inside zones, which move rigidly and so cannot cross (what is
    // left is the test's tolerance on pairs that start within it of each other).
    if (!merged) return;
    // Each zone's momentum (a pinned member holds it still).
    cache.momentum.assign(n, Vec3::Zero());
    cache.mass.assign(n, 0);
    cache.held.assign(n, 0);
    cache.zone.assign(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t r = zones.find(i);
      if (r != i) cache.zone[r] = cache.zone[i] = 1;
      if (s.inverseMass[i] == 0) {
        cache.held[r] = 1;
        continue;
      }
      cache.mass[r] += 1 / s.inverseMass[i];
      cache.momentum[r] += s.u[i] / s.inverseMass[i];
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t r = zones.find(i);
      if (!cache.zone[r]) continue;
      s.u[i] = cache.held[r] ? Vec3::Zero() : Vec3(cache.momentum[r] / cache.mass[r]);
    }
  }
}

}  // namespace

void Deformable::collideDeformables(std::span<Deformable* const> deformables, Real h,
                                    DeformableCollisionCache& collisionCache) {
  if (deformables.empty()) return;
  if (!collisionCache.impl_) collisionCache.impl_ = std::make_unique<Cache>();  // moved from
  Cache& cache = *collisionCache.impl_;
  Stage& s = cache.stage;
  s.h = h;
  s.thickness = 0;
  s.x0.clear();
  s.u.clear();
  s.inverseMass.clear();
  s.triangles.clear();
  s.edges.clear();
  std::vector<std::uint32_t>& offsets = cache.offsets;
  offsets.clear();
  for (const Deformable* d : deformables) {
    const std::uint32_t offset = std::uint32_t(s.x0.size());
    offsets.push_back(offset);
    s.thickness = std::max(s.thickness, d->settings_.thickness);
    for (std::size_t i = 0; i < d->vertexCount(); ++i) {
      const Vec3 x0 = Eigen::Map<const Vec3>(&d->scratch_->start[3 * i]);
      const Vec3 x1 = Eigen::Map<const Vec3>(&d->x_[3 * i]);
      s.x0.push_back(x0);
      s.u.push_back(d->pinned_[i] ? Vec3::Zero() : Vec3((x1 - x0) / h));
      s.inverseMass.push_back(d->pinned_[i] ? Real(0) : 1 / d->masses_[i]);
    }
    for (const auto& t : d->triangles_)
      s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    for (const auto& e : d->edges_) s.edges.push_back({e[0] + offset, e[1] + offset});
  }
  cache.before = s.u;
  repel(cache);
  if (!resolveImpacts(cache)) impactZones(cache);
  for (std::size_t k = 0; k < deformables.size(); ++k) {
    Deformable& d = *deformables[k];
    for (std::size_t i = 0; i < d.vertexCount(); ++i) {
      const std::size_t g = offsets[k] + i;
      if (d.pinned_[i]) continue;
      Eigen::Map<Vec3>(&d.v_[3 * i]) += s.u[g] - cache.before[g];
      Eigen::Map<Vec3>(&d.x_[3 * i]) = s.x0[g] + h * s.u[g];
    }
  }
}

}  // namespace inertia
