// Tearing: a spring breaks in the first step its strain exceeds the limit, is reported once,
// and then pulls no more.
#include <gtest/gtest.h>

#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

TEST(DeformableTearing, SpringBreaksAtItsStrainLimitAndIsReportedOnce) {
  const Real limit = Real(0.5), rest = 1;
  MassSpringModel m;
  m.positions = {Vec3::Zero(), Vec3(rest, 0, 0)};
  m.velocities = {Vec3::Zero(), Vec3(3, 0, 0)};
  m.masses = {1, 1};
  m.springs = {{0, 1, rest, Real(2), 0, SpringKind::Stretch}};  // soft: it keeps going
  m.pinned = {0};
  for (ode::Method method : {ode::Method::SymplecticEuler, ode::Method::BackwardEuler}) {
    Deformable d({.integrator = method, .tearStrain = limit}, m);
    Real previousStrain = 0;
    int events = 0;
    for (int s = 0; s < 60; ++s) {
      d.step(Real(1) / 60);
      const Real strain = (d.position(1) - d.position(0)).norm() / rest - 1;
      if (!d.tearEvents().empty()) {
        ++events;
        ASSERT_EQ(d.tearEvents().size(), 1u);
        const TearEvent& e = d.tearEvents()[0];
        EXPECT_EQ(e.spring, 0u);
        EXPECT_EQ(e.b, 1u);
        EXPECT_FLOAT_EQ(e.strain, strain);
        EXPECT_GT(strain, limit);
        EXPECT_LE(previousStrain, limit) << "the first step past the limit";
        EXPECT_NEAR(e.time, (s + 1) * double(Real(1) / 60), 1e-12);
      }
      previousStrain = strain;
    }
    EXPECT_EQ(events, 1) << ode::methodName(method);
    EXPECT_TRUE(d.isBroken(0));
    // Broken, the spring no longer decelerates the vertex: constant velocity from then on.
    const Vec3 v = d.velocity(1);
    d.step(Real(1) / 60);
    EXPECT_EQ(d.velocity(1), v);
  }
}

// A cloth whose left half is pinned and whose right half flies off to the right tears first
// where the two meet: at the start only the springs joining a pinned vertex to a free one are
// stretched (the free half moves as one), so the first tears are theirs.
TEST(DeformableTearing, ClothTearsFirstWhereItIsPulledApart) {
  const int n = 8;
  MassSpringModel m = cloth({.size = {1, 1},
                             .resolution = {n, n},
                             .mass = Real(0.2),
                             .stiffness = {.stretch = 50, .shear = 5, .bend = 0}});
  m.velocities.assign(m.vertexCount(), Vec3::Zero());
  for (std::uint32_t i = 0; i < m.vertexCount(); ++i) {
    if (m.positions[i].x() < 0)
      m.pinned.push_back(i);
    else
      m.velocities[i] = Vec3(3, 0, 0);
  }
  // Symplectic Euler at 1/600 s (omega_max h ~ 0.5), which does not damp the pull away as
  // backward Euler does at omega h ~ 2.4.
  Deformable d({.integrator = ode::Method::SymplecticEuler, .tearStrain = Real(0.2)}, m);
  const auto across = [&d](std::size_t k) {
    return d.isPinned(d.springs()[k].a) != d.isPinned(d.springs()[k].b);
  };
  bool first = true;
  for (int s = 0; s < 300; ++s) {
    d.step(Real(1) / 600);
    if (d.tearEvents().empty() || !first) continue;
    first = false;
    for (const TearEvent& e : d.tearEvents())
      EXPECT_TRUE(across(e.spring)) << "spring " << e.spring;
  }
  EXPECT_FALSE(first) << "it tore";
}

}  // namespace
}  // namespace inertia
