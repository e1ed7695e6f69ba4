// The separating-axis queries: the closed-form box-box queries (queryBoxBox, the seeds' 15-axis
// OBB test) against the general Gauss-map queries on the same boxes' polyhedron views, and the
// box-box manifold of the fast path against the general SAT-and-clip path.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "collision/polyhedron.h"
#include "collision_test_util.h"

using namespace inertia;
using namespace inertia::test;

namespace {

struct BoxPair {
  Box a, b;
  Transform poseA, poseB;
};

// Boxes of 0.05..1 m half extents (thin plates among them), centres within 1.5 m of each other:
// about half overlap, the rest are separated by up to a metre.
BoxPair randomPair(std::mt19937_64& rng) {
  BoxPair p{Box{randomVec(rng, 0.05, 1)}, Box{randomVec(rng, 0.05, 1)}, {}, {}};
  p.poseA = {randomVec(rng, -3, 3), randomRotation(rng)};
  p.poseB = {p.poseA.p + randomVec(rng, -1.5, 1.5), randomRotation(rng)};
  return p;
}

// The queries add about ten products of unit-sized rotations and metre-sized extents and
// offsets: a few ulps of the largest term, taken as 32 ulps of 4 m.
const double kSatTol = 32 * kEps * 4;

}  // namespace

TEST(Sat, BoxBoxQueriesEqualTheGaussMapQueries) {
  std::mt19937_64 rng(41);
  int faceChecked = 0, edgeChecked = 0, edgeIndexChecked = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const BoxPair p = randomPair(rng);
    detail::PolyStorage sa, sb;
    const detail::PolyView a = detail::makePolyView(p.a, sa), b = detail::makePolyView(p.b, sb);
    const Transform bToA = p.poseA.inverse() * p.poseB, aToB = p.poseB.inverse() * p.poseA;
    const detail::BoxBoxQuery fast = detail::queryBoxBox(p.a.halfExtents, p.b.halfExtents, bToA);
    const detail::FaceQuery faceA = detail::queryFaceDirections(a, b, bToA);
    const detail::FaceQuery faceB = detail::queryFaceDirections(b, a, aToB);
    const detail::EdgeQuery edge = detail::queryEdgeDirections(a, b, bToA);

    ASSERT_NEAR(fast.faceA.separation, faceA.separation, kSatTol) << "trial " << trial;
    ASSERT_NEAR(fast.faceB.separation, faceB.separation, kSatTol) << "trial " << trial;
    // The face must be the general query's, or one as good within rounding.
    const auto faceSeparation = [](const detail::PolyView& ref, const detail::PolyView& inc,
                                   const Transform& incToRef, int f) {
      const Vec3 n = ref.faces[f].normal;
      const Vec3 dir = incToRef.q.conjugate() * (-n);
      return n.dot(incToRef.apply(inc.vertices[inc.supportIndex(dir)])) - ref.faces[f].offset;
    };
    ASSERT_NEAR(faceSeparation(a, b, bToA, fast.faceA.face), faceA.separation, kSatTol);
    ASSERT_NEAR(faceSeparation(b, a, aToB, fast.faceB.face), faceB.separation, kSatTol);
    faceChecked += 2;

    // Edges: the general query skips nothing the closed form keeps (both use the same
    // parallel-sine cut), so the largest separations agree.
    ASSERT_EQ(fast.edge.edgeA >= 0, edge.edgeA >= 0) << "trial " << trial;
    if (edge.edgeA < 0) continue;
    // Both divide by the length of eA x eB, the sine of the edges' angle: the rounding of the
    // separation grows as 1 / sine for nearly parallel edges.
    const Vec3 dA = a.edgeDirection(edge.edgeA).normalized();
    const Vec3 dB = bToA.rotate(b.edgeDirection(edge.edgeB)).normalized();
    const double sine = dA.cross(dB).norm();
    ASSERT_NEAR(fast.edge.separation, edge.separation, kSatTol / sine) << "trial " << trial;
    ++edgeChecked;
    // The axis is unit, points from A to B, and the reported edges support it: the separation
    // along it measured from the two edges equals the reported one.
    ASSERT_NEAR(fast.edge.axis.norm(), 1, 8 * kEps);
    const Vec3 pa = a.vertices[a.edges[fast.edge.edgeA].v0];
    const Vec3 pb = bToA.apply(b.vertices[b.edges[fast.edge.edgeB].v0]);
    ASSERT_NEAR(fast.edge.axis.dot(pb - pa), fast.edge.separation, kSatTol / sine)
        << "trial " << trial;
    ASSERT_LE(std::abs(fast.edge.axis.dot(a.edgeDirection(fast.edge.edgeA))),
              kSatTol * a.edgeDirection(fast.edge.edgeA).norm());
    // Away from near-ties the same edge pair as the Gauss-map pruning.
    if (edge.edgeA == fast.edge.edgeA && edge.edgeB == fast.edge.edgeB) ++edgeIndexChecked;
  }
  EXPECT_EQ(faceChecked, 40000);
  EXPECT_GT(edgeChecked, 19000);          // nearly every pair has a non-parallel edge pair
  EXPECT_GT(edgeIndexChecked, edgeChecked * 99 / 100);
}

// The early stop changes nothing but the skipped edge query: the same face queries bit for
// bit, and the same edge query whenever no face axis separates beyond the limit.
TEST(Sat, BoxBoxQueryStopsAfterSeparatingFaces) {
  std::mt19937_64 rng(43);
  const Real limit = Real(0.02);
  int stopped = 0, full = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const BoxPair p = randomPair(rng);
    const Transform bToA = p.poseA.inverse() * p.poseB;
    const detail::BoxBoxQuery all = detail::queryBoxBox(p.a.halfExtents, p.b.halfExtents, bToA);
    const detail::BoxBoxQuery q =
        detail::queryBoxBox(p.a.halfExtents, p.b.halfExtents, bToA, limit);
    ASSERT_EQ(q.faceA.separation, all.faceA.separation) << "trial " << trial;
    ASSERT_EQ(q.faceA.face, all.faceA.face);
    ASSERT_EQ(q.faceB.separation, all.faceB.separation);
    ASSERT_EQ(q.faceB.face, all.faceB.face);
    if (std::max(all.faceA.separation, all.faceB.separation) > limit) {
      ASSERT_LT(q.edge.edgeA, 0) << "trial " << trial;
      ++stopped;
    } else {
      ASSERT_EQ(q.edge.separation, all.edge.separation) << "trial " << trial;
      ASSERT_EQ(q.edge.edgeA, all.edge.edgeA);
      ASSERT_EQ(q.edge.edgeB, all.edge.edgeB);
      ++full;
    }
  }
  // randomPair makes both kinds often.
  EXPECT_GT(stopped, 1000);
  EXPECT_GT(full, 1000);
}

TEST(Sat, BoxBoxFastPathGivesTheGeneralManifold) {
  std::mt19937_64 rng(42);
  const ContactSettings settings{.speculativeDistance = Real(0.02)};
  int touching = 0, compared = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const BoxPair p = randomPair(rng);
    detail::PolyStorage sa, sb;
    const detail::PolyView a = detail::makePolyView(p.a, sa), b = detail::makePolyView(p.b, sb);
    ContactManifold fast{}, general{};
    const bool hitFast = detail::collideBoxes(p.a, p.poseA, p.b, p.poseB, settings, fast);
    const bool hitGeneral = detail::collidePolyhedra(a, p.poseA, b, p.poseB, settings, general);
    // Both paths reject on the same three separations (equal within kSatTol): a different answer
    // is allowed only when one of them sits within kSatTol of the speculative distance.
    if (hitFast != hitGeneral) {
      const Transform bToA = p.poseA.inverse() * p.poseB;
      const detail::BoxBoxQuery q = detail::queryBoxBox(p.a.halfExtents, p.b.halfExtents, bToA);
      const double worst = std::max({q.faceA.separation, q.faceB.separation, q.edge.separation});
      ASSERT_NEAR(worst, settings.speculativeDistance, kSatTol) << "trial " << trial;
      continue;
    }
    if (!hitFast) continue;
    ++touching;
    // Near-ties between axes may pick different (equally valid) features; compare the rest.
    if ((fast.normal - general.normal).norm() > 1e-3 || fast.pointCount != general.pointCount)
      continue;
    ++compared;
    for (int k = 0; k < fast.pointCount; ++k) {
      const ContactPoint& f = fast.points[std::size_t(k)];
      const ContactPoint& g = general.points[std::size_t(k)];
      ASSERT_EQ(f.id, g.id) << "trial " << trial << " point " << k;
      ASSERT_LE((f.pointA - g.pointA).norm(), 8 * kSatTol) << "trial " << trial;
      ASSERT_LE((f.pointB - g.pointB).norm(), 8 * kSatTol) << "trial " << trial;
      ASSERT_NEAR(f.separation, g.separation, 8 * kSatTol) << "trial " << trial;
    }
  }
  EXPECT_GT(touching, 5000);
  EXPECT_GT(compared, touching * 99 / 100);
}
