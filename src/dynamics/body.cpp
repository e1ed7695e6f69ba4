#include "inertia/dynamics/body.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "inertia/core/error.h"
#include "inertia/core/math.h"

namespace inertia {

namespace {
struct TypeEntry {
  BodyType type;
  std::string_view name;
};
constexpr std::array<TypeEntry, 3> kTypes{{{BodyType::Static, "static"},
                                           {BodyType::Kinematic, "kinematic"},
                                           {BodyType::Dynamic, "dynamic"}}};

bool finiteNonNegative(Real x) { return std::isfinite(x) && x >= 0; }
}  // namespace

std::string_view bodyTypeName(BodyType type) {
  for (const auto& t : kTypes)
    if (t.type == type) return t.name;
  return "unknown";
}

bool bodyTypeFromName(std::string_view name, BodyType& out) {
  for (const auto& t : kTypes)
    if (t.name == name) {
      out = t.type;
      return true;
    }
  return false;
}

void validate(const Material& m) {
  require(std::isfinite(m.density) && m.density > 0, "Material::density must be finite and > 0 (kg/m^3)");
  require(finiteNonNegative(m.friction), "Material::friction must be finite and >= 0");
  require(std::isfinite(m.dynamicFriction), "Material::dynamicFriction must be finite");
  require(std::isfinite(m.restitution) && m.restitution >= 0 && m.restitution <= 1,
          "Material::restitution must be in [0, 1]");
  require(finiteNonNegative(m.rollingFriction), "Material::rollingFriction must be finite and >= 0 (m)");
  require(finiteNonNegative(m.spinningFriction),
          "Material::spinningFriction must be finite and >= 0 (m)");
}

bool simulableMassProperty(Real x) { return x >= kMinMassProperty && x <= kMaxMassProperty; }

std::string massPropertyRange() {
  char text[64];
  std::snprintf(text, sizeof(text), "[%.3g, %.3g]", double(kMinMassProperty),
                double(kMaxMassProperty));
  return text;
}

Real combine(CombineRule rule, Real a, Real b) {
  switch (rule) {
    case CombineRule::Average: return Real(0.5) * (a + b);
    case CombineRule::GeometricMean: return std::sqrt(a * b);
    case CombineRule::Minimum: return a < b ? a : b;
    case CombineRule::Maximum: return a > b ? a : b;
    case CombineRule::Multiply: return a * b;
  }
  return a;
}

void validate(const BodySettings& s) {
  require(allFinite(s.position), "BodySettings::position must be finite");
  const Real qn = s.orientation.norm();
  require(allFinite(s.orientation) && qn > Real(1e-6),
          "BodySettings::orientation must be a finite, non-zero quaternion");
  require(allFinite(s.linearVelocity), "BodySettings::linearVelocity must be finite");
  require(allFinite(s.angularVelocity), "BodySettings::angularVelocity must be finite");
  require(finiteNonNegative(s.linearDamping), "BodySettings::linearDamping must be finite and >= 0 (1/s)");
  require(finiteNonNegative(s.angularDamping), "BodySettings::angularDamping must be finite and >= 0 (1/s)");
  require(std::isfinite(s.gravityScale), "BodySettings::gravityScale must be finite");
  require(std::isfinite(s.maxLinearSpeed) && s.maxLinearSpeed > 0,
          "BodySettings::maxLinearSpeed must be finite and > 0 (m/s)");
  require(std::isfinite(s.maxAngularSpeed) && s.maxAngularSpeed > 0,
          "BodySettings::maxAngularSpeed must be finite and > 0 (rad/s)");
  require(finiteNonNegative(s.mass), "BodySettings::mass must be finite and >= 0 (kg; 0 = from shapes)");
  require(allFinite(s.inertia) && (s.inertia.array() >= 0).all(),
          "BodySettings::inertia must be finite and >= 0 (kg m^2)");
  // The messages are made only for the error: formatting the range's floats cost every body
  // created a few microseconds.
  if (s.mass != 0 && !simulableMassProperty(s.mass))
    throw InvalidArgument("BodySettings::mass is outside what Real can simulate, " +
                          massPropertyRange() + " kg");
  if (!s.inertia.isZero() &&
      !(simulableMassProperty(s.inertia.x()) && simulableMassProperty(s.inertia.y()) &&
        simulableMassProperty(s.inertia.z())))
    throw InvalidArgument("BodySettings::inertia is outside what Real can simulate, " +
                          massPropertyRange() + " kg m^2");
  require(s.inertia.isZero() || (s.mass > 0 && (s.inertia.array() > 0).all()),
          "BodySettings::inertia needs a mass and three positive principal moments");
  // Principal moments of a real body obey the triangle inequality (I1 <= I2 + I3, ...).
  if (!s.inertia.isZero()) {
    const Vec3& I = s.inertia;
    const Real tol = Real(1e-4) * I.sum();
    require(I.x() <= I.y() + I.z() + tol && I.y() <= I.x() + I.z() + tol &&
                I.z() <= I.x() + I.y() + tol,
            "BodySettings::inertia violates the triangle inequality of principal moments");
  }
}

}  // namespace inertia
