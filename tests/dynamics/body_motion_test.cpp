// The bodies' final motion (src/dynamics/body_motion.cpp), run in blocks on the step's
// workers: free bodies follow the closed form of constant acceleration, kinematic bodies move
// and turn by their velocities exactly, and the result is the same at one and two threads.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../step_constants.h"
#include "inertia/core/math.h"
#include "inertia/world/world.h"

using namespace inertia;
using inertia::test::kDt;

namespace {

constexpr int kSteps = 60;

struct Scene {
  World world;
  std::vector<BodyId> free, kinematic;
};

// 300 free spheres thrown apart (no two ever touch: 3 m apart, diverging) and 40 kinematic
// boxes moving and spinning: enough bodies that the workers split them into several blocks.
void build(Scene& s) {
  for (int i = 0; i < 300; ++i) {
    const Vec3 at(Real(3 * (i % 20)), Real(100), Real(3 * (i / 20)));
    const Vec3 v(Real(0.1) * Real(i % 7), Real(2 + i % 5), Real(-0.1) * Real(i % 3));
    const BodyId b = s.world.createBody({.position = at, .linearVelocity = v});
    s.world.addShape(b, Sphere{Real(0.2)});
    s.free.push_back(b);
  }
  for (int i = 0; i < 40; ++i) {
    const BodyId b = s.world.createBody({.type = BodyType::Kinematic,
                                         .position = Vec3(Real(3 * i), -50, 0),
                                         .linearVelocity = Vec3(1, Real(0.5), 0),
                                         .angularVelocity = Vec3(0, Real(0.01 * i), 0)});
    s.world.addShape(b, Box{Vec3::Constant(Real(0.5))});
    s.kinematic.push_back(b);
  }
}

}  // namespace

TEST(BodyMotion, FreeAndKinematicBodiesFollowTheirClosedForms) {
  Scene one{
      World({.integrator = ode::Method::VelocityVerlet, .threads = 1, .sleeping = false}), {}, {}};
  Scene two{
      World({.integrator = ode::Method::VelocityVerlet, .threads = 2, .sleeping = false}), {}, {}};
  build(one);
  build(two);
  std::vector<Vec3> start, velocity;
  for (BodyId b : one.free) {
    start.push_back(one.world.transform(b).p);
    velocity.push_back(one.world.linearVelocity(b));
  }
  for (int k = 0; k < kSteps; ++k) {
    one.world.step(kDt);
    two.world.step(kDt);
  }
  const Real t = kDt * kSteps;
  const Vec3 g(0, Real(-9.81), 0);
  for (std::size_t i = 0; i < one.free.size(); ++i) {
    // Velocity Verlet is exact for constant acceleration; what is left is float rounding:
    // 240 substeps, each rounding |x| <= 110 m to about 1e-5 m.
    const Vec3 expected = start[i] + velocity[i] * t + Real(0.5) * g * t * t;
    EXPECT_LT((one.world.transform(one.free[i]).p - expected).norm(), Real(3e-3)) << i;
    EXPECT_LT((one.world.linearVelocity(one.free[i]) - (velocity[i] + g * t)).norm(), Real(1e-4))
        << i;
  }
  for (std::size_t i = 0; i < one.kinematic.size(); ++i) {
    // x += v dt and an exact rotation per step: 60 roundings of |x| <= 120 m, and of a turn
    // of 0.01 i rad.
    const Transform pose = one.world.transform(one.kinematic[i]);
    EXPECT_LT((pose.p - Vec3(Real(3 * i) + t, -50 + Real(0.5) * t, 0)).norm(), Real(1e-3)) << i;
    const Real angle = rotationVector(pose.q).norm();
    EXPECT_NEAR(angle, Real(0.01 * double(i)) * t, Real(1e-5)) << i;
  }
  // The blocks' split does not change a bit.
  for (std::size_t i = 0; i < one.free.size(); ++i) {
    EXPECT_EQ(one.world.transform(one.free[i]).p, two.world.transform(two.free[i]).p);
    EXPECT_EQ(one.world.linearVelocity(one.free[i]), two.world.linearVelocity(two.free[i]));
  }
  for (std::size_t i = 0; i < one.kinematic.size(); ++i)
    EXPECT_EQ(one.world.transform(one.kinematic[i]).q.coeffs(),
              two.world.transform(two.kinematic[i]).q.coeffs());
}
