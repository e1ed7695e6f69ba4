// The particle system's fast paths against the general ones they stand for: the fused
// symplectic Euler kernel against ode::step, the single-plane collision path against the full
// obstacle loop, and the kernels' SSE2 and AVX2 versions against the scalar one. All must give
// the same bits, not merely close values.
#include "particles/fast_path.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "inertia/core/thread_pool.h"
#include "inertia/ode/step.h"
#include "inertia/particles/particle_system.h"

using namespace inertia;

namespace {

// A user field: a spring towards the origin plus a velocity-dependent swirl, per particle.
ForceField customField() {
  return {CustomField{[](const FieldBatch& b) {
    for (std::size_t i = 0; i < b.masses.size(); ++i) {
      const Real* x = &b.positions[3 * i];
      const Real* v = &b.velocities[3 * i];
      b.accelerations[3 * i] += Real(-0.5) * x[0] + Real(0.2) * v[2];
      b.accelerations[3 * i + 1] += Real(-0.5) * x[1];
      b.accelerations[3 * i + 2] += Real(-0.5) * x[2] - Real(0.2) * v[0];
    }
  }}};
}

std::vector<ForceField> someFields() {
  return {{GravityField{}},
          {LinearDragField{Real(0.02)}},
          {LinearDragField{Real(0.05)}, Aabb{Vec3(-1, -1, -1), Vec3(1, 3, 1)}},
          {QuadraticDragField{Real(0.001)}},
          {WindField{Vec3(2, 0, 1), Real(0.01)}},
          {VortexField{.angularSpeed = 3}},
          customField()};
}

ParticlePool::Spawn randomParticle(std::uint64_t& state) {
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return Real(double(state >> 11) * 0x1.0p-53);
  };
  ParticlePool::Spawn s;
  s.position = Vec3(4 * next() - 2, 4 * next(), 4 * next() - 2);
  s.velocity = Vec3(2 * next() - 1, 2 * next() - 1, 2 * next() - 1);
  s.mass = Real(0.001) + Real(0.01) * next();
  s.radius = Real(0.02) * next();
  s.lifetime = std::numeric_limits<Real>::infinity();
  return s;
}

template <class Span>
bool sameBytes(Span a, Span b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

using detail::SimdLevel;

}  // namespace

namespace inertia::detail {
// Names the instruction set in GoogleTest's messages.
void PrintTo(SimdLevel isa, std::ostream* os) { *os << simdLevelName(isa); }
}  // namespace inertia::detail

// Runs a test body with the kernels forced to one instruction set, restoring the choice after.
// Outside the anonymous namespace: the tests derive from it, and in a unity batch, which
// includes this file, GCC rejects a base of internal linkage (-Wsubobject-linkage).
class ParticleSimdTest : public testing::TestWithParam<SimdLevel> {
 protected:
  void SetUp() override {
    previous_ = detail::setParticleSimd(GetParam());
    ASSERT_EQ(detail::particleSimd(), GetParam());
  }
  void TearDown() override { detail::setParticleSimd(previous_); }

 private:
  SimdLevel previous_ = detail::bestParticleSimd();
};

namespace {

std::string isaName(const testing::TestParamInfo<SimdLevel>& info) {
  return detail::simdLevelName(info.param);
}

// Steps a system and the same equations through ode::step(SymplecticEuler) over the whole pool
// with the same acceleration callback, comparing the bits after every step.
void expectFusedIsOdeMethod(const std::vector<ForceField>& fields, std::size_t n) {
  ParticleSystem ps({.capacity = n, .integrator = ode::Method::SymplecticEuler});
  for (const ForceField& f : fields) ps.addField(f);
  std::uint64_t state = 7;
  for (std::size_t i = 0; i < n; ++i) ps.pool().add(randomParticle(state));
  std::vector<Real> x(ps.pool().positions().begin(), ps.pool().positions().end());
  std::vector<Real> v(ps.pool().velocities().begin(), ps.pool().velocities().end());
  std::vector<Real> m(ps.pool().masses().begin(), ps.pool().masses().end());
  auto accel = [&](Real t, ode::ConstView<Real> xs, ode::ConstView<Real> vs, ode::View<Real> a) {
    a.setZero();
    applyFields(fields, FieldBatch{t,
                                   {xs.data(), std::size_t(xs.size())},
                                   {vs.data(), std::size_t(vs.size())},
                                   m,
                                   {a.data(), std::size_t(a.size())}});
  };
  ode::Workspace<Real> ws;
  double time = 0;
  const Real h = Real(1.0 / 60);
  for (int step = 0; step < 20; ++step) {
    ps.step(h);
    ode::step(ode::Method::SymplecticEuler, accel, Real(time), h, std::span<Real>(x),
              std::span<Real>(v), ws);
    time += double(h);
    ASSERT_TRUE(sameBytes(ps.pool().positions(), std::span<Real>(x))) << "positions, step " << step;
    ASSERT_TRUE(sameBytes(ps.pool().velocities(), std::span<Real>(v)))
        << "velocities, step " << step;
  }
}

// The benchmark's scene, small: gravity and linear drag (summed inside the kernel), a ground
// plane and a sphere, particles raining onto both and settling, some dying on the way. 5003
// particles: 3 batches, the last partial and not a multiple of any vector width. The ground
// is tilted on both axes so that every term of the dot products counts (with a zero
// component, a sum's order would not show). `pebbles` small spheres on the ground besides:
// with more than kMaxParticleStepTests obstacles, the near filter leaves the kernel.
ParticleSystem rainScene(int pebbles) {
  ParticleSystem ps({.capacity = 5003, .restitution = Real(0.5), .friction = Real(0.1)});
  ps.addField({GravityField{}});
  ps.addField({LinearDragField{Real(1e-4)}});
  ps.addObstacle(
      {Collider(Shape(Plane{Vec3(Real(0.05), 1, Real(-0.03)).normalized(), 0})), Transform{}});
  ps.addObstacle({Collider(Shape(Sphere{1})), Transform{Vec3(0, 1, 0), Quat::Identity()}});
  for (int k = 0; k < pebbles; ++k)
    ps.addObstacle({Collider(Shape(Sphere{Real(0.1)})),
                    Transform{Vec3(Real(-1.8) + Real(0.3) * Real(k), Real(0.05), Real(1.5)),
                              Quat::Identity()}});
  std::uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return Real(double(state >> 11) * 0x1.0p-53);
  };
  for (std::size_t i = 0; i < ps.pool().capacity(); ++i) {
    ParticlePool::Spawn s;
    s.position = Vec3(4 * next() - 2, 3 * next() + Real(0.01), 4 * next() - 2);
    s.velocity = Vec3(2 * next() - 1, 2 * next() - 1, 2 * next() - 1);
    s.mass = Real(0.001) + Real(0.01) * next();
    s.lifetime = i % 7 == 0 ? 1 + next() : std::numeric_limits<Real>::infinity();
    s.radius = Real(0.02) * next();
    ps.pool().add(s);
  }
  return ps;
}

}  // namespace

TEST_P(ParticleSimdTest, FusedSymplecticEulerIsTheOdeMethodBitForBit) {
  // 5000 particles (3 batches, the last partial) under every built-in field kind and a user
  // field: the system's fused kernel (reading the fields' accelerations from a buffer) against
  // ode::step(SymplecticEuler) over the whole pool with the same acceleration callback. Fields
  // act per particle, so batching changes nothing.
  expectFusedIsOdeMethod(someFields(), 5000);
}

TEST_P(ParticleSimdTest, FieldsSummedInTheKernelAreTheOdeMethodBitForBit) {
  // Gravity and linear drag without regions are summed inside the kernel, in order from zero:
  // a gravity after a drag, and two of each, exercise the order. 5001 particles: a tail of 1.
  expectFusedIsOdeMethod({{LinearDragField{Real(0.02)}},
                          {GravityField{}},
                          {LinearDragField{Real(0.003)}},
                          {GravityField{Vec3(Real(0.3), Real(-0.1), Real(0.7))}}},
                         5001);
  expectFusedIsOdeMethod({{GravityField{}}, {LinearDragField{Real(0.05)}}}, 4099);
}

TEST_P(ParticleSimdTest, EveryInstructionSetGivesTheScalarBits) {
  // The benchmark's scene under the forced set against the same scene under the scalar
  // kernels, at one and two threads: positions, velocities, ages and deaths to the bit. With
  // 2 obstacles the kernel filters them, with 12 collideObstacles() does.
  for (int pebbles : {0, 10}) {
    ParticleSystem wide = rainScene(pebbles);
    const SimdLevel forced = detail::particleSimd();
    detail::setParticleSimd(SimdLevel::Scalar);
    ParticleSystem scalar = rainScene(pebbles);
    ThreadPool one(1), two(2);
    for (int step = 0; step < 90; ++step) {
      detail::setParticleSimd(forced);
      wide.step(Real(1.0 / 60), step % 2 ? &two : &one);
      detail::setParticleSimd(SimdLevel::Scalar);
      scalar.step(Real(1.0 / 60), &one);
      ASSERT_EQ(wide.pool().size(), scalar.pool().size()) << "step " << step;
      ASSERT_TRUE(sameBytes(wide.pool().positions(), scalar.pool().positions())) << "step " << step;
      ASSERT_TRUE(sameBytes(wide.pool().velocities(), scalar.pool().velocities()))
          << "step " << step;
      ASSERT_TRUE(sameBytes(wide.pool().ages(), scalar.pool().ages())) << "step " << step;
    }
    detail::setParticleSimd(forced);
    // The scene must reach the paths it is meant to cover: deaths, and particles on the ground.
    EXPECT_LT(wide.pool().size(), wide.pool().capacity());
    std::size_t settled = 0;
    for (std::size_t i = 0; i < wide.pool().size(); ++i)
      settled += wide.pool().position(i).y() < Real(0.05) ? 1 : 0;
    EXPECT_GT(settled, wide.pool().size() / 2) << pebbles << " pebbles";
  }
}

TEST_P(ParticleSimdTest, SinglePlanePathIsTheFullObstacleLoopBitForBit) {
  // The short path runs when a system has exactly one plane. The same system with the ground
  // plane given twice (one right after the other) takes the full loop everywhere; the duplicate
  // changes nothing there (its hit is never strictly earlier, and after the first one's push-out
  // the particle is r + skin away from it), so both must agree to the bit: bouncing, resting,
  // sliding, and near the sphere and the box.
  auto make = [](bool twice, const Vec3& normal) {
    ParticleSystem ps({.capacity = 6000, .restitution = Real(0.6), .friction = Real(0.3)});
    ps.addEmitter({.shape = EmitterShape::Sphere,
                   .pose = {Vec3(0, 2, 0), Quat::Identity()},
                   .radius = 1,
                   .rate = 4000,
                   .burst = 3000,
                   .spread = Real(0.5),
                   .speed = {0, 4},
                   .lifetime = {1, 4},
                   .size = {Real(0.005), Real(0.05)},
                   .seed = 11});
    ps.addField({GravityField{}});
    ps.addObstacle({Collider(Shape(Plane{normal, Real(-0.1)})), Transform{}});
    if (twice) ps.addObstacle({Collider(Shape(Plane{normal, Real(-0.1)})), Transform{}});
    ps.addObstacle({Collider(Shape(Sphere{Real(0.4)})),
                    Transform{Vec3(Real(0.5), Real(0.3), 0), Quat::Identity()}});
    ps.addObstacle({Collider(Shape(Box{Vec3(Real(0.3), Real(0.2), Real(0.5))})),
                    Transform{Vec3(-1, Real(0.1), 0),
                              Quat(Eigen::AngleAxis<Real>(Real(0.4), Vec3::UnitY()))}});
    return ps;
  };
  // Tilted about one axis, then about two (every term of the dot products non-zero, so that
  // a sum in another order would show).
  for (const Vec3& normal :
       {Vec3(Real(0.1), 1, 0).normalized(), Vec3(Real(0.1), 1, Real(-0.07)).normalized()}) {
    ParticleSystem fast = make(false, normal), full = make(true, normal);
    for (int step = 0; step < 240; ++step) {
      fast.step(Real(1.0 / 60));
      full.step(Real(1.0 / 60));
      ASSERT_EQ(fast.pool().size(), full.pool().size());
      ASSERT_TRUE(sameBytes(fast.pool().positions(), full.pool().positions())) << "step " << step;
      ASSERT_TRUE(sameBytes(fast.pool().velocities(), full.pool().velocities())) << "step " << step;
    }
    EXPECT_GT(fast.pool().size(), 3000u);
  }
}

// Every set this build and processor support (the double build and processors without AVX2
// have fewer), so that no test runs a set it cannot force.
std::vector<SimdLevel> supportedIsas() {
  std::vector<SimdLevel> out;
  for (SimdLevel isa : {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2})
    if (isa <= detail::bestParticleSimd()) out.push_back(isa);
  return out;
}

INSTANTIATE_TEST_SUITE_P(ParticleFastPaths, ParticleSimdTest, testing::ValuesIn(supportedIsas()),
                         isaName);
