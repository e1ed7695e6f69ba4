// Valid but extreme worlds (issue 21): checks that each stays finite and finishes, and prints
// what it reached, for the limits documented in README (Robustness):
//   - N boxes (100,000 by default) in a lattice over a plane, a few steps;
//   - a 1 mm sphere resting on a 1 km box;
//   - a box of density ratio 100, 1000 and 1e4 resting on another, with each solver;
//   - a ball and a box dropped at dt 1e-5 s and 0.1 s.
//   inertia_extremes [BODIES]
// Exit status 1 when a world turned non-finite.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "inertia/world/world.h"
#include "thread_sweep.h"

namespace {

using namespace inertia;
using Clock = std::chrono::steady_clock;

bool finite(const World& w) {
  for (BodyId b : w.rigidBodies().bodies())
    if (!w.transform(b).p.allFinite() || !w.linearVelocity(b).allFinite()) return false;
  return true;
}

void addGround(World& w) {
  const BodyId g = w.createBody({.type = BodyType::Static});
  w.addShape(g, Plane{Vec3::UnitY(), 0});
}

double seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// Steps n times; false (and a message) when something turned non-finite.
bool run(World& w, Real dt, int n, const char* what) {
  for (int i = 0; i < n; ++i) {
    w.step(dt);
    if (!finite(w)) {
      std::printf("%s: NOT FINITE at step %d\n", what, i);
      return false;
    }
  }
  return true;
}

bool manyBodies(int n) {
  const auto t0 = Clock::now();
  World w({.threads = 0});
  addGround(w);
  const int side = int(std::ceil(std::cbrt(double(n))));
  for (int k = 0; k < n; ++k) {
    const Vec3 p(Real(1.1) * Real(k % side), Real(0.5) + Real(1.1) * Real(k / side % side),
                 Real(1.1) * Real(k / (side * side)));
    const BodyId b = w.createBody({.position = p});
    w.addShape(b, Box{Vec3::Constant(Real(0.5))});
  }
  const double created = seconds(t0);
  const auto t1 = Clock::now();
  const bool ok = run(w, Real(1) / 60, 5, "many bodies");
  std::printf("%d boxes: created in %.1f s, 5 steps in %.1f s (%.2f s a step), finite %d\n", n,
              created, seconds(t1), seconds(t1) / 5, ok);
  return ok;
}

bool smallOnLarge() {
  World w({.sleeping = false});
  addGround(w);
  const BodyId big = w.createBody({.position = Vec3(0, 1000, 0)});
  w.addShape(big, Box{Vec3::Constant(1000)});
  const BodyId small = w.createBody({.position = Vec3(0, Real(2000.01), 0)});
  w.addShape(small, Sphere{Real(1e-3)});
  const bool ok = run(w, Real(1) / 60, 600, "1 mm on 1 km");
  std::printf(
      "1 mm sphere dropped 1 cm onto a 1 km box, 10 s: centre %.3g m above the top "
      "(radius 1e-3), finite %d\n",
      double(w.transform(small).p.y()) - 2000, ok);
  return ok;
}

bool massRatios() {
  bool ok = true;
  for (SolverType solver :
       {SolverType::SoftStep, SolverType::Pgs, SolverType::LcpDantzig, SolverType::LcpLemke}) {
    for (Real ratio : {Real(100), Real(1000), Real(1e4)}) {
      World w({.solver = {.type = solver}, .sleeping = false});
      addGround(w);
      const BodyId light = w.createBody({.position = Vec3(0, Real(0.5), 0)});
      w.addShape(light, Box{Vec3::Constant(Real(0.5))}, Material{.density = 1});
      const BodyId heavy = w.createBody({.position = Vec3(0, Real(1.5), 0)});
      w.addShape(heavy, Box{Vec3::Constant(Real(0.5))}, Material{.density = ratio});
      ok = run(w, Real(1) / 60, 300, "mass ratio") && ok;
      std::printf(
          "%-12s mass ratio %6g: heavy box's centre at %.4f m after 5 s (1.5 resting "
          "on the light one)\n",
          solverName(solver).data(), double(ratio), double(w.transform(heavy).p.y()));
    }
  }
  return ok;
}

bool timeSteps() {
  bool ok = true;
  for (Real dt : {Real(1e-5), Real(0.1)}) {
    World w({.dt = dt, .sleeping = false});
    addGround(w);
    const BodyId ball = w.createBody({.position = Vec3(0, 1, 0)});
    w.addShape(ball, Sphere{Real(0.5)}, Material{.restitution = Real(0.5)});
    const BodyId box = w.createBody({.position = Vec3(0, Real(2.2), 0)});
    w.addShape(box, Box{Vec3::Constant(Real(0.5))});
    const auto t0 = Clock::now();
    ok = run(w, dt, int(std::lround(2 / dt)), "time step") && ok;
    std::printf(
        "dt %g s: ball and box dropped, 2 s in %.1f s: ball at %.4f m, box at %.4f m "
        "(0.5 and 1.5 resting)\n",
        double(dt), seconds(t0), double(w.transform(ball).p.y()), double(w.transform(box).p.y()));
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2) {
    std::fprintf(stderr, "inertia_extremes: one argument at most (BODIES), got %d\n", argc - 1);
    return 2;
  }
  // 0: skip the many-bodies world.
  const long n =
      argc > 1 ? bench::parseCount("inertia_extremes: BODIES", argv[1], 0, 10'000'000) : 100000;
  bool ok = smallOnLarge();
  ok = massRatios() && ok;
  ok = timeSteps() && ok;
  if (n > 0) ok = manyBodies(int(n)) && ok;
  return ok ? 0 : 1;
}
