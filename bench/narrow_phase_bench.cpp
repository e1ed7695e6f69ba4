// Narrow phase and ray casts against Bullet 3 in the same run (issue 4's speed figures):
// - box-box manifolds: Inertia's collide() (SAT with Gauss-map pruning and clipping, up to 4
//   points) against Bullet's btBoxBoxDetector (ODE's box-box: SAT and clipping, up to 4 points);
// - hull-hull: collide() on hulls of 24 random points (SAT and clipping) against Bullet's
//   btGjkPairDetector with EPA on btConvexHullShape (one closest point per call, not a
//   manifold: Bullet's manifold comes from adding one point per frame);
// - ray casts against a 100,352-triangle mesh (a bumpy 224 x 224 grid): castRay() on the mesh's
//   BVH against btBvhTriangleMeshShape::performRaycast, closest hit.
// Random poses from a fixed seed; every pair of the box and hull sets overlaps or nearly does
// (centres within 1.3 box widths). Reported: ns per pair and rays per second, with the share of
// pairs that made contact (or rays that hit) in each engine as a sanity check.
#include <BulletCollision/CollisionDispatch/btBoxBoxDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <btBulletCollisionCommon.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "inertia/collision/contact.h"
#include "inertia/collision/queries.h"
#include "inertia/geometry/geometry.h"

using namespace inertia;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kPairs = 4096;
constexpr double kMinSeconds = 0.5;  // per measurement

btVector3 bt(const Vec3& v) { return {btScalar(v.x()), btScalar(v.y()), btScalar(v.z())}; }
btTransform bt(const Transform& t) {
  return btTransform(
      btQuaternion(btScalar(t.q.x()), btScalar(t.q.y()), btScalar(t.q.z()), btScalar(t.q.w())),
      bt(t.p));
}

Quat randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Quat(Real(g(rng)), Real(g(rng)), Real(g(rng)), Real(g(rng))).normalized();
}

// Pose pairs: A at the origin, B within 1.3 m (unit shapes: most overlap or nearly touch).
std::vector<std::pair<Transform, Transform>> posePairs(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<std::pair<Transform, Transform>> out;
  while (out.size() < std::size_t(kPairs)) {
    const Vec3 d(Real(u(rng)), Real(u(rng)), Real(u(rng)));
    if (d.norm() > 1) continue;
    out.push_back({{Vec3::Zero(), randomRotation(rng)}, {Real(1.3) * d, randomRotation(rng)}});
  }
  return out;
}

// Runs `pass` (one sweep over all items, returning how many gave a result) until kMinSeconds
// have passed; returns seconds per item and the result count of one sweep.
template <class Pass>
std::pair<double, int> timePasses(int items, Pass pass) {
  int found = pass();  // warm-up
  int sweeps = 0;
  const auto t0 = Clock::now();
  double elapsed = 0;
  do {
    found = pass();
    ++sweeps;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  } while (elapsed < kMinSeconds);
  return {elapsed / (double(sweeps) * items), found};
}

void row(const char* what, const char* engine, double secondsPerItem, int found, int items,
         const char* unit) {
  if (unit[0] == 'n')
    std::printf("| %s | %s | %.0f ns | %.1f%% |\n", what, engine, 1e9 * secondsPerItem,
                100.0 * found / items);
  else
    std::printf("| %s | %s | %.2f M rays/s | %.1f%% |\n", what, engine, 1e-6 / secondsPerItem,
                100.0 * found / items);
  std::fflush(stdout);
}

struct CountResult : btDiscreteCollisionDetectorInterface::Result {
  int points = 0;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3&, btScalar depth) override {
    if (depth < 0) ++points;
  }
};

void boxes() {
  const auto poses = posePairs(1);
  const Collider box(Box{Vec3::Constant(Real(0.5))});
  std::vector<ContactManifold> manifolds;
  const auto inertia = timePasses(kPairs, [&] {
    int found = 0;
    for (const auto& [a, b] : poses) {
      manifolds.clear();
      collide(box, a, box, b, {}, manifolds);
      found += !manifolds.empty() && manifolds[0].pointCount > 0;
    }
    return found;
  });
  row("box-box manifold", "Inertia collide()", inertia.first, inertia.second, kPairs, "ns");

  btBoxShape btBox(btVector3(btScalar(0.5), btScalar(0.5), btScalar(0.5)));
  btBox.setMargin(0);
  const auto bullet = timePasses(kPairs, [&] {
    int found = 0;
    for (const auto& [a, b] : poses) {
      btBoxBoxDetector detector(&btBox, &btBox);
      btDiscreteCollisionDetectorInterface::ClosestPointInput input;
      input.m_transformA = bt(a);
      input.m_transformB = bt(b);
      CountResult result;
      detector.getClosestPoints(input, result, nullptr);
      found += result.points > 0;
    }
    return found;
  });
  row("box-box manifold", "Bullet btBoxBoxDetector", bullet.first, bullet.second, kPairs, "ns");
}

void hulls() {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> g;
  std::vector<Vec3> points;
  for (int i = 0; i < 24; ++i)
    points.push_back(Real(0.5) * Vec3(Real(g(rng)), Real(g(rng)), Real(g(rng))).normalized());
  const ConvexHull hull(points);
  const Collider shape{Shape(hull)};
  const auto poses = posePairs(3);
  std::vector<ContactManifold> manifolds;
  const auto inertia = timePasses(kPairs, [&] {
    int found = 0;
    for (const auto& [a, b] : poses) {
      manifolds.clear();
      collide(shape, a, shape, b, {}, manifolds);
      found += !manifolds.empty() && manifolds[0].pointCount > 0;
    }
    return found;
  });
  row("hull-hull (24 random points)", "Inertia collide() (manifold)", inertia.first, inertia.second,
      kPairs, "ns");

  btConvexHullShape btHull;
  for (const Vec3& v : hull.vertices()) btHull.addPoint(bt(v), false);
  btHull.recalcLocalAabb();
  btHull.setMargin(0);
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  const auto bullet = timePasses(kPairs, [&] {
    int found = 0;
    for (const auto& [a, b] : poses) {
      btGjkPairDetector detector(&btHull, &btHull, &simplex, &epa);
      btDiscreteCollisionDetectorInterface::ClosestPointInput input;
      input.m_transformA = bt(a);
      input.m_transformB = bt(b);
      CountResult result;
      detector.getClosestPoints(input, result, nullptr);
      found += result.points > 0;
    }
    return found;
  });
  row("hull-hull (24 random points)", "Bullet GJK+EPA (one point)", bullet.first, bullet.second,
      kPairs, "ns");
}

// The closest hit of a segment on a Bullet triangle mesh.
struct ClosestHit : btTriangleRaycastCallback {
  ClosestHit(const btVector3& from, const btVector3& to) : btTriangleRaycastCallback(from, to) {}
  bool hit = false;
  btScalar reportHit(const btVector3&, btScalar fraction, int, int) override {
    hit = true;
    return fraction;  // clips the segment: later hits must be nearer
  }
};

void rays() {
  // A 225 x 225 vertex grid over 100 x 100 m with smooth bumps: 224^2 * 2 = 100,352 triangles.
  constexpr int n = 225;
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = 100.0 * i / (n - 1) - 50, z = 100.0 * j / (n - 1) - 50;
      vertices.emplace_back(Real(x), Real(2 * std::sin(0.3 * x) * std::cos(0.2 * z)), Real(z));
    }
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const std::uint32_t a = std::uint32_t(i * n + j), b = a + 1, c = a + n, d = c + 1;
      triangles.push_back({a, b, d});
      triangles.push_back({a, d, c});
    }
  const Collider mesh{Shape(TriangleMesh(vertices, triangles))};
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-55, 55), dir(-1, 1);
  std::vector<Ray> rays;
  for (int k = 0; k < kPairs; ++k) {
    const Vec3 origin(Real(u(rng)), 10, Real(u(rng)));
    const Vec3 direction = Vec3(Real(dir(rng)), -1, Real(dir(rng))).normalized() * 30;
    rays.push_back({origin, direction, 1});
  }
  const auto inertia = timePasses(kPairs, [&] {
    int found = 0;
    for (const Ray& r : rays) found += castRay(mesh, Transform::identity(), r).has_value();
    return found;
  });
  row("ray, 100,352-triangle mesh", "Inertia castRay()", inertia.first, inertia.second, kPairs,
      "rays");

  std::vector<int> indices;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) indices.push_back(int(t[std::size_t(k)]));
  std::vector<btScalar> coords;
  for (const Vec3& v : vertices)
    for (int k = 0; k < 3; ++k) coords.push_back(btScalar(v[k]));
  btTriangleIndexVertexArray array(int(triangles.size()), indices.data(), 3 * int(sizeof(int)),
                                   int(vertices.size()), coords.data(), 3 * int(sizeof(btScalar)));
  btBvhTriangleMeshShape btMesh(&array, true);
  const auto bullet = timePasses(kPairs, [&] {
    int found = 0;
    for (const Ray& r : rays) {
      const btVector3 from = bt(r.origin), to = bt(r.origin + r.direction);
      ClosestHit hit(from, to);
      btMesh.performRaycast(&hit, from, to);
      found += hit.hit;
    }
    return found;
  });
  row("ray, 100,352-triangle mesh", "Bullet btBvhTriangleMeshShape", bullet.first, bullet.second,
      kPairs, "rays");
}

}  // namespace

int main() {
  std::printf(
      "narrow phase and ray casts: %d random cases each, 1 thread, Real = %s, btScalar = %s\n\n",
      kPairs, sizeof(Real) == 4 ? "float" : "double", sizeof(btScalar) == 4 ? "float" : "double");
  std::printf("| query | engine | per case | in contact / hit |\n|---|---|---|---|\n");
  boxes();
  hulls();
  rays();
  std::printf(
      "\nPublished anchor: about 100 ns per box-box manifold for a SAT with clipping (Box2D v3). "
      "Bullet's hull-hull row is one GJK/EPA closest point per call, not a manifold.\n");
  return 0;
}
