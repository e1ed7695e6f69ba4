// Mass properties of the primitives against textbook formulas and an independent quadrature.
#include "inertia/geometry/mass.h"

#include <gtest/gtest.h>

#include "geometry_test_util.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

// Results are computed in double and rounded once to Real; the test's own inputs are the same
// Real values, so each entry differs from the double formula by <= 1/2 ulp of Real. 4 eps
// leaves room for the rounding of the test's own formula.
constexpr double kRel = 4 * kEps;

void expectDiagonal(const MassProperties& p, double ixx, double iyy, double izz) {
  const double scale = std::max({ixx, iyy, izz});
  EXPECT_NEAR(p.inertia(0, 0), ixx, kRel * scale);
  EXPECT_NEAR(p.inertia(1, 1), iyy, kRel * scale);
  EXPECT_NEAR(p.inertia(2, 2), izz, kRel * scale);
  // Off-diagonal products of inertia vanish by symmetry: exactly zero in the closed forms.
  EXPECT_EQ(p.inertia(0, 1), 0);
  EXPECT_EQ(p.inertia(0, 2), 0);
  EXPECT_EQ(p.inertia(1, 2), 0);
  EXPECT_EQ(p.centerOfMass, Vec3::Zero());
}

// Gauss-Legendre 3-point rule on [a, b]: exact for polynomials of degree <= 5.
template <class F>
double gauss3(F f, double a, double b) {
  const double m = (a + b) / 2, h = (b - a) / 2, x = std::sqrt(0.6);
  return h * (5 * f(m - h * x) + 8 * f(m) + 5 * f(m + h * x)) / 9;
}

}  // namespace

TEST(PrimitiveMass, SphereIsTwoFifthsMR2) {
  const double r = 0.7, rho = 1200;
  const auto p = massProperties(Sphere{Real(r)}, Real(rho));
  const double v = 4.0 / 3.0 * kPi * r * r * r, m = rho * v;
  EXPECT_NEAR(p.volume, v, kRel * v);
  EXPECT_NEAR(p.mass, m, kRel * m);
  expectDiagonal(p, 0.4 * m * r * r, 0.4 * m * r * r, 0.4 * m * r * r);
}

TEST(PrimitiveMass, BoxIsMOver12TimesSumOfSquaredSides) {
  const double a = 2 * 0.3, b = 2 * 1.1, c = 2 * 0.05, rho = 7800;
  const auto p = massProperties(Box{Vec3(Real(0.3), Real(1.1), Real(0.05))}, Real(rho));
  const double m = rho * a * b * c;
  EXPECT_NEAR(p.volume, a * b * c, kRel * a * b * c);
  EXPECT_NEAR(p.mass, m, kRel * m);
  expectDiagonal(p, m / 12 * (b * b + c * c), m / 12 * (a * a + c * c), m / 12 * (a * a + b * b));
}

TEST(PrimitiveMass, CylinderAxialAndTransverse) {
  const double r = 0.4, h = 2 * 0.9, rho = 500;
  const auto p = massProperties(Cylinder{Real(r), Real(0.9)}, Real(rho));
  const double v = kPi * r * r * h, m = rho * v;
  EXPECT_NEAR(p.volume, v, kRel * v);
  EXPECT_NEAR(p.mass, m, kRel * m);
  const double across = m / 12 * (3 * r * r + h * h);
  expectDiagonal(p, across, m * r * r / 2, across);
}

TEST(PrimitiveMass, CapsuleIsCylinderPlusShiftedHemispheres) {
  const double r = 0.3, hh = 0.5, h = 2 * hh, rho = 1000;
  const auto p = massProperties(Capsule{Real(r), Real(hh)}, Real(rho));
  // Textbook assembly: hemisphere mass mh, its centre of mass 3r/8 from its flat face,
  // I about its own centre of mass 2/5 mh r^2 - mh (3r/8)^2, shifted out to h/2 + 3r/8.
  const double mc = rho * kPi * r * r * h, mh = rho * 2.0 / 3.0 * kPi * r * r * r;
  const double hemiOwn = 0.4 * mh * r * r - mh * (3 * r / 8) * (3 * r / 8);
  const double hemiShift = mh * (hh + 3 * r / 8) * (hh + 3 * r / 8);
  const double across = mc * (3 * r * r + h * h) / 12 + 2 * (hemiOwn + hemiShift);
  const double axial = mc * r * r / 2 + 2 * 0.4 * mh * r * r;
  EXPECT_NEAR(p.mass, mc + 2 * mh, kRel * (mc + 2 * mh));
  EXPECT_NEAR(p.volume, (mc + 2 * mh) / rho, kRel * (mc + 2 * mh) / rho);
  expectDiagonal(p, across, axial, across);

  // (Dropping the 3r/8 shift, the classic bug, moves I_xx by 2-10 % here: far outside kRel.)
}

// Independent check of the capsule (and cylinder, sphere) by slicing into discs along the axis:
// a disc of radius R(y) and mass dm has I_yy = dm R^2 / 2 and I_xx = dm (R^2 / 4 + y^2). The
// integrands are polynomials of degree <= 4 in y on each piece (R^2 = r^2 - (|y| - hh)^2 on the
// caps), so 3-point Gauss-Legendre per piece is exact up to double rounding.
TEST(PrimitiveMass, CapsuleMatchesDiscSlicing) {
  for (auto [r, hh] : {std::pair{0.3, 0.5}, std::pair{1.0, 0.01}, std::pair{0.05, 2.0}}) {
    const double rho = 900;
    auto r2 = [&](double y) {
      const double s = std::abs(y) - hh;
      return s <= 0 ? r * r : r * r - s * s;
    };
    auto mass = [&](double y) { return rho * kPi * r2(y); };
    auto iyy = [&](double y) { return mass(y) * r2(y) / 2; };
    auto ixx = [&](double y) { return mass(y) * (r2(y) / 4 + y * y); };
    double m = 0, ax = 0, tr = 0;
    for (auto [a, b] : {std::pair{-hh - r, -hh}, std::pair{-hh, hh}, std::pair{hh, hh + r}}) {
      m += gauss3(mass, a, b);
      ax += gauss3(iyy, a, b);
      tr += gauss3(ixx, a, b);
    }
    const auto p = massProperties(Capsule{Real(r), Real(hh)}, Real(rho));
    EXPECT_NEAR(p.mass, m, kRel * m) << r << ' ' << hh;
    expectDiagonal(p, tr, ax, tr);
  }
}

TEST(PrimitiveMass, ShapeDispatchEqualsPerTypeFunction) {
  // The Shape dispatcher gives the same as the per-type function.
  const Shape s = Box{Vec3(1, 2, 3)};
  const auto a = massProperties(s, 10), b = massProperties(Box{Vec3(1, 2, 3)}, 10);
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.inertia, b.inertia);
}

TEST(MassUtilities, TransformedRotatesInertiaAndMovesCentre) {
  std::mt19937_64 rng(3);
  const auto p = massProperties(Box{Vec3(Real(0.2), Real(0.5), Real(1.0))}, 100);
  const Transform xf{randomVec(rng, -2, 2), randomRotation(rng)};
  const auto q = transformed(p, xf);
  const Mat3d r = xf.q.toRotationMatrix().cast<double>();
  // A handful of Real products and sums per entry: 8 eps relative to the largest entry.
  EXPECT_LE(relativeError(q.inertia.cast<double>(), r * p.inertia.cast<double>() * r.transpose()),
            8 * kEps);
  EXPECT_LE((q.centerOfMass - xf.p).norm(), 4 * kEps * xf.p.norm());
  EXPECT_EQ(q.mass, p.mass);
}

TEST(MassUtilities, ParallelAxisOfPointMass) {
  // A point mass m at d: I = m (|d|^2 E - d d^T), e.g. m (y^2 + z^2) on the x axis.
  const Mat3 i = parallelAxis(Mat3::Zero(), 2, Vec3(1, 2, 3));
  EXPECT_NEAR(i(0, 0), 2 * (4 + 9), 64 * kEps);
  EXPECT_NEAR(i(0, 1), -2 * 2, 64 * kEps);
  EXPECT_NEAR(i(1, 2), -2 * 6, 64 * kEps);
}

TEST(MassErrors, StaticShapesHaveNoMass) {
  EXPECT_THROW(massProperties(Shape(Plane{Vec3(0, 1, 0), 0}), 1000), InvalidArgument);
  EXPECT_THROW(massProperties(Shape(HeightField({{0, 1}, {1, 0}}, 1)), 1000), InvalidArgument);
  try {
    massProperties(Shape(Plane{}), 1000);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("static"), std::string::npos) << e.what();
  }
}

TEST(MassErrors, DensityMustBePositiveAndFinite) {
  for (Real d : {Real(0), Real(-1), std::numeric_limits<Real>::quiet_NaN(),
                 std::numeric_limits<Real>::infinity()}) {
    EXPECT_THROW(massProperties(Sphere{1}, d), InvalidArgument) << d;
    EXPECT_THROW(massProperties(Shape(Box{}), d), InvalidArgument) << d;
  }
  try {
    massProperties(Sphere{1}, -5);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("density"), std::string::npos) << e.what();
  }
}

TEST(MassErrors, CombineNeedsMass) {
  EXPECT_THROW(combine({}), InvalidArgument);
  const MassProperties zero;
  EXPECT_THROW(combine(std::span(&zero, 1)), InvalidArgument);
}

// Thin and slender primitives: no NaN, positive semi-definite inertia, right volume.
TEST(PrimitiveMass, NearDegenerateSizesStayFinite) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> logSize(-6, 3);
  for (int i = 0; i < 500; ++i) {
    auto s = [&] { return Real(std::pow(10.0, logSize(rng))); };
    const Real a = s(), b = s(), c = s();
    for (const Shape& shape : {Shape(Box{Vec3(a, b, c)}), Shape(Sphere{a}), Shape(Capsule{a, b}),
                               Shape(Cylinder{a, b})}) {
      const auto p = massProperties(shape, Real(1000));
      ASSERT_TRUE(std::isfinite(p.mass) && p.mass > 0) << shapeTypeName(shape.type());
      ASSERT_TRUE(p.inertia.allFinite() && p.centerOfMass.allFinite());
      ASSERT_GE(p.inertia.diagonal().minCoeff(), 0);
    }
  }
}
