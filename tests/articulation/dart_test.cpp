// Against DART (Debian's libdart-dev), an independent implementation of Featherstone's
// algorithms: the same random trees built as DART skeletons (revolute, prismatic, ball, weld and
// free joints), then the mass matrix, forward dynamics (ABA) and inverse dynamics compared.
// Built only where CMake finds DART.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "dart_model.h"
#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"

using namespace inertia::articulation;
using namespace inertia::articulation::dart_peer;

// Both sides are double-precision recursions over the same data, so they agree to rounding,
// kappa(H) n eps ~ 1e-13 for these trees (measured: 1e-15 to 5e-14); the 1e-9 relative
// is asserted.
TEST(Dart, MassMatrixForwardAndInverseDynamicsAgree) {
  double worst[3] = {0, 0, 0};
  for (bool floating : {false, true}) {
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
      const Model<double> model = randomTree<double>(
          {.links = 10, .floatingBase = floating, .armature = false, .seed = seed});
      VectorX<double> q, qd;
      randomState(model, seed + 50, q, qd);
      const VectorX<double> tau = VectorX<double>::Random(model.nv());
      DartTree d = toDart(model);
      ASSERT_EQ(static_cast<int>(d.skeleton->getNumDofs()), model.nv());
      d.skeleton->setPositions(dartPositions(model, d, q));
      d.skeleton->setVelocities(toDartOrder(d, qd));

      const MatrixX<double> H = crba(model, q);
      MatrixX<double> Hd(model.nv(), model.nv());
      for (int a = 0; a < model.nv(); ++a)
        for (int b = 0; b < model.nv(); ++b)
          Hd(a, b) = d.skeleton->getMassMatrix()(d.dof[a], d.dof[b]);
      worst[0] = std::max(worst[0], (H - Hd).norm() / H.norm());
      EXPECT_LT((H - Hd).norm(), 1e-9 * H.norm()) << "seed " << seed << " floating " << floating;

      d.skeleton->setForces(toDartOrder(d, tau));
      d.skeleton->computeForwardDynamics();
      const VectorX<double> qdd = aba(model, q, qd, tau);
      const Eigen::VectorXd qddDart =
          readDartVector(model.nv(), [&](int i) { return d.skeleton->getAcceleration(i); });
      worst[1] = std::max(worst[1], (toDartOrder(d, qdd) - qddDart).norm() / qdd.norm());
      EXPECT_LT((toDartOrder(d, qdd) - qddDart).norm(), 1e-9 * qdd.norm()) << "seed " << seed;

      d.skeleton->setAccelerations(toDartOrder(d, qdd));
      d.skeleton->computeInverseDynamics();
      const VectorX<double> tauOurs = rnea(model, q, qd, qdd);
      const Eigen::VectorXd tauDart =
          readDartVector(model.nv(), [&](int i) { return d.skeleton->getForce(i); });
      worst[2] = std::max(worst[2], (toDartOrder(d, tauOurs) - tauDart).norm() / tau.norm());
      EXPECT_LT((toDartOrder(d, tauOurs) - tauDart).norm(), 1e-9 * tau.norm()) << "seed " << seed;
    }
  }
  std::printf("against DART, worst relative difference: H %.3g, ABA %.3g, RNEA %.3g\n", worst[0],
              worst[1], worst[2]);
}

// The benchmarks' humanoid (30 DOF, a floating base, chains of small links at shared joint
// origins): its mass matrix and ABA agree with DART's to the same 1e-9, and ABA with CRBA and
// Cholesky, at a random state.
TEST(Dart, HumanoidAgrees) {
  const Model<double> model = humanoid<double>();
  ASSERT_EQ(model.nv(), 30);
  double mass = 0;
  for (const Link<double>& l : model.links()) mass += l.mass;
  EXPECT_NEAR(mass, 56.6, 1e-9);  // the links' masses, summed by hand
  VectorX<double> q, qd;
  randomState(model, 7, q, qd);
  const VectorX<double> tau = VectorX<double>::Random(model.nv());
  DartTree d = toDart(model);
  d.skeleton->setPositions(dartPositions(model, d, q));
  d.skeleton->setVelocities(toDartOrder(d, qd));
  const MatrixX<double> H = crba(model, q);
  MatrixX<double> Hd(model.nv(), model.nv());
  for (int a = 0; a < model.nv(); ++a)
    for (int b = 0; b < model.nv(); ++b) Hd(a, b) = d.skeleton->getMassMatrix()(d.dof[a], d.dof[b]);
  EXPECT_LT((H - Hd).norm(), 1e-9 * H.norm());
  d.skeleton->setForces(toDartOrder(d, tau));
  d.skeleton->computeForwardDynamics();
  const VectorX<double> qdd = aba(model, q, qd, tau);
  const Eigen::VectorXd qddDart =
      readDartVector(model.nv(), [&](int i) { return d.skeleton->getAcceleration(i); });
  EXPECT_LT((toDartOrder(d, qdd) - qddDart).norm(), 1e-9 * qdd.norm());
  EXPECT_LT((qdd - forwardDynamicsCrba(model, q, qd, tau)).norm(), 1e-9 * qdd.norm());
}
