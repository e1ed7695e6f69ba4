// The viewer's clock: fixed steps decoupled from the frame rate, pause, single step, slow
// motion, restart, live settings, and poses interpolated between the last two steps.
#include "playback.h"

#include <gtest/gtest.h>

#include <cmath>

#include "inertia/core/error.h"

namespace inertia::viewer {
namespace {

// A ball falling freely from y = 10 (no ground), stepped at 100 Hz.
io::Scene fallingBall() {
  io::Scene scene;
  scene.world.dt = Real(0.01);
  scene.world.substeps = 1;
  BodyDesc& ball = scene.bodies.emplace_back();
  ball.settings.position = Vec3(0, 10, 0);
  ball.shapes.push_back({.shape = Sphere{Real(0.5)}});
  return scene;
}

TEST(Playback, StepsFollowRealTimeNotFrames) {
  // 0.5 s in 1 ms frames and in 20 ms frames: 50 fixed steps of 10 ms either way.
  Playback a(fallingBall()), b(fallingBall());
  int stepsA = 0, stepsB = 0;
  for (int i = 0; i < 500; ++i) stepsA += a.frame(0.001);
  for (int i = 0; i < 25; ++i) stepsB += b.frame(0.02);
  EXPECT_NEAR(stepsA, 50, 1);
  EXPECT_EQ(stepsB, 50);
  EXPECT_EQ(a.world().stepCount(), stepsA);
  const BodyId ball = b.world().rigidBodies().bodies()[0];
  // The same number of fixed steps gives the same state, bit for bit.
  if (stepsA == stepsB) {
    EXPECT_EQ(a.world().transform(ball).p, b.world().transform(ball).p);
  }
  const double t = 0.5;
  EXPECT_NEAR(b.world().transform(ball).p.y(), 10 - 0.5 * 9.81 * t * t, 0.05);
}

TEST(Playback, LongFramesAreCapped) {
  Playback p(fallingBall());
  p.maxStepsPerFrame = 4;
  EXPECT_EQ(p.frame(1.0), 4);  // 100 steps' worth, capped; the rest is dropped
  EXPECT_LE(p.frame(0.0), 1);
}

TEST(Playback, PauseStepAndSlowMotion) {
  Playback p(fallingBall());
  p.paused = true;
  EXPECT_EQ(p.frame(0.5), 0);
  EXPECT_EQ(p.world().stepCount(), 0);
  p.singleStep();
  EXPECT_EQ(p.world().stepCount(), 1);
  p.paused = false;
  p.timeScale = 0.25;
  int steps = 0;
  for (int i = 0; i < 40; ++i) steps += p.frame(0.01);  // 0.4 s real, 0.1 s simulated
  EXPECT_NEAR(steps, 10, 1);
  EXPECT_THROW(p.frame(-1), InvalidArgument);
  p.timeScale = 0;
  EXPECT_THROW(p.frame(0.01), InvalidArgument);
}

TEST(Playback, DrawPosesInterpolateBetweenTheLastTwoSteps) {
  Playback p(fallingBall());
  const BodyId ball = p.world().rigidBodies().bodies()[0];
  p.frame(0.05);  // 5 steps
  const Real before = p.world().transform(ball).p.y();
  p.frame(0.016);  // one step and 0.6 of the next
  const Real after = p.world().transform(ball).p.y();
  ASSERT_EQ(p.world().stepCount(), 6);
  const Real alpha = p.world().interpolationAlpha();
  EXPECT_NEAR(alpha, 0.6, 1e-3);
  const std::vector<Transform> poses = p.drawPoses();
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_NEAR(poses[0].p.y(), before + alpha * (after - before), 1e-5);
  EXPECT_LT(poses[0].p.y(), before);
  EXPECT_GT(poses[0].p.y(), after);
  // Paused: the current state as it is.
  p.paused = true;
  EXPECT_EQ(p.drawPoses()[0].p.y(), after);
}

TEST(Playback, BeforeStepRunsBeforeEveryStep) {
  Playback p(fallingBall());
  int calls = 0;
  std::int64_t stepAtCall = -1;
  bool ordered = true;
  p.beforeStep = [&](World& w) {
    ordered = ordered && w.stepCount() == stepAtCall + 1;
    stepAtCall = w.stepCount();
    ++calls;
  };
  int steps = 0;
  for (int i = 0; i < 30; ++i) steps += p.frame(0.0173);
  p.singleStep();
  EXPECT_EQ(calls, steps + 1);
  EXPECT_TRUE(ordered);
}

TEST(Playback, RestartAndLiveSettings) {
  Playback p(fallingBall());
  const BodyId ball = p.world().rigidBodies().bodies()[0];
  p.frame(0.3);
  const Vec3 position = p.world().transform(ball).p;
  const std::int64_t steps = p.world().stepCount();

  WorldSettings zeroG = p.scene().world;
  zeroG.gravity = Vec3::Zero();
  zeroG.solver.iterations = 12;
  p.applySettings(zeroG);
  // The state carried over, the new settings in force: no more acceleration.
  EXPECT_EQ(p.world().stepCount(), steps);
  EXPECT_EQ(p.world().transform(ball).p, position);
  EXPECT_EQ(p.world().settings().solver.iterations, 12);
  const Vec3 v = p.world().linearVelocity(ball);
  p.frame(0.1);
  EXPECT_TRUE(p.world().linearVelocity(ball).isApprox(v, 1e-5f));

  WorldSettings bad = zeroG;
  bad.substeps = 0;
  EXPECT_THROW(p.applySettings(bad), InvalidArgument);
  EXPECT_EQ(p.world().settings().substeps, zeroG.substeps);  // unchanged

  p.restart();  // from the scene, keeping the settings applied
  EXPECT_EQ(p.world().stepCount(), 0);
  EXPECT_EQ(p.world().transform(p.world().rigidBodies().bodies()[0]).p, Vec3(0, 10, 0));
  EXPECT_EQ(p.world().settings().gravity, Vec3::Zero());
}

TEST(Playback, NewSettingsWakeSleepingBodies) {
  io::Scene scene = fallingBall();
  scene.world.dt = Real(1.0 / 60);
  scene.bodies[0].settings.position = Vec3(0, 0.5, 0);
  BodyDesc& ground = scene.bodies.emplace_back();
  ground.settings.type = BodyType::Static;
  ground.shapes.push_back({.shape = Plane{Vec3::UnitY(), 0}});
  Playback p(std::move(scene));
  const BodyId ball = p.world().rigidBodies().bodies()[0];
  for (int i = 0; i < 240 && p.world().rigidBodies().isAwake(ball); ++i) p.singleStep();
  ASSERT_FALSE(p.world().rigidBodies().isAwake(ball));
  WorldSettings up = p.scene().world;
  up.gravity = Vec3(0, 2, 0);
  p.applySettings(up);
  EXPECT_TRUE(p.world().rigidBodies().isAwake(ball));
  for (int i = 0; i < 60; ++i) p.singleStep();  // 1 s rising at 2 m/s^2: 1 m
  EXPECT_NEAR(p.world().transform(ball).p.y(), 1.5, 0.05);
}

}  // namespace
}  // namespace inertia::viewer
