// Collisions with static shapes: no vertex closer to a shape than the thickness after any
// step, friction that holds or lets slide as Coulomb says, fast vertices that do not tunnel.
#include <gtest/gtest.h>

#include <cmath>

#include "../sanitizer.h"
#include "inertia/collision/queries.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

// Vertices are pushed out to thickness (1 + 1e-3); their float coordinates near 1 m round by
// 1.2e-7 m, and a point query's distance by a few eps: 1e-6 m of slack.
constexpr Real kSlack = Real(1e-6);

Real closest(const Deformable& d, const Obstacle& o) {
  Real nearest = std::numeric_limits<Real>::infinity();
  for (std::size_t i = 0; i < d.vertexCount(); ++i)
    nearest = std::min(nearest, queryPoint(o.collider, o.pose, d.position(i)).distance);
  return nearest;
}

// A 1 m cloth dropped from 0.3 m above each shape (and a ground plane below), implicit at
// 1/60 s for 2 s: it drapes, and after every step every vertex is at least the thickness from
// each shape.
TEST(DeformableCollision, DroppedClothKeepsItsThicknessFromEveryShape) {
  const Real thickness = Real(0.02);
  const Obstacle ground{Collider(Plane{Vec3::UnitY(), Real(-1)}), Transform{}};
  const Obstacle shapes[] = {
      {Collider(Sphere{Real(0.3)}), Transform{}},
      {Collider(Box{Vec3(Real(0.25), Real(0.25), Real(0.25))}),
       Transform{Vec3::Zero(), Quat(Eigen::AngleAxis<Real>(Real(0.4), Vec3::UnitY()))}},
      {Collider(Capsule{Real(0.15), Real(0.3)}),
       Transform{Vec3::Zero(), Quat(Eigen::AngleAxis<Real>(Real(1.5707963), Vec3::UnitZ()))}},
  };
  // A coarser cloth under the sanitizers (see sanitizer.h): the same contacts, a quarter of
  // the vertices.
  const int res = test::samplesFor(16, 8);
  for (const Obstacle& shape : shapes) {
    MassSpringModel m = cloth({.pose = {Vec3(0, Real(0.6), 0), Quat::Identity()},
                               .size = {1, 1},
                               .resolution = {res, res},
                               .mass = Real(0.2),
                               .stiffness = {.stretch = 2000, .shear = 200, .bend = 1},
                               .damping = Real(0.02)});
    Deformable d({.thickness = thickness, .friction = Real(0.4)}, m);
    d.addField({GravityField{}});
    d.addObstacle(shape);
    d.addObstacle(ground);
    for (int s = 0; s < 120; ++s) {
      d.step(Real(1) / 60);
      ASSERT_GE(closest(d, shape), thickness - kSlack)
          << "step " << s << " shape " << int(shape.collider.type());
      ASSERT_GE(closest(d, ground), thickness - kSlack) << "step " << s;
    }
    // It rests on the shape: the centre vertex lies on top, inside the band of resting contacts
    // (holdBodyContacts holds a vertex within twice the thickness at the surface's normal
    // velocity, so it rests where it was caught, anywhere in [thickness, 2 thickness): the
    // coarse cloth of the sanitizer builds rests its centre at 1.65 thickness on one shape).
    const Vec3 centre = d.position(std::size_t(res / 2 * (res + 2)));
    EXPECT_LT(queryPoint(shape.collider, shape.pose, centre).distance, 2 * thickness);
  }
}

// Hair on a head (a sphere obstacle of the roots' radius), implicit at 1/60 s for 1.5 s: the
// strands fall over the head and hang, and after every step every vertex but the pinned roots
// is at least the thickness from the head.
TEST(DeformableCollision, HairFallsOverTheHeadAndKeepsItsThickness) {
  const Real radius = Real(0.1), thickness = Real(0.005);
  const int segments = 8;
  const MassSpringModel m = hair({.radius = radius,
                                  .capAngle = Real(1.3),
                                  .strands = 60,
                                  .segments = segments,
                                  .length = Real(0.2),
                                  .mass = Real(0.01),
                                  .stiffness = {.stretch = 500, .bend = Real(0.2)},
                                  .damping = Real(0.001)});
  Deformable d({.thickness = thickness, .friction = Real(0.2)}, m);
  d.addField({GravityField{}});
  const Obstacle head{Collider(Sphere{radius}), Transform{}};
  d.addObstacle(head);
  for (int s = 0; s < 90; ++s) {
    d.step(Real(1) / 60);
    ASSERT_TRUE(d.lastSolve().converged) << "step " << s;
    for (std::size_t i = 0; i < d.vertexCount(); ++i) {
      if (i % std::size_t(segments + 1) == 0) continue;  // a root, pinned on the scalp
      ASSERT_GE(queryPoint(head.collider, head.pose, d.position(i)).distance, thickness - kSlack)
          << "step " << s << " vertex " << i;
    }
  }
  // Every tip has fallen below its root's height plus a tenth of the length: nothing stands.
  for (std::size_t root : m.pinned)
    EXPECT_LT(d.position(root + std::size_t(segments)).y(), m.positions[root].y() + Real(0.02))
        << "strand from vertex " << root;
}

// A soft ball placed on the ground settles under its weight alone. Energy: the springs can hold
// no more than gravity released, m g times the centre of mass's drop (Clapeyron: half of it
// for a linear response). Stiffness: it compresses about in inverse proportion to k (10x
// softer: more than 5x the drop, the spokes' geometry bending the proportion). Before resting
// contacts were held in the solve, the bottom vertices gave way in every solve and were only
// projected out after it: the ball settled squashed by 5 cm whatever k, with 14.7 J in its
// springs at k = 2000 against 0.15 J released.
TEST(DeformableCollision, SoftBallRestsUnderItsWeightAlone) {
  const Real radius = Real(0.25), mass = Real(0.5), g = Real(9.81), thickness = Real(0.01);
  double drops[2] = {};
  const Real stiffness[2] = {2000, 200};
  for (int run = 0; run < 2; ++run) {
    const MassSpringModel m =
        softSphere({.pose = {Vec3(0, radius + thickness + Real(1e-4), 0), Quat::Identity()},
                    .radius = radius,
                    .subdivisions = 2,
                    .mass = mass,
                    .stiffness = {.stretch = stiffness[run], .bend = 20},
                    .damping = Real(0.05)});
    Deformable d({.thickness = thickness, .friction = Real(0.5)}, m);
    d.addField({GravityField{}});
    d.addObstacle({Collider(Plane{Vec3::UnitY(), 0}), Transform{}});
    const auto meanHeight = [&] {
      double y = 0;
      for (std::size_t i = 0; i < d.vertexCount(); ++i) y += double(d.position(i).y());
      return y / double(d.vertexCount());  // the masses are equal
    };
    const double start = meanHeight();
    for (int s = 0; s < 180; ++s) d.step(Real(1) / 60);
    drops[run] = start - meanHeight();
    EXPECT_GT(drops[run], 0);
    EXPECT_LE(d.springEnergy(), double(mass * g) * drops[run]) << "k = " << stiffness[run];
    EXPECT_LT(d.kineticEnergy(), 1e-6) << "k = " << stiffness[run];
  }
  EXPECT_GT(drops[1], 5 * drops[0]);
}

// A single vertex at 200 m/s towards a 2 cm thick wall, 3.3 m per step: swept, it stops at the
// wall instead of passing through.
TEST(DeformableCollision, FastVertexIsSweptAndDoesNotTunnel) {
  MassSpringModel m;
  m.positions = {Vec3(-1, 0, 0)};
  m.velocities = {Vec3(200, 0, 0)};
  m.masses = {1};
  for (ode::Method method : {ode::Method::BackwardEuler, ode::Method::SymplecticEuler}) {
    Deformable d({.integrator = method, .thickness = Real(0.005), .friction = 0}, m);
    const Obstacle wall{Collider(Box{Vec3(Real(0.01), 1, 1)}), Transform{}};
    d.addObstacle(wall);
    for (int s = 0; s < 3; ++s) d.step(Real(1) / 60);
    EXPECT_LT(d.position(0).x(), Real(-0.01)) << ode::methodName(method);
    EXPECT_LE(d.velocity(0).x(), 0) << "inelastic: stopped";
  }
}

// Coulomb friction on a 30 degree slope: with mu = 0.8 > tan 30 a resting rope stays (up to
// the first step's settling), with mu = 0.3 < tan 30 it slides down with acceleration close to
// g (sin 30 - mu cos 30). Symplectic Euler: the discrete push-out applies friction to each
// step's normal velocity change, h g cos 30, so the slide's rate is exact per step once in
// contact. Implicit Euler: the held contacts' active set sticks the rope, or slides it with mu
// times the normal impulse h m g cos 30, exact per step too (it slid at g sin 30 whatever mu
// while its held vertices had no friction).
TEST(DeformableCollision, FrictionHoldsOrSlidesOnASlopeAsCoulombSays) {
  const Real angle = Real(0.5235988);
  const Vec3 normal(-std::sin(angle), std::cos(angle), 0);
  const Vec3 down(-std::cos(angle), -std::sin(angle), 0);
  const Obstacle slope{Collider(Plane{normal, 0}), Transform{}};
  const Vec3 across = normal.cross(down).normalized();
  for (ode::Method method : {ode::Method::SymplecticEuler, ode::Method::BackwardEuler})
    for (Real mu : {Real(0.8), Real(0.3)}) {
      MassSpringModel m = rope({.from = normal * Real(0.011) - across * Real(0.2),
                                .to = normal * Real(0.011) + across * Real(0.2),
                                .segments = 4,
                                .mass = 1,
                                .stiffness = {.stretch = 500, .bend = 0}});
      Deformable d({.integrator = method, .thickness = Real(0.01), .friction = mu}, m);
      d.addField({GravityField{}});
      d.addObstacle(slope);
      for (int s = 0; s < 60; ++s) d.step(Real(1) / 60);
      const Real speed = d.velocity(2).dot(down);
      const Real expected = mu > std::tan(angle)
                                ? 0
                                : Real(9.81) * (std::sin(angle) - mu * std::cos(angle)) * Real(1);
      EXPECT_NEAR(speed, expected, Real(0.02) * Real(9.81))
          << ode::methodName(method) << ", mu " << mu;
    }
}

}  // namespace
}  // namespace inertia
