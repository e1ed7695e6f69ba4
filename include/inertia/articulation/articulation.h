// An articulation that steps in time: a Model, its state (q, qd), joint forces, and the joint
// effects that are not part of the rigid-body dynamics: limits, damping, Coulomb friction,
// velocity limits and PD drives.
//
// A step has two stages:
//  1. The smooth dynamics (gravity, Coriolis and centrifugal forces, the applied joint forces)
//     by the articulated-body algorithm, integrated by semi-implicit Euler (qd += h qdd, then
//     q (+)= h qd) or by the ode layer's classic RK4 on the state (q, qd).
//  2. The joint-space constraint stage (joint_rows.cpp): one row per joint effect, each acting on
//     one degree of freedom with an impulse bounded as the effect demands, solved by projected
//     Gauss-Seidel through the mass matrix (CRBA and its Cholesky factor):
//       - limits, unilateral: the step ends at the limit, not beyond (an inelastic stop); a
//         joint found beyond its limit goes no deeper and its position is moved back by
//         `limitBaumgarte` of the violation per step (no velocity is left to carry it on);
//         limits that the other rows push a dof past join the rows, and the sweeps repeat;
//       - Coulomb friction: the velocity is driven to zero by an impulse of at most friction h;
//       - velocity limits: |qd| <= limit;
//       - damping and drives as soft rows, implicit in the end-of-step velocity and position
//         (Catto's soft constraints: the force k (q_target - q(t + h)) + c (v_target - qd(t + h)),
//         at most maxForce): unconditionally stable whatever the gains.
//     The stage is first order whatever the integrator, and is skipped when no row is active.
#pragma once

#include "inertia/articulation/dynamics.h"
#include "inertia/ode/workspace.h"

namespace inertia::articulation {

enum class Integrator {
  SemiImplicitEuler,  ///< Symplectic: bounded energy error, O(h) per unit time.
  Rk4,                ///< The ode layer's classic Runge-Kutta, O(h^4) per unit time.
};

template <class S>
struct ArticulationSettings {
  Integrator integrator = Integrator::SemiImplicitEuler;
  int constraintIterations = 20;  ///< Gauss-Seidel sweeps over the rows (1..1000).
  S limitBaumgarte = S(0.2);      ///< Fraction of a limit's violation removed per step (0..1).
};

template <class S>
class Articulation {
 public:
  /// Takes the model; starts at its neutral configuration at rest. Throws InvalidArgument for
  /// bad settings.
  explicit Articulation(Model<S> model, const ArticulationSettings<S>& settings = {});

  const Model<S>& model() const { return model_; }
  const VectorX<S>& q() const { return q_; }
  const VectorX<S>& qd() const { return qd_; }

  /// Sets the state. Throws InvalidArgument for wrong sizes, non-finite values or zero
  /// quaternions (which are normalised).
  void setState(const ConstRef<S>& q, const ConstRef<S>& qd);
  /// Joint forces (N m or N) applied at every step until changed.
  void setJointForces(const ConstRef<S>& tau);
  /// Moves the drive of degree of freedom `dof` (rad and rad/s, or m and m/s).
  void setDriveTarget(int dof, S position, S velocity = S(0));
  /// Replaces the drive of `dof` (revolute and prismatic joints only).
  void setDrive(int dof, const Drive<S>& drive);

  /// Advances by h seconds (h > 0 and finite, else InvalidArgument).
  void step(S h);

  /// The step in two halves, for a world that solves contacts between them (World's substeps,
  /// link_response.h): the smooth velocity update by ABA (semi-implicit Euler whatever the
  /// integrator), then the position update and the joint-space constraint stage. With
  /// semi-implicit Euler, integrateVelocity(h); integratePosition(h) is step(h). No checks.
  void integrateVelocity(S h);
  void integratePosition(S h);
  /// Adds `delta` to the velocity qd (a contact's impulse through the mass matrix). No checks.
  void addVelocity(const ConstRef<S>& delta) { qd_ += delta; }
  /// Gravity in the base frame (m/s^2).
  void setGravity(const Vector3<S>& g) { model_.gravity = g; }

  /// Generalised impulses (N m s or N s) of the last step's constraint stage, per dof.
  const VectorX<S>& constraintImpulses() const { return impulse_; }

 private:
  void integrateSmooth(S h);
  void buildJointRows(S h);
  bool addLimitRows(S h);
  void recoverLimits();
  void solveJointRows(S h);

  Model<S> model_;
  ArticulationSettings<S> settings_;
  VectorX<S> q_, qd_, tau_, qdd_, impulse_;
  VectorX<S> qStart_, qdSmooth_;  // q at the step's start; qd after the smooth stage
  Workspace<S> ws_;
  ode::Workspace<S> odeWs_;
  VectorX<S> y_;  // (q, qd) stacked for RK4
  struct Row {
    int dof = 0;
    S target = 0;      // velocity the row drives its dof to
    S softness = 0;    // gamma: 0 for a hard row
    S lo = 0, hi = 0;  // impulse bounds
    S lambda = 0;
  };
  std::vector<Row> rows_;
  MatrixX<S> Minv_;                // columns H^-1 e_dof for the rows' dofs
  std::vector<int> column_;        // dof -> column of Minv_, -1 when none
  std::vector<char> hasLimitRow_;  // per dof: lower, upper
};

}  // namespace inertia::articulation
