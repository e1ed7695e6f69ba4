#include "inertia/particles/emitter.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "inertia/core/error.h"
#include "inertia/geometry/mesh.h"

using namespace inertia;

TEST(Emitter, RateCarriesFractionsBetweenSteps) {
  // 2.5 particles per second at 1 s steps: 2, 3, 2, 3, ... (the half carries over).
  ParticlePool pool(100);
  Emitter e({.rate = Real(2.5)});
  std::int64_t total = 0;
  for (int step = 0; step < 10; ++step) total += e.emit(pool, 1);
  EXPECT_EQ(total, 25);
  EXPECT_EQ(pool.size(), 25u);
}

TEST(Emitter, BurstComesOnceAndOverflowIsCounted) {
  ParticlePool pool(10);
  Emitter e({.burst = 15});
  EXPECT_EQ(e.emit(pool, Real(0.01)), 10);
  EXPECT_EQ(e.dropped(), 5);
  EXPECT_EQ(e.emit(pool, Real(0.01)), 0);
}

TEST(Emitter, SameSeedSameParticles) {
  ParticlePool a(1000), b(1000), c(1000);
  EmitterSettings s{.shape = EmitterShape::Sphere, .burst = 1000, .spread = Real(0.5),
                    .speed = {1, 5}, .seed = 42};
  Emitter(s).emit(a, Real(0.01));
  Emitter(s).emit(b, Real(0.01));
  s.seed = 43;
  Emitter(s).emit(c, Real(0.01));
  EXPECT_TRUE(std::equal(a.positions().begin(), a.positions().end(), b.positions().begin()));
  EXPECT_TRUE(std::equal(a.velocities().begin(), a.velocities().end(), b.velocities().begin()));
  EXPECT_FALSE(std::equal(a.positions().begin(), a.positions().end(), c.positions().begin()));
}

TEST(Emitter, ConeDirectionsStayWithinTheAngleAndFillIt) {
  const Real angle = Real(0.4);
  ParticlePool pool(20000);
  Emitter e({.shape = EmitterShape::Cone, .angle = angle, .burst = 20000, .direction = Vec3(1, 0, 0),
             .speed = {2, 2}});
  e.emit(pool, Real(1e-9));  // a negligible step: velocities are the emission directions
  double meanCos = 0;
  Real maxAngle = 0;
  for (std::size_t i = 0; i < pool.size(); ++i) {
    const Vec3 d = pool.velocity(i).normalized();
    maxAngle = std::max(maxAngle, std::acos(std::min(Real(1), d.x())));
    meanCos += d.x();
  }
  meanCos /= double(pool.size());
  EXPECT_LE(maxAngle, angle + Real(1e-3));  // acos near 1 loses ~sqrt(eps) in float
  EXPECT_GE(maxAngle, angle - Real(0.02));  // 20000 samples reach the rim
  // Uniform on the cap: cos theta uniform on [cos a, 1], mean (1 + cos a) / 2. Standard error
  // of the mean: (1 - cos a) / sqrt(12 n) = 4.5e-5; allow 5 sigma.
  EXPECT_NEAR(meanCos, (1 + std::cos(double(angle))) / 2, 5 * (1 - std::cos(double(angle))) / std::sqrt(12.0 * 20000));
}

TEST(Emitter, SphereVolumeIsUniform) {
  // Uniform in a ball of radius R: E[r] = 3R/4, sd(r) = sqrt(3/80) R.
  const Real R = 2;
  const int n = 20000;
  ParticlePool pool(n);
  Emitter e({.shape = EmitterShape::Sphere, .pose = {Vec3(5, 0, 0), Quat::Identity()}, .radius = R,
             .burst = n, .speed = {0, 0}});
  e.emit(pool, Real(1e-3));
  double mean = 0;
  for (std::size_t i = 0; i < pool.size(); ++i) {
    const double r = double((pool.position(i) - Vec3(5, 0, 0)).norm());
    ASSERT_LE(r, double(R) * (1 + 1e-6));
    mean += r;
  }
  mean /= n;
  EXPECT_NEAR(mean, 0.75 * double(R), 5 * std::sqrt(3.0 / 80) * double(R) / std::sqrt(double(n)));
}

TEST(Emitter, DiscBoxAndSurfaceEmittersStayOnTheirShapes) {
  ParticlePool disc(1000), box(1000), shell(1000);
  Emitter({.shape = EmitterShape::Disc, .radius = 1, .burst = 1000, .direction = Vec3(0, 0, 1),
           .speed = {0, 0}})
      .emit(disc, Real(1e-3));
  Emitter({.shape = EmitterShape::Box, .halfExtents = Vec3(1, 2, 3), .burst = 1000, .speed = {0, 0}})
      .emit(box, Real(1e-3));
  Emitter({.shape = EmitterShape::SphereSurface, .radius = 3, .burst = 1000, .speed = {0, 0}})
      .emit(shell, Real(1e-3));
  for (std::size_t i = 0; i < 1000; ++i) {
    EXPECT_NEAR(disc.position(i).z(), 0, 1e-6);
    EXPECT_LE(disc.position(i).norm(), 1 + 1e-5);
    EXPECT_TRUE((box.position(i).cwiseAbs().array() <= Vec3(1, 2, 3).array() + Real(1e-5)).all());
    EXPECT_NEAR(shell.position(i).norm(), 3, 1e-5);
  }
}

TEST(Emitter, MeshSurfaceSamplesByArea) {
  // Two triangles, one with three times the area of the other: a quarter of the particles on
  // the small one. Binomial standard error sqrt(p (1-p) / n); allow 5 sigma.
  auto mesh = std::make_shared<TriangleMesh>(
      std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {10, 0, 0}, {13, 0, 0}, {10, 1, 0}},
      std::vector<Triangle>{{0, 1, 2}, {3, 4, 5}});
  const int n = 20000;
  ParticlePool pool(n);
  Emitter({.shape = EmitterShape::MeshSurface, .mesh = mesh, .burst = n, .speed = {1, 1}}).emit(pool, Real(1e-9));
  int small = 0;
  for (std::size_t i = 0; i < pool.size(); ++i) {
    small += pool.position(i).x() < 5;
    EXPECT_NEAR(pool.velocity(i).z(), 1, 1e-4);  // along the triangles' normal +z
  }
  EXPECT_NEAR(double(small) / n, 0.25, 5 * std::sqrt(0.25 * 0.75 / n));
}

TEST(Emitter, RejectsBadSettings) {
  EXPECT_THROW(Emitter({.rate = -1}), InvalidArgument);
  EXPECT_THROW(Emitter({.direction = Vec3::Zero()}), InvalidArgument);
  EXPECT_THROW(Emitter({.speed = {3, 1}}), InvalidArgument);
  EXPECT_THROW(Emitter({.lifetime = {0, 1}}), InvalidArgument);
  EXPECT_THROW(Emitter({.mass = {std::numeric_limits<Real>::quiet_NaN(), 1}}), InvalidArgument);
  EXPECT_THROW(Emitter({.shape = EmitterShape::MeshSurface}), InvalidArgument);
  EXPECT_NO_THROW(Emitter({.lifetime = {std::numeric_limits<Real>::infinity(),
                                        std::numeric_limits<Real>::infinity()}}));
}
