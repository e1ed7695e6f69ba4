// Two-way coupling of deformables with dynamic bodies in a World: contact impulses shared by a
// vertex and a body (closed form), friction of a held vertex shared with the body it slides on
// (closed form), a ball caught by a pinned cloth, a body hanging from a rope
// by an attachment at its static equilibrium (closed form).
#include <gtest/gtest.h>

#include <limits>

#include "inertia/collision/queries.h"
#include "inertia/deformable/generators.h"
#include "inertia/world/world.h"

namespace inertia {
namespace {

MassSpringModel oneVertex(const Vec3& x, const Vec3& v, Real mass) {
  MassSpringModel m;
  m.positions = {x};
  m.velocities = {v};
  m.masses = {mass};
  return m;
}

// A vertex (m = 0.5 kg, 3 m/s) hits a resting box (M = 2 kg) off its centre, without gravity
// or friction. The inelastic impulse along the face normal n is the closed form
//     j = -v_n / (1/m + 1/M + (r x n)^T I^-1 (r x n)),
// after which the vertex moves at v + j n / m, the box at -j n / M and -I^-1 (r x j n); the
// total linear momentum is unchanged (to float rounding of the velocities, eps m |v|).
TEST(DeformableCoupling, VertexBodyImpulseConservesMomentumInClosedForm) {
  World world({.gravity = Vec3::Zero(), .dt = Real(1) / 60});
  const Real bodyMass = 2, m = Real(0.5), speed = 3;
  const Vec3 half(Real(0.5), Real(0.2), Real(0.3));
  const BodyId box = world.createBody({.mass = bodyMass});
  world.addShape(box, Box{half});
  // Starts 0.01 m above the top face at x = 0.3 (off the centre), moving down.
  const Vec3 start(Real(0.3), half.y() + Real(0.0101), 0);
  const DeformableId id = world.createDeformable({.thickness = Real(0.01), .friction = 0},
                                                 oneVertex(start, Vec3(0, -speed, 0), m));
  world.step(Real(1) / 60);
  const Deformable& d = world.deformable(id);
  ASSERT_EQ(d.obstacleImpulses().size(), 1u);
  // The closed form at the contact point the vertex was pushed out to.
  const Vec3 r = d.obstacleImpulses()[0].point - world.rigidBodies().centerOfMass(box);
  const Vec3 n = Vec3::UnitY();
  const Mat3 inverseInertia = world.rigidBodies().inertiaWorld(box).inverse();
  const Real j = speed / (1 / m + 1 / bodyMass + r.cross(n).dot(inverseInertia * r.cross(n)));
  const Real eps = std::numeric_limits<Real>::epsilon();
  EXPECT_NEAR(d.velocity(0).y(), -speed + j / m, 8 * eps * speed);
  EXPECT_NEAR(world.linearVelocity(box).y(), -j / bodyMass, 8 * eps * speed);
  EXPECT_LT((world.angularVelocity(box) + inverseInertia * r.cross(j * n)).norm(),
            32 * eps * speed);
  const Vec3 momentum = m * d.velocity(0) + bodyMass * world.linearVelocity(box);
  EXPECT_LT((momentum - Vec3(0, -m * speed, 0)).norm(), 8 * eps * m * speed);
  // Not the one-way answer (the vertex stopped dead, the box untouched).
  EXPECT_LT(world.linearVelocity(box).y(), -0.1f);
}

// A vertex (m = 0.5 kg) sliding at 1 m/s on a box (M = 2 kg) that rests on frictionless ground,
// with friction mu = 0.5 between them, under implicit Euler (the vertex held on the box in the
// solve). Friction takes mu m g h off their relative speed each step, (1 + m/M) of it, and
// hands the box what it takes from the vertex: they stop sliding after u0 / (mu g (1 + m/M)) =
// 0.16 s and move on together at m u0 / (m + M) = 0.2 m/s (a perfectly inelastic collision's
// closed form), the total horizontal momentum m u0 unchanged throughout. Tolerances: the
// momentum to 1e-5 of m u0 (float velocities over 60 steps, a few eps each); the common speed
// to 1e-3: the body takes the vertex's impulse a step late (explicit coupling), so they pass
// the common speed by up to mu g h m/M (2% of it) when they stick, an overshoot that shrinks
// about fourfold a step and is under 1e-5 by the 20th step. Without friction in the solve the
// vertex slid on at 1 m/s and the box never moved.
TEST(DeformableCoupling, FrictionOfAHeldVertexDragsTheBodyItSlidesOn) {
  World world({.dt = Real(1) / 60});
  const Real m = Real(0.5), bodyMass = 2, u0 = 1, mu = Real(0.5), thickness = Real(0.01);
  const Vec3 half(Real(0.5), Real(0.1), Real(0.5));
  const BodyId ground = world.createBody({.type = BodyType::Static, .position = Vec3(0, -1, 0)});
  world.addShape(ground, Box{Vec3(5, 1, 5)}, Material{.friction = 0});
  const BodyId box = world.createBody({.position = Vec3(0, half.y(), 0), .mass = bodyMass});
  world.addShape(box, Box{half}, Material{.friction = 0});
  const Vec3 start(Real(-0.3), 2 * half.y() + thickness * Real(1.001), 0);
  const DeformableId id = world.createDeformable({.thickness = thickness, .friction = mu},
                                                 oneVertex(start, Vec3(u0, 0, 0), m));
  world.deformable(id).addField({GravityField{}});
  for (int s = 0; s < 60; ++s) {
    world.step(Real(1) / 60);
    const Real momentum =
        m * world.deformable(id).velocity(0).x() + bodyMass * world.linearVelocity(box).x();
    ASSERT_NEAR(momentum, m * u0, Real(1e-5) * m * u0) << "step " << s;
  }
  const Real together = m * u0 / (m + bodyMass);
  EXPECT_NEAR(world.deformable(id).velocity(0).x(), together, Real(1e-3) * together);
  EXPECT_NEAR(world.linearVelocity(box).x(), together, Real(1e-3) * together);
}

// A ball (0.5 kg) dropped from 0.6 m onto a cloth pinned all round (a trampoline) is caught:
// the cloth's springs push it back through the contacts (held in the implicit solve, their
// impulses handed to the ball), so it stops falling well above where it would be in free fall
// (2 m lower after 1.5 s), moves up again (bounces) and no vertex passes into it. One way
// (the cloth not colliding with bodies), it falls through.
TEST(DeformableCoupling, BallDroppedOnAPinnedClothIsCaught) {
  for (bool twoWay : {true, false}) {
    World world({.dt = Real(1) / 60});
    const Real radius = Real(0.15), thickness = Real(0.01);
    const BodyId ball = world.createBody({.position = {0, Real(0.6), 0}, .mass = Real(0.5)});
    world.addShape(ball, Sphere{radius});
    const int n = 20;
    MassSpringModel sheet = cloth({.size = {1, 1},
                                   .resolution = {n, n},
                                   .mass = Real(0.2),
                                   .stiffness = {.stretch = 5000, .shear = 500, .bend = 5},
                                   .damping = Real(0.05)});
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (i == 0 || j == 0 || i == n || j == n)
          sheet.pinned.push_back(std::uint32_t(i + j * (n + 1)));
    const DeformableId id =
        world.createDeformable({.thickness = thickness, .collideWithBodies = twoWay}, sheet);
    world.deformable(id).addField({GravityField{}});
    const Collider sphere(Sphere{radius});
    Real lowest = 1, highestAfterLowest = -1;
    bool rose = false;
    for (int s = 0; s < 90; ++s) {
      world.step(Real(1) / 60);
      const Real y = world.transform(ball).p.y();
      if (y < lowest) lowest = y, highestAfterLowest = y;
      highestAfterLowest = std::max(highestAfterLowest, y);
      rose = rose || world.linearVelocity(ball).y() > Real(0.05);
      if (!twoWay) continue;
      const Deformable& d = world.deformable(id);
      for (std::size_t i = 0; i < d.vertexCount(); ++i)
        ASSERT_GE(queryPoint(sphere, world.transform(ball), d.position(i)).distance,
                  thickness - Real(1e-4))
            << "step " << s;
    }
    if (twoWay) {
      EXPECT_GT(lowest, Real(0));     // the ball's centre stayed above the pinned frame
      EXPECT_LT(lowest, Real(0.15));  // the cloth gave (the ball's bottom went below the frame)
      EXPECT_TRUE(rose);              // it bounced
      EXPECT_LT(std::abs(world.linearVelocity(ball).y()), Real(0.5));
    } else {
      EXPECT_LT(lowest, Real(-1));  // it fell through
    }
  }
}

// A body of mass M hangs from a vertical rope (pinned at its top, stretch springs only) by an
// attachment of stiffness k_a. At rest every spring carries the weight below it: spring j
// (from the top) stretches by g (M + (N - j) m_v) / k, the attachment by M g / k_a, so the
// body's centre sits at y_top - sum (L + stretch_j) - M g / k_a. Damped, it settles there
// (to 1e-4 m, far below the 0.02 m of the attachment's own stretch) and stays. (Its velocity
// read after a step is not zero: the step's attachment impulse, M g dt, is applied at its end,
// after gravity's, in the coupling's explicit exchange.)
TEST(DeformableCoupling, BodyHangingFromARopeSettlesAtTheStaticEquilibrium) {
  const Real g = Real(9.81), bodyMass = 1, ropeMass = Real(0.2), k = 2000, ka = 500;
  const int segments = 8;
  const Real length = 1, top = 2;
  World world({.gravity = Vec3(0, -g, 0), .dt = Real(1) / 60});
  const BodyId body = world.createBody({.position = {0, top - length, 0}, .mass = bodyMass});
  world.addShape(body, Sphere{Real(0.1)});
  MassSpringModel r = rope({.from = {0, top, 0},
                            .to = {0, top - length, 0},
                            .segments = segments,
                            .mass = ropeMass,
                            .stiffness = {.stretch = k, .bend = 0},
                            .damping = 5});
  r.pinned = {0};
  const DeformableId id = world.createDeformable({.collideWithBodies = false}, r);
  Deformable& d = world.deformable(id);
  d.addField({GravityField{Vec3(0, -g, 0)}});
  d.addAttachment(
      {.vertex = std::uint32_t(segments), .body = body, .stiffness = ka, .damping = 10});
  for (int s = 0; s < 60 * 20; ++s) world.step(Real(1) / 60);
  const Real before = world.transform(body).p.y();
  world.step(Real(1) / 60);
  const double mv = double(ropeMass) / (segments + 1), restLength = double(length) / segments;
  double y = double(top);
  for (int j = 0; j < segments; ++j)
    y -= restLength + double(g) * (double(bodyMass) + (segments - j) * mv) / double(k);
  EXPECT_NEAR(double(world.deformable(id).position(std::size_t(segments)).y()), y, 1e-4);
  y -= double(bodyMass) * double(g) / double(ka);
  EXPECT_NEAR(double(world.transform(body).p.y()), y, 1e-4);
  EXPECT_LT(std::abs(world.transform(body).p.y() - before), Real(1e-6));
}

}  // namespace
}  // namespace inertia
