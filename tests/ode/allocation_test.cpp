// No heap allocation once the workspace is warm: every fixed-step method except the
// matrix-free backward Euler (Eigen's Krylov solvers allocate their work vectors per solve), and
// both adaptive controllers' tryStep.
//
// Eigen's own allocations are caught by EIGEN_RUNTIME_NO_MALLOC, with eigen_assert turned into
// an exception so that it also fires in release builds; everything else (std containers,
// strings) by counting the global operator new. Both macros must precede every Eigen include,
// which is why this is a separate test executable.
#include <stdexcept>
#define EIGEN_RUNTIME_NO_MALLOC
#define eigen_assert(x)                                    \
  do {                                                     \
    if (!(x)) throw std::logic_error("eigen_assert: " #x); \
  } while (false)

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <span>
#include <vector>

#include "inertia/ode/ode.h"

namespace {
std::atomic<long> gNewCalls{0};
int* volatile gSink = nullptr;  // keeps the detector's own allocation from being elided
}  // namespace

void* operator new(std::size_t size) {
  ++gNewCalls;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// The array forms too: a sanitizer runtime defines its own, which would bypass the count.
void* operator new[](std::size_t size) { return operator new(size); }
// The replacement pair malloc/free is consistent; GCC's heuristic does not see the pairing.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace ode = inertia::ode;

namespace {

constexpr int kParticles = 1000;

void spring(float, ode::ConstView<float> x, ode::ConstView<float> v, ode::View<float> a) {
  a = -x - 0.1f * v;
}
void decay(float t, ode::ConstView<float> y, ode::View<float> dy) { dy = -y * (1 + 0.1f * t); }

/// Runs `body` once to warm up, then 50 more times with every heap allocation forbidden;
/// returns the number of allocations seen (Eigen's throw from inside `body`).
template <class Body>
long allocationsAfterWarmUp(Body body) {
  body();
  const long before = gNewCalls.load();
  Eigen::internal::set_is_malloc_allowed(false);
  try {
    for (int i = 0; i < 50; ++i) body();
  } catch (const std::logic_error& e) {
    Eigen::internal::set_is_malloc_allowed(true);
    ADD_FAILURE() << "Eigen allocated: " << e.what();
    return -1;
  }
  Eigen::internal::set_is_malloc_allowed(true);
  return gNewCalls.load() - before;
}

}  // namespace

class NoAllocation : public testing::TestWithParam<ode::Method> {};

TEST_P(NoAllocation, GenericStepOnSpansAfterWarmUp) {
  std::vector<float> x(kParticles, 1.0f), v(kParticles, 0.5f);
  ode::Workspace<float> ws(kParticles);
  float t = 0;
  EXPECT_EQ(allocationsAfterWarmUp([&] {
              ode::step(GetParam(), spring, t, 0.01f, std::span<float>(x), std::span<float>(v), ws);
              t += 0.01f;
            }),
            0);
}

INSTANTIATE_TEST_SUITE_P(ExplicitAndSecondOrder, NoAllocation,
                         testing::Values(ode::Method::ExplicitEuler, ode::Method::Midpoint,
                                         ode::Method::Heun, ode::Method::Rk4, ode::Method::Verlet,
                                         ode::Method::VelocityVerlet, ode::Method::SymplecticEuler),
                         [](const testing::TestParamInfo<ode::Method>& info) {
                           return std::string(ode::methodName(info.param));
                         });

TEST(NoAllocation, FirstOrderSteppersAfterWarmUp) {
  std::vector<float> y(kParticles, 1.0f);
  ode::Workspace<float> ws(kParticles);
  EXPECT_EQ(allocationsAfterWarmUp([&] { ode::rk4(decay, 0.0f, 0.01f, std::span<float>(y), ws); }),
            0);
  EXPECT_EQ(allocationsAfterWarmUp(
                [&] { ode::dormandPrince5(decay, 0.0f, 0.01f, std::span<float>(y), ws); }),
            0);
}

TEST(NoAllocation, DenseBackwardEulerAfterWarmUp) {
  // Small systems: Eigen's blocked LU works on the stack below EIGEN_STACK_ALLOCATION_LIMIT.
  Eigen::VectorXd y = Eigen::VectorXd::Ones(8);
  ode::Workspace<double> ws(8);
  const auto f = [](double, ode::ConstView<double> yy, ode::View<double> dy) { dy = -yy; };
  const auto jacobian = [](double, ode::ConstView<double>, ode::JacobianView<double> J) {
    J.diagonal().setConstant(-1);
  };
  EXPECT_EQ(allocationsAfterWarmUp([&] { ode::backwardEuler(f, jacobian, 0.0, 0.1, y, ws); }), 0);
}

TEST(NoAllocation, AdaptiveTryStepAfterWarmUp) {
  std::vector<float> y(kParticles, 1.0f);
  ode::DormandPrince45<float> dp;
  ode::StepDoubling<float> sd;
  float t = 0;
  EXPECT_EQ(allocationsAfterWarmUp([&] {
              const auto attempt = dp.tryStep(decay, t, std::span<float>(y), 0.01f);
              if (attempt.accepted) t += 0.01f;
            }),
            0);
  EXPECT_EQ(allocationsAfterWarmUp([&] { sd.tryStep(decay, t, std::span<float>(y), 0.01f); }), 0);
}

// The detector works: a step that does allocate is caught.
TEST(NoAllocation, DetectorCatchesAnAllocation) {
  long count = 0;
  EXPECT_NONFATAL_FAILURE(
      count = allocationsAfterWarmUp([] { Eigen::VectorXd v = Eigen::VectorXd::Ones(10); }),
      "Eigen allocated");
  EXPECT_EQ(count, -1);
  EXPECT_GT(allocationsAfterWarmUp([] {
              gSink = new int[10];
              delete[] gSink;
            }),
            0);
}
