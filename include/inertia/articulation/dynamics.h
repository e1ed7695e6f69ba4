// Dynamics of an articulation in reduced coordinates, as plain functions over (model, q, qd),
// named after Featherstone's Rigid Body Dynamics Algorithms (2008):
//
//   aba                  forward dynamics, the articulated-body algorithm (Table 7.1), O(n)
//   rnea                 inverse dynamics, recursive Newton-Euler (Table 5.1), O(n)
//   crba                 the joint-space mass matrix H, composite-rigid-body algorithm (Table 6.2)
//   forwardDynamicsCrba  forward dynamics by H qdd = tau - C, C from rnea, Cholesky (Eigen's LLT)
//   kineticEnergy, potentialEnergy, centerOfMass, momentum
//
// Joint armature is part of the mass matrix (H_ii += armature_i) in all three algorithms.
// Gravity enters as a fictitious acceleration -g of the base (Featherstone section 5.3).
// Each function has a form that takes a Workspace, which then holds every intermediate, so that
// repeated calls allocate nothing, and a convenience form that makes its own.
#pragma once

#include <Eigen/Cholesky>
#include <vector>

#include "inertia/articulation/kinematics.h"

namespace inertia::articulation {

/// Scratch and intermediate results of the algorithms, sized for one model.
template <class S>
struct Workspace {
  using SmallMatrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;

  Workspace() = default;
  explicit Workspace(const Model<S>& model) { resize(model); }
  void resize(const Model<S>& model);

  std::vector<PluckerTransform<S>> Xup;  ///< i_X_lambda(i)
  std::vector<Vector6<S>> v, a, c, pA, f;
  std::vector<Matrix6<S>> IA;  ///< Articulated (ABA) or composite (CRBA) inertias.
  std::vector<SmallMatrix> Dinv;
  Matrix6X<S> U;  ///< U_i = IA_i S_i, columns as in motionSubspace().
  VectorX<S> u, bias, rhs;
  MatrixX<S> H;                ///< The mass matrix of the last crba call.
  Eigen::LLT<MatrixX<S>> llt;  ///< Its Cholesky factor (forwardDynamicsCrba).
};

/// Forward dynamics by the articulated-body algorithm: qdd (size nv) from q, qd and the joint
/// forces tau (N m or N, size nv).
template <class S>
void aba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd, const ConstRef<S>& tau,
         Ref<S> qdd, Workspace<S>& ws);
template <class S>
VectorX<S> aba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
               const ConstRef<S>& tau);

/// Inverse dynamics by recursive Newton-Euler: the joint forces tau that give accelerations qdd.
template <class S>
void rnea(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
          const ConstRef<S>& qdd, Ref<S> tau, Workspace<S>& ws);
template <class S>
VectorX<S> rnea(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                const ConstRef<S>& qdd);

/// The joint-space mass matrix H(q) (nv x nv, symmetric positive definite) by the
/// composite-rigid-body algorithm, left in ws.H.
template <class S>
void crba(const Model<S>& model, const ConstRef<S>& q, Workspace<S>& ws);
template <class S>
MatrixX<S> crba(const Model<S>& model, const ConstRef<S>& q);

/// Forward dynamics by H qdd = tau - C(q, qd), C = rnea(q, qd, 0), with H from crba and solved
/// by its Cholesky factorisation (left in ws.llt).
template <class S>
void forwardDynamicsCrba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                         const ConstRef<S>& tau, Ref<S> qdd, Workspace<S>& ws);
template <class S>
VectorX<S> forwardDynamicsCrba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                               const ConstRef<S>& tau);

/// Kinetic energy (J), sum of 1/2 v_i . I_i v_i over the links plus 1/2 armature qd^2, which is
/// 1/2 qd . H qd.
template <class S>
S kineticEnergy(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd);

/// Potential energy in the model's gravity (J), -sum m_i g . c_i (zero at the base origin).
template <class S>
S potentialEnergy(const Model<S>& model, const ConstRef<S>& q);

/// Centre of mass of the links (m, base frame).
template <class S>
Vector3<S> centerOfMass(const Model<S>& model, const ConstRef<S>& q);

/// Spatial momentum of the links in base coordinates about the base origin: [angular momentum
/// (kg m^2/s); linear momentum (kg m/s)].
template <class S>
Vector6<S> momentum(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd);

}  // namespace inertia::articulation
