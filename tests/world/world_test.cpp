#include "inertia/world/world.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "inertia/core/error.h"

using namespace inertia;

TEST(World, StepAdvancesTimeByDt) {
  World world({.dt = Real(0.01)});
  for (int i = 0; i < 100; ++i) world.step(Real(0.01));
  EXPECT_EQ(world.stepCount(), 100);
  // 100 additions of float(0.01) in double: exact sum 100 * float(0.01), rounding ~1e-15.
  EXPECT_NEAR(world.time(), 100 * double(Real(0.01)), 1e-12);
}

TEST(World, AdvanceTakesFixedStepsAndKeepsTheRemainder) {
  const Real h = Real(0.01);
  World world({.dt = h});
  // 0.025 s of frame time is two whole steps; the rest (0.005 s) waits in the accumulator.
  EXPECT_EQ(world.advance(Real(0.025)), 2);
  EXPECT_NEAR(world.interpolationAlpha(), 0.5, 1e-4);  // float rounding of 0.025 and 0.01
  EXPECT_EQ(world.advance(Real(0.006)), 1);           // 0.011 s accumulated: one more step
  EXPECT_NEAR(world.interpolationAlpha(), 0.1, 1e-4);
  EXPECT_EQ(world.stepCount(), 3);
}

TEST(World, AdvanceNeverFallsBehindWithoutBound) {
  World world({.dt = Real(0.01)});
  // A 10 s hitch is clamped to maxSteps steps; the accumulator stays below one step.
  EXPECT_EQ(world.advance(Real(10), 8), 8);
  EXPECT_LT(world.interpolationAlpha(), 1);
  EXPECT_GE(world.interpolationAlpha(), 0);
}

TEST(World, RejectsBadInput) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(World({.dt = 0}), InvalidArgument);
  EXPECT_THROW(World({.dt = nan}), InvalidArgument);
  EXPECT_THROW(World({.gravity = Vec3(0, nan, 0)}), InvalidArgument);
  EXPECT_THROW(World({.substeps = 0}), InvalidArgument);
  EXPECT_THROW(World({.threads = -1}), InvalidArgument);
  World world;
  EXPECT_THROW(world.step(-1), InvalidArgument);
  EXPECT_THROW(world.step(nan), InvalidArgument);
  EXPECT_THROW(world.advance(nan), InvalidArgument);
  EXPECT_EQ(world.stepCount(), 0);  // a rejected call changes nothing
}

TEST(World, SolverNamesRoundTrip) {
  for (SolverType t : {SolverType::SoftStep, SolverType::Pgs, SolverType::LcpDantzig,
                       SolverType::LcpLemke}) {
    SolverType back{};
    ASSERT_TRUE(solverFromName(solverName(t), back));
    EXPECT_EQ(back, t);
  }
  SolverType unused{};
  EXPECT_FALSE(solverFromName("gauss", unused));
}

// A world accepts the direct LCP solvers (they were refused before they were built) and steps.
TEST(World, AcceptsLcpSolvers) {
  for (SolverType t : {SolverType::LcpDantzig, SolverType::LcpLemke}) {
    World world({.solver = {.type = t}});
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0});
    const BodyId box = world.createBody({.position = Vec3(0, Real(0.5), 0)});
    world.addShape(box, Box{Vec3::Constant(Real(0.5))});
    for (int i = 0; i < 30; ++i) world.step(Real(1.0 / 60));
    EXPECT_NEAR(world.transform(box).p.y(), Real(0.5), Real(0.01)) << solverName(t);
  }
}
