// Energy: symplectic Euler's bounded error on an undamped linear system, and the implicit
// step's stability where the explicit ones blow up.
#include <gtest/gtest.h>

#include <cmath>

#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

// A free chain along x, stretched unevenly and released from rest, moves along x only, where
// its springs (neighbour and skip-one, all along the line) are exactly linear: M x'' = -K x.
// Symplectic Euler conserves H~ = E - (h/2) x^T K v exactly on it, and
// |x^T K v| <= omega_max E (Cauchy-Schwarz in the mass-weighted norm), so from rest (H~ = E0)
// E stays in [E0 / (1 + a), E0 / (1 - a)] with a = h omega_max / 2. Gershgorin bounds
// omega_max^2 by the largest row sum of |M^-1 K|: 2 (2 k_stretch + 2 k_bend) / m.
TEST(DeformableEnergy, SymplecticEulerStaysWithinItsModifiedEnergyBound) {
  const int segments = 12;
  const Real mass = 1.3f, ks = 400, kb = 50;
  MassSpringModel m = rope({.from = {0, 0, 0},
                            .to = {Real(segments) * Real(0.1), 0, 0},
                            .segments = segments,
                            .mass = mass,
                            .stiffness = {.stretch = ks, .bend = kb}});
  for (std::size_t i = 0; i < m.vertexCount(); ++i)
    m.positions[i].x() += Real(0.02) * std::sin(Real(i) * Real(1.3)) + Real(0.01) * Real(i % 3);
  Deformable d({.integrator = ode::Method::SymplecticEuler}, m);
  const double mi = double(mass) / double(m.vertexCount());
  const double omegaMax = std::sqrt(4 * (double(ks) + double(kb)) / mi);
  const double h = 0.6 / omegaMax, a = h * omegaMax / 2;
  const double e0 = d.springEnergy() + d.kineticEnergy();
  double lo = e0, hi = e0;
  for (int s = 0; s < 2000; ++s) {
    d.step(Real(h));
    const double e = d.springEnergy() + d.kineticEnergy();
    lo = std::min(lo, e), hi = std::max(hi, e);
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      ASSERT_EQ(d.position(i).y(), 0) << "stays on the line";
  }
  // Float rounding of l - L in the spring energy: relative ~ eps L / (l - L) ~ 1e-5.
  EXPECT_GE(lo, e0 / (1 + a) * (1 - 1e-4));
  EXPECT_LE(hi, e0 / (1 - a) * (1 + 1e-4));
  // Not a bound that nothing reaches: the energy does swing by a fair part of it.
  EXPECT_GT(hi - lo, 0.1 * (e0 / (1 - a) - e0 / (1 + a)));
}

// Total mechanical energy of a cloth under gravity g: kinetic + springs + m g y.
double mechanicalEnergy(const Deformable& d, double g) {
  double e = d.kineticEnergy() + d.springEnergy();
  for (std::size_t i = 0; i < d.vertexCount(); ++i)
    e += double(d.masses()[i]) * g * double(d.position(i).y());
  return e;
}

// A cloth pinned at two corners, released flat, with stiff springs (1e6 N/m, 0.01 kg per
// vertex): omega_max h ~ sqrt(4 * 2e6 / 0.01) / 60 ~ 470 at 1/60 s, far beyond symplectic
// Euler's limit of 2. Symplectic Euler blows up, while the implicit step stays finite with
// its kinetic and spring energy bounded by what gravity can give: no vertex can fall more
// than the cloth's diagonal (1.42 m, plus its stretch) below the pins, so K + S <= M g 1.5 m.
// (Not "never more than at the start": the one linearised Newton step of Baraff and Witkin
// stretches a stiff spring that turns by h v across it, by (h v)^2 / 2L, which here makes the
// spring energy swing by up to a few J while the total falls; see README.)
TEST(DeformableEnergy, ImplicitIsStableAtSixtyHertzWhereExplicitBlowsUp) {
  const int n = 10;
  const double g = 9.81;
  ClothSettings cs{.size = {1, 1},
                   .resolution = {n, n},
                   .mass = Real(0.01 * (n + 1) * (n + 1)),
                   .stiffness = {.stretch = 1e6f, .shear = 1e6f, .bend = 1e3f}};
  MassSpringModel m = cloth(cs);
  m.pinned = {0, std::uint32_t(n)};
  Deformable implicit({.integrator = ode::Method::BackwardEuler, .solverTolerance = 1e-8}, m);
  Deformable symplectic({.integrator = ode::Method::SymplecticEuler}, m);
  for (Deformable* d : {&implicit, &symplectic}) d->addField({GravityField{Vec3(0, Real(-g), 0)}});
  double totalMass = 0;
  for (Real mi : implicit.masses()) totalMass += double(mi);
  const double bound = totalMass * g * 1.5;
  bool symplecticFailed = false;
  for (int s = 0; s < 120; ++s) {
    implicit.step(Real(1) / 60);
    symplectic.step(Real(1) / 60);
    const double e = implicit.kineticEnergy() + implicit.springEnergy();
    ASSERT_TRUE(std::isfinite(mechanicalEnergy(implicit, g))) << "step " << s;
    ASSERT_LE(e, bound) << "step " << s;
    const double es = symplectic.kineticEnergy() + symplectic.springEnergy();
    symplecticFailed = symplecticFailed || !std::isfinite(es) || es > bound;
  }
  EXPECT_TRUE(symplecticFailed);
  // It fell: the free corners hang below the pins.
  EXPECT_LT(implicit.position(std::size_t(n * (n + 1))).y(), -0.5f);
}

}  // namespace
}  // namespace inertia
