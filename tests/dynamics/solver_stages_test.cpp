// The solver stages (src/dynamics/solver_stages.cpp) against statics: in a resting stack the
// impulses stored after a step (the last substep's, which warm-start the next) carry the
// weight above each contact over one substep, m g h, for every solver and at one and two
// threads.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../step_constants.h"
#include "inertia/world/world.h"

using namespace inertia;
using inertia::test::kDt;
using inertia::test::kG;
using inertia::test::kSubsteps;

namespace {

// The sum of the normal impulses (N s) over the contacts between body `a` and body `b`.
Real normalImpulse(const RigidBodySystem& rb, BodyId a, BodyId b) {
  Real sum = 0;
  for (const ContactInfo& c : rb.contacts()) {
    if (!((c.bodyA == a && c.bodyB == b) || (c.bodyA == b && c.bodyB == a))) continue;
    for (int k = 0; k < c.manifold.pointCount; ++k) sum += c.normalImpulses[std::size_t(k)];
  }
  return sum;
}

}  // namespace

TEST(SolverStages, RestingStackCarriesItsWeight) {
  for (SolverType solver : {SolverType::SoftStep, SolverType::Pgs, SolverType::LcpDantzig}) {
    for (int threads : {1, 2}) {
      World world({.substeps = kSubsteps,
                   .solver = {.type = solver},
                   .threads = threads,
                   .sleeping = false});
      const BodyId ground = world.createBody({.type = BodyType::Static});
      world.addShape(ground, Plane{Vec3::UnitY(), 0});
      std::vector<BodyId> boxes;
      for (int i = 0; i < 4; ++i) {
        boxes.push_back(world.createBody({.position = Vec3(0, Real(0.5) + Real(i), 0)}));
        world.addShape(boxes.back(), Box{Vec3::Constant(Real(0.5))});
      }
      for (int k = 0; k < 120; ++k) world.step(kDt);  // 2 s to settle
      const RigidBodySystem& rb = world.rigidBodies();
      const Real m = rb.mass(boxes[0]);
      // At rest each contact carries the boxes above it over a substep. The residual motion
      // of a settled stack changes velocities by well under 1e-3 m/s a substep, under 1% of
      // g h = 0.04 m/s.
      for (int i = 0; i < 4; ++i) {
        const BodyId below = i == 0 ? ground : boxes[std::size_t(i - 1)];
        const Real expected = Real(4 - i) * m * kG * kDt / kSubsteps;
        EXPECT_NEAR(normalImpulse(rb, below, boxes[std::size_t(i)]), expected,
                    Real(0.01) * expected)
            << solverName(solver) << ", " << threads << " threads, contact " << i;
      }
    }
  }
}
