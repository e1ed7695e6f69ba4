// A two-link arm in reduced coordinates: the dynamics functions, then a drive swinging the elbow
// to its target under gravity. The README's Articulations section shows this code.
#include <inertia/articulation/articulation.h>

#include <cmath>
#include <cstdio>

using namespace inertia::articulation;

int main() {
  Model<double> model;            // templated on the scalar: float or double
  model.gravity = {0, 0, -9.81};  // in the base frame (m/s^2)
  int upper = model.addLink({.name = "upper",
                             .joint = {.type = JointType::Revolute,
                                       .axis = {0, 1, 0},
                                       .lower = -1,
                                       .upper = 1,
                                       .damping = 0.1},
                             .inertia = {.mass = 2, .centerOfMass = {0, 0, -0.25}}});
  model.addLink(
      {.name = "lower",
       .parent = upper,
       .joint = {.originPosition = {0, 0, -0.5},
                 .axis = {0, 1, 0},
                 .drive = {.stiffness = 100, .damping = 20, .targetPosition = 0.5, .maxForce = 50}},
       .inertia = {.mass = 1, .centerOfMass = {0, 0, -0.25}}});

  VectorX<double> q = model.neutralConfiguration(), qd = VectorX<double>::Zero(model.nv());
  VectorX<double> qdd = aba(model, q, qd, VectorX<double>::Zero(model.nv()));  // forward dynamics
  MatrixX<double> H = crba(model, q);                                          // mass matrix
  VectorX<double> tau = rnea(model, q, qd, qdd);                               // inverse dynamics
  std::printf("H = [%.3f %.3f; %.3f %.3f], |rnea(aba(0)) - 0| = %.1e\n", H(0, 0), H(0, 1), H(1, 0),
              H(1, 1), tau.norm());

  Articulation<double> arm(model, {.integrator = Integrator::SemiImplicitEuler});
  for (int i = 0; i < 3000; ++i) arm.step(0.001);
  std::printf("after 3 s: shoulder %.3f rad, elbow %.3f rad (drive target 0.5)\n", arm.q()(0),
              arm.q()(1));
  // The drive holds the elbow near its target against gravity's pull on the lower link.
  return std::abs(arm.q()(1) - 0.5) < 0.1 && tau.norm() < 1e-12 ? 0 : 1;
}
