// Materials, combine rules and body settings checks.
#include "inertia/dynamics/body.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "inertia/core/error.h"

using namespace inertia;

TEST(Body, CombineRules) {
  EXPECT_FLOAT_EQ(combine(CombineRule::Average, Real(0.2), Real(0.8)), Real(0.5));
  EXPECT_FLOAT_EQ(combine(CombineRule::GeometricMean, Real(0.2), Real(0.8)), Real(0.4));
  EXPECT_FLOAT_EQ(combine(CombineRule::Minimum, Real(0.2), Real(0.8)), Real(0.2));
  EXPECT_FLOAT_EQ(combine(CombineRule::Maximum, Real(0.2), Real(0.8)), Real(0.8));
  EXPECT_FLOAT_EQ(combine(CombineRule::Multiply, Real(0.2), Real(0.8)), Real(0.16));
  EXPECT_FLOAT_EQ((Material{.friction = Real(0.7)}).sliding(), Real(0.7));
  EXPECT_FLOAT_EQ((Material{.friction = Real(0.7), .dynamicFriction = Real(0.5)}).sliding(), Real(0.5));
}

TEST(Body, TypeNamesRoundTrip) {
  for (BodyType t : {BodyType::Static, BodyType::Kinematic, BodyType::Dynamic}) {
    BodyType back{};
    ASSERT_TRUE(bodyTypeFromName(bodyTypeName(t), back));
    EXPECT_EQ(back, t);
  }
  BodyType unused{};
  EXPECT_FALSE(bodyTypeFromName("rigid", unused));
}

TEST(Body, InvalidMaterialsAndSettingsAreNamed) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([] { validate(Material{.density = 0}); }).find("density"), std::string::npos);
  EXPECT_NE(message([] { validate(Material{.restitution = Real(1.5)}); }).find("restitution"), std::string::npos);
  EXPECT_NE(message([&] { validate(Material{.friction = nan}); }).find("friction"), std::string::npos);
  EXPECT_NE(message([] { validate(BodySettings{.linearDamping = -1}); }).find("linearDamping"), std::string::npos);
  EXPECT_NE(message([] { validate(BodySettings{.orientation = Quat(0, 0, 0, 0)}); }).find("orientation"),
            std::string::npos);
  // Principal moments must satisfy the triangle inequality of a real body.
  EXPECT_NE(message([] { validate(BodySettings{.mass = 1, .inertia = Vec3(1, 1, 3)}); }).find("triangle"),
            std::string::npos);
  EXPECT_NO_THROW(validate(BodySettings{.mass = 1, .inertia = Vec3(1, 1, 2)}));
}
