// Featherstone's algorithms (ABA forward dynamics, RNEA inverse dynamics, CRBA mass matrix) in
// double, against DART 6.12 (Debian's libdart-dev) in the same run, on a 7-DOF arm (the Panda's
// kinematics), a 100-link revolute chain, a 30-DOF humanoid (floating base) and a 30-link random
// tree with every joint type.
// Each figure is the best of 5 rounds of about 0.1 s of calls, in microseconds per call, at one
// of two random states per model, alternated. Both sides recompute their kinematics in every call:
// ours from (q, qd, tau) with a reused Workspace; DART after setPositions/setVelocities invalidate
// its caches (setPositions, then computeForwardDynamics, computeInverseDynamics or getMassMatrix).
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "dart_model.h"
#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"

using namespace inertia::articulation;
using Clock = std::chrono::steady_clock;

namespace {

volatile double sink = 0;  // keeps results alive

// Best of 5 rounds, microseconds per call.
double microseconds(const std::function<double()>& call) {
  double best = 1e30;
  for (int round = 0; round < 5; ++round) {
    int calls = 0;
    const auto t0 = Clock::now();
    double elapsed = 0;
    while (elapsed < 0.1) {
      for (int i = 0; i < 32; ++i) sink = sink + call();
      calls += 32;
      elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    best = std::min(best, elapsed / calls * 1e6);
  }
  return best;
}

void run(const std::string& name, const Model<double>& model) {
  // Two states, alternated, so that no side can skip work on an unchanged state (DART returns
  // at once from setPositions with the positions it holds, and keeps its mass matrix).
  VectorX<double> q[2], qd[2];
  randomState(model, 7, q[0], qd[0]);
  randomState(model, 8, q[1], qd[1]);
  const VectorX<double> tau = VectorX<double>::Random(model.nv());
  const VectorX<double> qddIn = VectorX<double>::Random(model.nv());
  Workspace<double> ws(model);
  VectorX<double> out(model.nv());

  dart_peer::DartTree d = dart_peer::toDart(model);
  const Eigen::VectorXd dq[2] = {dart_peer::dartPositions(model, d, q[0]),
                                 dart_peer::dartPositions(model, d, q[1])};
  const Eigen::VectorXd dqd[2] = {dart_peer::toDartOrder(d, qd[0]),
                                  dart_peer::toDartOrder(d, qd[1])};
  const Eigen::VectorXd dtau = dart_peer::toDartOrder(d, tau);
  const Eigen::VectorXd dqdd = dart_peer::toDartOrder(d, qddIn);
  dart::dynamics::Skeleton& s = *d.skeleton;
  int k = 0;

  const double abaOurs = microseconds([&] {
    k ^= 1;
    aba<double>(model, q[k], qd[k], tau, out, ws);
    return out(0);
  });
  const double abaDart = microseconds([&] {
    k ^= 1;
    s.setPositions(dq[k]);
    s.setVelocities(dqd[k]);
    s.setForces(dtau);
    s.computeForwardDynamics();
    return s.getAcceleration(0);
  });
  const double rneaOurs = microseconds([&] {
    k ^= 1;
    rnea<double>(model, q[k], qd[k], qddIn, out, ws);
    return out(0);
  });
  const double rneaDart = microseconds([&] {
    k ^= 1;
    s.setPositions(dq[k]);
    s.setVelocities(dqd[k]);
    s.setAccelerations(dqdd);
    s.computeInverseDynamics();
    return s.getForce(0);
  });
  const double crbaOurs = microseconds([&] {
    k ^= 1;
    crba<double>(model, q[k], ws);
    return ws.H(0, 0);
  });
  const double crbaDart = microseconds([&] {
    k ^= 1;
    s.setPositions(dq[k]);
    return s.getMassMatrix()(0, 0);
  });
  std::printf(
      "%-22s %4d dof  ABA %8.2f us (DART %8.2f, %.2fx)  RNEA %8.2f us (DART %8.2f, "
      "%.2fx)  CRBA %8.2f us (DART %8.2f, %.2fx)\n",
      name.c_str(), model.nv(), abaOurs, abaDart, abaOurs / abaDart, rneaOurs, rneaDart,
      rneaOurs / rneaDart, crbaOurs, crbaDart, crbaOurs / crbaDart);
}

}  // namespace

int main() {
  std::printf(
      "Inertia's articulation algorithms against DART %s, microseconds per call "
      "(ratio: Inertia / DART, lower is faster)\n",
      DART_VERSION);
  run("7-DOF arm (Panda)", sevenDofArm<double>());
  run("100-link chain", pendulumChain<double>(100, 0.1, 1.0));
  run("30-DOF humanoid", humanoid<double>());
  run("30-link random tree", randomTree<double>({.links = 30, .armature = false, .seed = 3}));
  return 0;
}
