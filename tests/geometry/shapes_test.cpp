// The Shape value: type tags, access, validation of every primitive, height fields.
#include "inertia/geometry/shapes.h"

#include <gtest/gtest.h>

#include "geometry_test_util.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

template <class Fn>
void expectInvalid(Fn&& fn, const std::string& word) {
  try {
    fn();
    ADD_FAILURE() << "no exception; expected one mentioning " << word;
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr Real kInf = std::numeric_limits<Real>::infinity();

}  // namespace

TEST(Shape, TypeTagsAndAccess) {
  const Shape shapes[] = {
      Plane{},
      Sphere{1},
      Capsule{1, 2},
      Box{Vec3(1, 2, 3)},
      Cylinder{1, 2},
      ConvexHull(std::vector<Vec3>{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}),
      TriangleMesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}}),
      HeightField({{0, 0}, {0, 0}}, 1),
      Compound({{Sphere{1}, {}}})};
  for (int i = 0; i < kShapeTypeCount; ++i) EXPECT_EQ(int(shapes[i].type()), i);
  EXPECT_STREQ(shapeTypeName(shapes[5].type()), "hull");
  EXPECT_EQ(shapes[3].get<Box>().halfExtents, Vec3(1, 2, 3));
  EXPECT_EQ(shapes[5].get<ConvexHull>().vertices().size(), 4u);
  EXPECT_EQ(shapes[1].getIf<Box>(), nullptr);
  EXPECT_EQ(shapes[1].getIf<ConvexHull>(), nullptr);
  EXPECT_THROW(shapes[1].get<Box>(), InvalidArgument);
  EXPECT_TRUE(isConvex(shapes[4].type()));
  EXPECT_FALSE(isConvex(shapes[6].type()));
  // Copies share the immutable hull data.
  const Shape copy = shapes[5];
  EXPECT_EQ(&copy.get<ConvexHull>(), &shapes[5].get<ConvexHull>());
  // visit hands over the concrete type.
  EXPECT_EQ(shapes[2].visit([](const auto& s) { return sizeof(s) > 0 ? 7 : 0; }), 7);
}

TEST(Shape, PlaneNormalIsNormalisedKeepingTheHalfSpace) {
  const Shape s = Plane{Vec3(0, 2, 0), 3};  // 2y <= 3, i.e. y <= 1.5
  EXPECT_NEAR(s.get<Plane>().normal.y(), 1, 0);
  EXPECT_NEAR(s.get<Plane>().offset, 1.5, 2 * kEps);
}

TEST(ShapeErrors, InvalidPrimitivesNameWhatIsWrong) {
  for (Real bad : {Real(0), Real(-1), kNaN, kInf}) {
    expectInvalid([&] { Shape s = Sphere{bad}; }, "Sphere radius");
    expectInvalid([&] { Shape s = Capsule{bad, 1}; }, "Capsule radius");
    expectInvalid([&] { Shape s = Capsule{1, bad}; }, "Capsule halfHeight");
    expectInvalid([&] { Shape s = Cylinder{bad, 1}; }, "Cylinder radius");
    expectInvalid([&] { Shape s = Cylinder{1, bad}; }, "Cylinder halfHeight");
    expectInvalid([&] { Shape s = Box{Vec3(bad, 1, 1)}; }, "Box halfExtents.x");
    expectInvalid([&] { Shape s = Box{Vec3(1, bad, 1)}; }, "Box halfExtents.y");
    expectInvalid([&] { Shape s = Box{Vec3(1, 1, bad)}; }, "Box halfExtents.z");
    // The per-type mass functions validate too.
    expectInvalid([&] { massProperties(Sphere{bad}, 1); }, "Sphere radius");
  }
  expectInvalid([] { Shape s = Plane{Vec3::Zero(), 0}; }, "zero-length");
  expectInvalid([] { Shape s = Plane{Vec3(0, kNaN, 0), 0}; }, "normal must be finite");
  expectInvalid([] { Shape s = Plane{Vec3(0, 1, 0), kInf}; }, "offset");
  expectInvalid([] { Shape s(std::shared_ptr<const ConvexHull>{}); }, "null");
}

TEST(HeightField, LayoutAndTriangles) {
  const HeightField field({{0, 1, 2}, {3, 4, 5}}, Real(0.5));
  EXPECT_EQ(field.rows(), 2u);
  EXPECT_EQ(field.cols(), 3u);
  // Row i at z = i * spacing, column j at x = j * spacing, y up.
  EXPECT_EQ(field.point(1, 2), Vec3(1, 5, Real(0.5)));
  EXPECT_EQ(field.minHeight(), 0);
  EXPECT_EQ(field.maxHeight(), 5);
  for (std::size_t j = 0; j < 2; ++j)
    for (const auto& tri : field.cellTriangles(0, j)) {
      const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
      EXPECT_GT(n.y(), 0);  // counter-clockwise seen from above
    }
  const Aabb b = localBounds(Shape(field));
  EXPECT_EQ(b.lower, Vec3(0, 0, 0));
  EXPECT_EQ(b.upper, Vec3(1, 5, Real(0.5)));
}

TEST(HeightFieldErrors, InvalidFieldsAreRejected) {
  expectInvalid([] { HeightField f({{0, 0}}, 1); }, "2 rows");
  expectInvalid([] { HeightField f({{0}, {0}}, 1); }, "2 heights");
  expectInvalid([] { HeightField f({{0, 0}, {0}}, 1); }, "row 1");
  expectInvalid([] { HeightField f({{0, 0}, {0, kNaN}}, 1); }, "not finite");
  expectInvalid([] { HeightField f({{0, 0}, {0, 0}}, 0); }, "spacing");
  expectInvalid([] { HeightField f({{0, 0}, {0, 0}}, kInf); }, "spacing");
}
