// Convex hulls: topology from Qhull, and mass properties against boxes, spheres and Monte Carlo.
#include "inertia/geometry/hull.h"

#include <gtest/gtest.h>

#include <array>

#include "geometry_test_util.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

std::vector<Vec3> boxCorners(const Vec3& h, const Transform& xf = {}) {
  std::vector<Vec3> out;
  for (int i = 0; i < 8; ++i)
    out.push_back(
        xf.apply(Vec3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z())));
  return out;
}

std::vector<Vec3> randomCloud(std::mt19937_64& rng, int n, const Vec3& scale) {
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) out.push_back(randomVec(rng, -1, 1).cwiseProduct(scale));
  return out;
}

// Every structural invariant the SAT and clipping code will rely on. `tol` (m) bounds how far a
// vertex may sit above a face plane: rounding of the Real vertices and of Qhull's merge.
void expectWellFormed(const ConvexHull& hull, std::span<const Vec3> input, double tol) {
  const auto& v = hull.vertices();
  const auto& f = hull.faces();
  const auto& he = hull.halfEdges();
  const auto& e = hull.edges();
  // Euler's formula for a convex polyhedron (genus 0).
  EXPECT_EQ(long(v.size()) - long(e.size()) + long(f.size()), 2);
  EXPECT_EQ(he.size(), 2 * e.size());
  for (std::size_t i = 0; i < he.size(); ++i) {
    const HullHalfEdge& h = he[i];
    // Twins pair up, lie on different faces and run opposite ways.
    EXPECT_EQ(he[h.twin].twin, i);
    EXPECT_NE(he[h.twin].face, h.face);
    EXPECT_EQ(he[h.twin].origin, he[h.next].origin);
    EXPECT_EQ(he[h.twin].edge, h.edge);
    const HullEdge& edge = e[h.edge];
    EXPECT_TRUE((edge.face0 == h.face && edge.face1 == he[h.twin].face) ||
                (edge.face1 == h.face && edge.face0 == he[h.twin].face));
  }
  for (std::size_t fi = 0; fi < f.size(); ++fi) {
    const HullFace& face = f[fi];
    EXPECT_NEAR(face.normal.norm(), 1, 8 * kEps);
    EXPECT_GE(face.edgeCount, 3u);
    const Vec3d n = face.normal.cast<double>();
    const auto loop = hull.faceEdges(fi);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      EXPECT_EQ(loop[k].face, fi);
      EXPECT_EQ(loop[k].next, face.firstEdge + (k + 1) % loop.size());
      // Counter-clockwise about the outward normal: each corner turns left (or goes straight
      // for a vertex on a straight stretch of the boundary).
      const Vec3d a = v[loop[k].origin].cast<double>();
      const Vec3d b = v[loop[(k + 1) % loop.size()].origin].cast<double>();
      const Vec3d c = v[loop[(k + 2) % loop.size()].origin].cast<double>();
      EXPECT_GE((b - a).cross(c - b).dot(n), -tol * ((b - a).norm() + (c - b).norm()));
      // The loop's vertices lie on the face plane.
      EXPECT_NEAR(n.dot(a), face.offset, tol);
    }
    // Outward: no vertex, and no input point, above any face plane.
    for (const Vec3& x : v) EXPECT_LE(n.dot(x.cast<double>()), face.offset + tol);
    for (const Vec3& x : input) EXPECT_LE(n.dot(x.cast<double>()), face.offset + tol);
  }
  // Vertex adjacency lists exactly the edges touching each vertex.
  std::size_t total = 0;
  for (std::size_t vi = 0; vi < v.size(); ++vi) {
    EXPECT_GE(hull.vertexEdges(vi).size(), 3u);
    for (std::uint32_t ei : hull.vertexEdges(vi)) EXPECT_TRUE(e[ei].v0 == vi || e[ei].v1 == vi);
    total += hull.vertexEdges(vi).size();
  }
  EXPECT_EQ(total, 2 * e.size());
}

double extentOf(std::span<const Vec3> pts) {
  Aabb b;
  for (const Vec3& p : pts) b.extend(p);
  return (b.upper - b.lower).norm();
}

}  // namespace

TEST(HullStructure, CubeHasSixQuadrilateralFaces) {
  const auto pts = boxCorners(Vec3(1, 2, 3));
  const ConvexHull hull(pts);
  EXPECT_EQ(hull.vertices().size(), 8u);
  EXPECT_EQ(hull.faces().size(), 6u);
  EXPECT_EQ(hull.edges().size(), 12u);
  for (const HullFace& f : hull.faces()) EXPECT_EQ(f.edgeCount, 4u);
  expectWellFormed(hull, pts, 8 * kEps * extentOf(pts));
}

TEST(HullStructure, CoplanarGridPointsMergeIntoCubeFaces) {
  // 5x5x5 grid: 98 points on the surface, most of them coplanar with a face, edge or corner.
  std::vector<Vec3> pts;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) pts.emplace_back(Real(i) / 4, Real(j) / 4, Real(k) / 4);
  const ConvexHull hull(pts);
  EXPECT_EQ(hull.vertices().size(), 8u);
  EXPECT_EQ(hull.faces().size(), 6u);
  expectWellFormed(hull, pts, 8 * kEps * extentOf(pts));
}

TEST(HullStructure, RotatedCubeInRealPrecisionStillHasSixFaces) {
  // The corners of a rotated box carry Real rounding (~eps |x|), so its faces are coplanar only
  // up to that; the merge tolerance must absorb it.
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const Transform xf{randomVec(rng, -10, 10), randomRotation(rng)};
    const auto pts = boxCorners(randomVec(rng, 0.1, 2), xf);
    const ConvexHull hull(pts);
    ASSERT_EQ(hull.faces().size(), 6u) << trial;
    ASSERT_EQ(hull.vertices().size(), 8u) << trial;
    expectWellFormed(hull, pts, 64 * kEps * (extentOf(pts) + xf.p.norm()));
  }
}

TEST(HullStructure, RandomCloudsAreWellFormed) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const auto pts = randomCloud(rng, 10 + 10 * trial, randomVec(rng, 0.2, 3));
    const ConvexHull hull(pts);
    expectWellFormed(hull, pts, 64 * kEps * extentOf(pts));
  }
}

TEST(HullStructure, TetrahedronAndDuplicatesOfItsCorners) {
  std::vector<Vec3> pts{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  for (int i = 0; i < 3; ++i) pts.insert(pts.end(), pts.begin(), pts.begin() + 4);
  const ConvexHull hull(pts);
  EXPECT_EQ(hull.vertices().size(), 4u);
  EXPECT_EQ(hull.faces().size(), 4u);
  expectWellFormed(hull, pts, 8 * kEps);
  // Volume 1/6, centroid at the corners' mean (Real rounding of a double result).
  const auto p = massProperties(hull, 1);
  EXPECT_NEAR(p.volume, 1.0 / 6, 4 * kEps);
  EXPECT_LE((p.centerOfMass - Vec3::Constant(Real(0.25))).norm(), 4 * kEps);
}

TEST(HullMass, BoxCornersGiveTheBox) {
  const Vec3 h(Real(0.5), Real(1.5), Real(0.25));
  const auto pts = boxCorners(h, Transform{Vec3(1, -2, 3), Quat::Identity()});
  const auto hull = massProperties(ConvexHull(pts), 800);
  const auto box = massProperties(Box{h}, 800);
  // Tetrahedron sums in double around an interior point: only the final rounding to Real and
  // the corners' own rounding after the shift (|x| ~ 4): ~16 eps relative.
  EXPECT_NEAR(hull.volume, box.volume, 16 * kEps * box.volume);
  EXPECT_NEAR(hull.mass, box.mass, 16 * kEps * box.mass);
  EXPECT_LE((hull.centerOfMass - Vec3(1, -2, 3)).norm(), 16 * kEps * 4);
  EXPECT_LE(relativeError(hull.inertia.cast<double>(), box.inertia.cast<double>()), 64 * kEps);
}

// The hull of points on a sphere of radius R contains the ball of radius r_in (the nearest face
// plane) and lies in the ball of radius R. Volume, and the moment u^T I_origin u about any axis
// u through the centre, are monotone under inclusion, so both are bracketed by the two balls.
TEST(HullMass, PointsOnASphereApproachTheSphere) {
  std::mt19937_64 rng(9);
  const double R = 1.5, rho = 1000;
  double previousError = 1;
  for (int n : {100, 1000, 10000}) {
    std::vector<Vec3> pts;
    for (int i = 0; i < n; ++i) pts.push_back((R * randomUnit(rng)).cast<Real>());
    const ConvexHull hull(pts);
    double rIn = R;
    for (const HullFace& f : hull.faces()) rIn = std::min(rIn, double(f.offset));
    const auto p = massProperties(hull, Real(rho));
    // Slack for Real rounding of the points (eps R) and of the results.
    const double slack = 16 * kEps;
    auto ballVolume = [](double r) { return 4.0 / 3.0 * kPi * r * r * r; };
    auto ballMoment = [&](double r) { return rho * 8.0 / 15.0 * kPi * std::pow(r, 5); };
    EXPECT_GE(p.volume, ballVolume(rIn) * (1 - slack));
    EXPECT_LE(p.volume, ballVolume(R) * (1 + slack));
    const Mat3d io = inertiaAboutOrigin(p);
    for (int k = 0; k < 10; ++k) {
      const Vec3d u = randomUnit(rng);
      EXPECT_GE(u.dot(io * u), ballMoment(rIn) * (1 - slack));
      EXPECT_LE(u.dot(io * u), ballMoment(R) * (1 + slack));
    }
    // |m c| = |first moment of hull minus ball(r_in)| <= rho (V(R) - V(r_in)) R.
    EXPECT_LE(p.mass * p.centerOfMass.norm(),
              rho * (ballVolume(R) - ballVolume(rIn)) * R * (1 + slack) + slack * p.mass * R);
    const double error = 1 - p.volume / ballVolume(R);
    EXPECT_LT(error, previousError);  // converges as points are added
    previousError = error;
    std::printf("  n = %5d: r_in/R = %.5f, volume error %.2e\n", n, rIn / R, error);
  }
}

// Monte Carlo on the hull's bounding box with N samples; each integral's standard error is
// estimated from the samples, and 5 sigma (plus Real rounding) bounds the difference: a
// deterministic seed, and a false failure chance < 1e-6 per quantity if it were reseeded.
TEST(HullMass, RandomHullMatchesMonteCarloAndTransformsRigidly) {
  std::mt19937_64 rng(13);
  const auto pts = randomCloud(rng, 40, Vec3(1, Real(0.7), Real(1.3)));
  const ConvexHull hull(pts);
  const auto p = massProperties(hull, 1);
  // Plain doubles: this runs ~10^7 times, and unoptimised Eigen (sanitizer builds) is slow.
  std::vector<std::array<double, 4>> planes;
  for (const HullFace& f : hull.faces())
    planes.push_back({f.normal.x(), f.normal.y(), f.normal.z(), f.offset});
  auto inside = [&](const Vec3d& x) {
    const double px = x.x(), py = x.y(), pz = x.z();
    for (const auto& p : planes)
      if (p[0] * px + p[1] * py + p[2] * pz > p[3]) return false;
    return true;
  };
  const Aabb b = hull.bounds();
  const int n = 400000;
  const MonteCarlo mc = monteCarlo(inside, b.lower.cast<double>(), b.upper.cast<double>(), n, 1);
  const double round = 16 * kEps;
  EXPECT_NEAR(p.volume, mc.volume, 5 * mc.volumeSigma + round * mc.volume);
  const Vec3d first = double(p.mass) * p.centerOfMass.cast<double>();
  const Mat3d io = inertiaAboutOrigin(p);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(first[i], mc.first[i], 5 * mc.firstSigma[i] + round * mc.volume);
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(io(i, j), mc.inertia(i, j), 5 * mc.inertiaSigma(i, j) + round * io.norm());
  }
  std::printf("  volume %.5f vs Monte Carlo %.5f +- %.5f\n", double(p.volume), mc.volume,
              mc.volumeSigma);

  // Rotated and translated copy: centre R c + t, inertia R I R^T. The moved points carry
  // rounding ~ 2 eps |x| (|x| <= 6), which moves the volume by ~ area * that, a relative
  // ~ 10 * 2 eps * 6 / size: 256 eps covers it.
  const Transform xf{Vec3(3, -4, 5), randomRotation(rng)};
  std::vector<Vec3> moved;
  for (const Vec3& x : pts) moved.push_back(xf.apply(x));
  const auto q = massProperties(ConvexHull(moved), 1);
  const Mat3d r = xf.q.toRotationMatrix().cast<double>();
  EXPECT_NEAR(q.volume, p.volume, 256 * kEps * p.volume);
  EXPECT_LE((q.centerOfMass - xf.apply(p.centerOfMass)).norm(), 256 * kEps * 7);
  EXPECT_LE(relativeError(q.inertia.cast<double>(), r * p.inertia.cast<double>() * r.transpose()),
            256 * kEps);
}

TEST(HullErrors, InvalidCloudsAreRejected) {
  auto expectThrowMentioning = [](std::vector<Vec3> pts, const std::string& word) {
    try {
      ConvexHull hull(pts);
      ADD_FAILURE() << "no exception; expected one mentioning " << word;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  expectThrowMentioning({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, "at least 4");
  expectThrowMentioning({}, "at least 4");
  expectThrowMentioning(std::vector<Vec3>(10, Vec3(1, 2, 3)), "coincide");
  expectThrowMentioning({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3)}, "collinear");
  expectThrowMentioning(
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(Real(0.3), Real(0.2), 0)},
      "coplanar");
  expectThrowMentioning({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                         Vec3(0, 0, std::numeric_limits<Real>::quiet_NaN())},
                        "not finite");
  expectThrowMentioning({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                         Vec3(0, 0, std::numeric_limits<Real>::infinity())},
                        "not finite");
  // Many random points on a plane (a tilted one, so the points carry rounding off it).
  std::mt19937_64 rng(17);
  const Quat tilt = randomRotation(rng);
  std::vector<Vec3> flat;
  for (int i = 0; i < 100; ++i) {
    Vec3 x = randomVec(rng, -1, 1);
    x.z() = 0;
    flat.push_back(tilt * x);
  }
  expectThrowMentioning(flat, "coplanar");
}

// Nearly coplanar clouds, thickness from 1e-7 to 1e-2 of their size: each is either rejected
// as coplanar (InvalidArgument) or gives a well-formed hull with finite, positive mass.
TEST(HullErrors, NearDegenerateCloudsNeverGiveNaN) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> logThickness(-7, -2);
  int built = 0, rejected = 0;
  double thickestRejected = 0, thinnestBuilt = 1;
  for (int trial = 0; trial < 200; ++trial) {
    const double t = std::pow(10.0, logThickness(rng));
    const Transform xf{randomVec(rng, -5, 5), randomRotation(rng)};
    std::vector<Vec3> pts;
    const int n = 4 + trial % 30;
    for (int i = 0; i < n; ++i) {
      Vec3 x = randomVec(rng, -1, 1);
      x.z() *= Real(t);
      pts.push_back(xf.apply(x));
    }
    try {
      const ConvexHull hull(pts);
      ++built;
      thinnestBuilt = std::min(thinnestBuilt, t);
      const auto p = massProperties(hull, 1000);
      ASSERT_TRUE(std::isfinite(p.mass) && p.mass > 0) << t;
      ASSERT_TRUE(p.centerOfMass.allFinite() && p.inertia.allFinite()) << t;
      ASSERT_EQ(
          long(hull.vertices().size()) - long(hull.edges().size()) + long(hull.faces().size()), 2);
      for (const HullFace& f : hull.faces()) ASSERT_TRUE(f.normal.allFinite());
    } catch (const InvalidArgument& e) {
      ++rejected;
      thickestRejected = std::max(thickestRejected, t);
      // Only thin clouds may be rejected as coplanar. The test measures the extreme-point
      // simplex, whose height for a few points in a slab of thickness t can be a small
      // fraction of t (4 points are nearly coplanar by chance), and the moved points carry
      // rounding ~ 8 eps: rejecting anything thicker than 100 times the threshold is a bug.
      EXPECT_LT(t, 100 * (ConvexHull::kMinThickness + 8 * kEps)) << e.what();
    }
  }
  std::printf("  built %d (thinnest %.2e), rejected %d (thickest %.2e)\n", built, thinnestBuilt,
              rejected, thickestRejected);
  EXPECT_GT(built, 100);
}
