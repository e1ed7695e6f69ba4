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
// In a World the rows are not a stage of their own: they are swept in the contacts' solve and
// relax iterations, warm-started from the last substep (link_response.h, integrateVelocity).
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
  /// Gauss-Seidel sweeps over the rows per step() (1..1000). In a World the rows are swept
  /// with the contacts instead, once per solver and relax iteration (the world's iterations).
  int constraintIterations = 20;
  S limitBaumgarte = S(0.2);  ///< Fraction of a limit's violation removed per step (0..1).
  /// Speed guards, as a rigid body's (BodySettings): before each velocity and each position
  /// update (so whatever a world's relax sweeps and contacts left too) every joint's
  /// speed is scaled down to at most these, the norm of a spherical joint's or a floating
  /// base's angular velocity (rad/s, > 0) and of a prismatic joint's or a floating base's
  /// linear velocity (m/s, > 0). They keep semi-implicit Euler's explicit Coriolis and
  /// centrifugal terms stable (|qd| h of order one diverges) when a link is struck by
  /// something fast; unlike the joints' velocity limits they are not constraint rows.
  S maxLinearSpeed = S(400);
  S maxAngularSpeed = S(200);
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

  /// The step in parts, for a world that solves its contacts and these rows together (World's
  /// substeps, link_response.h), under semi-implicit Euler whatever the integrator:
  ///   factorMassMatrix(q()) once per step: H (CRBA) and its Cholesky factor, whose inverse
  ///     the joint rows use (and the world's contacts, massMatrixFactor()) until the next call;
  ///   per substep: integrateVelocity(h), the smooth velocity update by ABA, then the joint rows
  ///     from the substep's start position; sweepJointRows() in each solver iteration, beside
  ///     the contacts; integratePosition(h), q (+)= h qd, the recovery of violated limits, and
  ///     the limit rows aimed from the new position, for sweepJointRows() in relax iterations.
  /// With semi-implicit Euler, step(h) is these with constraintIterations sweeps. No checks.
  void factorMassMatrix(const VectorX<S>& q);
  const Eigen::LLT<MatrixX<S>>& massMatrixFactor() const { return ws_.llt; }
  void integrateVelocity(S h);
  void sweepJointRows();
  void integratePosition(S h);
  /// Adds `delta` to the velocity qd (a contact's impulse through the mass matrix). No checks.
  void addVelocity(const ConstRef<S>& delta) { qd_ += delta; }
  /// Gravity in the base frame (m/s^2).
  void setGravity(const Vector3<S>& g) { model_.gravity = g; }

  /// Generalised impulses (N m s or N s) of the joint rows in the last step (in a world, the
  /// last substep's solve), per dof.
  const VectorX<S>& constraintImpulses() const { return impulse_; }

 private:
  void integrateRk4(S h);
  void smoothVelocity(S h);
  void aimLimits(const VectorX<S>& from, S h, bool afterSmooth);
  void buildJointRows(S h);
  bool addLimitRows();
  void retargetLimitRows();
  typename MatrixX<S>::ColXpr inverseMassColumn(int dof);
  void sweepRows();
  void solveJointRows();
  void gatherImpulses();
  void recoverLimits();
  void clampSpeeds();

  Model<S> model_;
  ArticulationSettings<S> settings_;
  VectorX<S> q_, qd_, tau_, qdd_, impulse_;
  VectorX<S> qStart_, qdSmooth_;  // q at the step's start; qd after the smooth stage
  // Per dof: a scalar dof ends the step at base_ + h_ w; its limits' stops.
  VectorX<S> base_, lowStop_, highStop_;
  S h_ = 0;
  Workspace<S> ws_;
  ode::Workspace<S> odeWs_;
  VectorX<S> y_;  // (q, qd) stacked for RK4
  // Each row's effect, which with its dof names it from one substep to the next (warm start).
  enum RowKind { kDamping, kFriction, kDrive, kSpeedMax, kSpeedMin, kLower, kUpper, kRowKinds };
  struct Row {
    int dof = 0;
    RowKind kind = kDamping;
    S target = 0;      // velocity the row drives its dof to
    S softness = 0;    // gamma: 0 for a hard row
    S lo = 0, hi = 0;  // impulse bounds
    S lambda = 0;
  };
  Row limitRow(int dof, RowKind kind) const;
  void warmStartJointRows();
  std::vector<Row> rows_;
  MatrixX<S> Minv_;  // column k: H^-1 e_k, once columnReady_[k]
  std::vector<char> columnReady_;
  std::vector<char> hasLimitRow_;  // per dof: lower, upper
  std::vector<S> lastImpulse_;     // per kind and dof: the last substep's lambda
};

}  // namespace inertia::articulation
