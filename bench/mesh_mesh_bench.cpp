// Mesh against mesh: two closed triangle meshes of 81,920 triangles each (no bunny is available
// offline: icospheres subdivided six times, radii 1 m and 0.8 m, with deterministic radial bumps
// of a few per cent), queried in 200 relative poses (random rotation, centres 0.6..2.4 m apart:
// some intersecting, some separated). Queries per second of
//   - meshesOverlap: does any pair of triangles intersect (dual BVH traversal, first hit stops),
//   - collide(): every intersecting triangle pair with its manifold (the contact path),
//   - meshDistance: the exact distance (0 when intersecting) by branch and bound,
// and, when Bullet was found at configure time, btGImpactMeshShape against btGImpactMeshShape
// through btCollisionWorld::contactPairTest (GImpact's mesh-mesh algorithm; Bullet has no
// mesh-mesh distance query, and btBvhTriangleMeshShape pairs are not supported at all), in the
// same run. The reference is the seeds' figure for Gottschalk et al.'s OBBTree (SIGGRAPH 1996):
// 110 overlap queries per second for two 70,000-triangle bunnies.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "inertia/collision/contact.h"
#include "inertia/collision/distance.h"
#include "inertia/geometry/geometry.h"

#ifdef INERTIA_BENCH_BULLET
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletCollisionCommon.h>
#endif

using namespace inertia;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kLevels = 6;  // 20 * 4^6 = 81,920 triangles
constexpr int kPoses = 200;
constexpr double kMinSeconds = 0.5;  // per measurement

// An icosphere of `levels` subdivisions, its vertices pushed to radius
// r (1 + bumps(direction)): smooth deterministic bumps plus finer ripples.
TriangleMesh bumpySphere(double r, int levels, double phase) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Triangle> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = std::uint32_t(v.size() - 1);
    };
    std::vector<Triangle> g;
    g.reserve(4 * f.size());
    for (const Triangle& tri : f) {
      const std::uint32_t ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]),
                          ca = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], ab, ca});
      g.push_back({tri[1], bc, ab});
      g.push_back({tri[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  std::vector<Vec3> out;
  out.reserve(v.size());
  for (const auto& d : v) {
    const double bump =
        0.04 * std::sin(5 * d.x() + phase) * std::sin(6 * d.y()) * std::sin(7 * d.z()) +
        0.01 * std::sin(23 * d.x() + 19 * d.y() + phase) * std::cos(29 * d.z());
    out.push_back((r * (1 + bump) * d).cast<Real>());
  }
  return TriangleMesh(std::move(out), std::move(f));
}

template <class F>
double queriesPerSecond(F&& query) {
  int reps = 0;
  const auto t0 = Clock::now();
  double elapsed = 0;
  do {
    for (int i = 0; i < kPoses; ++i) query(i);
    ++reps;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  } while (elapsed < kMinSeconds);
  return reps * kPoses / elapsed;
}

}  // namespace

int main() {
  const auto b0 = Clock::now();
  const TriangleMesh meshA = bumpySphere(1.0, kLevels, 0.0), meshB = bumpySphere(0.8, kLevels, 1.3);
  const Collider a{Shape(meshA)}, b{Shape(meshB)};
  const double buildSeconds = std::chrono::duration<double>(Clock::now() - b0).count();

  std::mt19937_64 rng(7);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.6, 2.4);
  std::vector<Transform> poses;
  for (int i = 0; i < kPoses; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    const Quat q = Quat(Real(n(rng)), Real(n(rng)), Real(n(rng)), Real(n(rng))).normalized();
    poses.push_back({(u(rng) * dir).cast<Real>(), q});
  }
  const Transform poseA = Transform::identity();

  // Agreement first: overlap, contacts and distance classify every pose alike.
  int intersecting = 0, disagree = 0;
  double minSep = 1e300, maxSep = 0;
  std::vector<ContactManifold> manifolds;
  for (int i = 0; i < kPoses; ++i) {
    const bool hit = meshesOverlap(a, poseA, b, poses[std::size_t(i)]);
    manifolds.clear();
    collide(a, poseA, b, poses[std::size_t(i)], ContactSettings{.speculativeDistance = 0},
            manifolds);
    const auto d = meshDistance(a, poseA, b, poses[std::size_t(i)]);
    intersecting += hit;
    disagree += (hit != !manifolds.empty()) + (hit != (d->distance == 0));
    if (d->distance > 0)
      minSep = std::min(minSep, double(d->distance)),
      maxSep = std::max(maxSep, double(d->distance));
  }

  std::size_t contactPairs = 0;
  const double overlapQps = queriesPerSecond([&](int i) {
    volatile bool hit = meshesOverlap(a, poseA, b, poses[std::size_t(i)]);
    (void)hit;
  });
  const double collideQps = queriesPerSecond([&](int i) {
    manifolds.clear();
    collide(a, poseA, b, poses[std::size_t(i)], ContactSettings{.speculativeDistance = 0},
            manifolds);
    contactPairs += manifolds.size();
  });
  const double distanceQps = queriesPerSecond([&](int i) {
    volatile Real d = meshDistance(a, poseA, b, poses[std::size_t(i)])->distance;
    (void)d;
  });
  // Separated poses only: the distance query cannot stop at a first intersecting pair.
  std::vector<int> apart;
  for (int i = 0; i < kPoses; ++i)
    if (!meshesOverlap(a, poseA, b, poses[std::size_t(i)])) apart.push_back(i);
  double apartQps = 0;
  if (!apart.empty()) {
    int reps = 0;
    const auto t0 = Clock::now();
    double elapsed = 0;
    do {
      for (int i : apart) {
        volatile Real d = meshDistance(a, poseA, b, poses[std::size_t(i)])->distance;
        (void)d;
      }
      ++reps;
      elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    } while (elapsed < kMinSeconds);
    apartQps = double(reps) * double(apart.size()) / elapsed;
  }

  std::printf(
      "Two icospheres of %zu and %zu triangles (bumpy, radii 1 and 0.8 m; BVHs built in "
      "%.2f s), %d poses: %d intersecting, %d apart (%.3g..%.3g m); %d disagreements "
      "between overlap, collide and distance.\n\n",
      meshA.triangles().size(), meshB.triangles().size(), buildSeconds, kPoses, intersecting,
      kPoses - intersecting, minSep, maxSep, disagree);
  std::printf("| query | queries/s |\n|---|---|\n");
  std::printf("| Inertia meshesOverlap (first intersecting pair) | %.0f |\n", overlapQps);
  std::printf("| Inertia collide() mesh-mesh (all pairs + manifolds) | %.0f |\n", collideQps);
  std::printf("| Inertia meshDistance (all poses) | %.0f |\n", distanceQps);
  std::printf("| Inertia meshDistance (separated poses only) | %.0f |\n", apartQps);

#ifdef INERTIA_BENCH_BULLET
  {
    // GImpact over the same triangles and poses (float); contactPairTest runs GImpact's
    // mesh-mesh algorithm (its BVH pair traversal and triangle-triangle SAT) with no early out.
    struct BulletMesh {
      std::vector<int> indices;
      std::vector<btScalar> vertices;
      std::unique_ptr<btTriangleIndexVertexArray> array;
      std::unique_ptr<btGImpactMeshShape> shape;
      explicit BulletMesh(const TriangleMesh& m) {
        for (const Triangle& t : m.triangles())
          for (std::uint32_t k : t) indices.push_back(int(k));
        for (const Vec3& p : m.vertices())
          for (int k = 0; k < 3; ++k) vertices.push_back(btScalar(p[k]));
        array = std::make_unique<btTriangleIndexVertexArray>(
            int(m.triangles().size()), indices.data(), int(3 * sizeof(int)),
            int(m.vertices().size()), vertices.data(), int(3 * sizeof(btScalar)));
        shape = std::make_unique<btGImpactMeshShape>(array.get());
        shape->updateBound();
      }
    };
    const BulletMesh ba(meshA), bb(meshB);
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btGImpactCollisionAlgorithm::registerAlgorithm(&dispatcher);
    // contactPairTest asks the dispatcher's closest-points table, which registerAlgorithm does
    // not fill: register GImpact's algorithm there too.
    static btGImpactCollisionAlgorithm::CreateFunc gimpactCreate;
    dispatcher.registerClosestPointsCreateFunc(GIMPACT_SHAPE_PROXYTYPE, GIMPACT_SHAPE_PROXYTYPE,
                                               &gimpactCreate);
    btDbvtBroadphase broadphase;
    btCollisionWorld world(&dispatcher, &broadphase, &config);
    btCollisionObject oa, ob;
    oa.setCollisionShape(ba.shape.get());
    ob.setCollisionShape(bb.shape.get());
    struct Counter : btCollisionWorld::ContactResultCallback {
      int contacts = 0;
      btScalar addSingleResult(btManifoldPoint&, const btCollisionObjectWrapper*, int, int,
                               const btCollisionObjectWrapper*, int, int) override {
        ++contacts;
        return 0;
      }
    };
    const auto place = [&](int i) {
      const Transform& p = poses[std::size_t(i)];
      btTransform x;
      x.setOrigin(btVector3(btScalar(p.p.x()), btScalar(p.p.y()), btScalar(p.p.z())));
      x.setRotation(
          btQuaternion(btScalar(p.q.x()), btScalar(p.q.y()), btScalar(p.q.z()), btScalar(p.q.w())));
      ob.setWorldTransform(x);
    };
    int bulletHits = 0;
    for (int i = 0; i < kPoses; ++i) {
      place(i);
      Counter c;
      world.contactPairTest(&oa, &ob, c);
      bulletHits += c.contacts > 0;
    }
    const double bulletQps = queriesPerSecond([&](int i) {
      place(i);
      Counter c;
      world.contactPairTest(&oa, &ob, c);
    });
    std::printf("| Bullet %d.%02d btGImpactMeshShape pair, contactPairTest | %.0f |\n",
                btGetVersion() / 100, btGetVersion() % 100, bulletQps);
    std::printf("\nBullet reports contacts in %d of the %d poses (margin %.3g m per shape).\n",
                bulletHits, kPoses, double(ba.shape->getMargin()));
  }
#else
  std::printf("\nBullet not found at configure time: no GImpact comparison.\n");
#endif
  std::printf(
      "Reference: OBBTree (Gottschalk, Lin, Manocha 1996), two 70,000-triangle bunnies: "
      "110 overlap queries/s.\n");
  std::printf("(%zu contact manifolds over the timed collide() runs)\n", contactPairs);
  return disagree == 0 ? 0 : 1;
}
