// Featherstone's articulated-body algorithm (Rigid Body Dynamics Algorithms, Table 7.1):
// forward dynamics in three passes over the tree, O(n).
#include "inertia/articulation/dynamics.h"

namespace inertia::articulation {

template <class S>
void aba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd, const ConstRef<S>& tau,
         Ref<S> qdd, Workspace<S>& ws) {
  const int n = model.linkCount();
  const Matrix6X<S>& Sm = model.motionSubspace();
  if (static_cast<int>(ws.IA.size()) != n || ws.U.cols() != model.nv()) ws.resize(model);
  parentTransforms<S>(model, q, ws.Xup);

  // Pass 1, root to leaves: velocities, velocity-product accelerations c_i = v_i x vJ (c_J = 0
  // for these joints), rigid-body inertias and bias forces pA_i = v_i x* I_i v_i.
  for (int i = 0; i < n; ++i) {
    const Link<S>& L = model.link(i);
    const Vector6<S> vJ = Sm.middleCols(L.vIndex, L.nv) * qd.segment(L.vIndex, L.nv);
    ws.v[i] = L.parent < 0 ? vJ : Vector6<S>(ws.Xup[i].apply(ws.v[L.parent]) + vJ);
    ws.c[i] = crossMotion(ws.v[i], vJ);
    ws.IA[i] = L.I;
    ws.pA[i] = crossForce(ws.v[i], Vector6<S>(L.I * ws.v[i]));
  }

  // Pass 2, leaves to root: articulated inertias IA_i and bias forces pA_i, each handed to the
  // parent through the joint (Ia = IA - U D^-1 U^T, pa = pA + Ia c + U D^-1 u).
  for (int i = n - 1; i >= 0; --i) {
    const Link<S>& L = model.link(i);
    const int k = L.vIndex, m = L.nv;
    Matrix6<S> Ia;
    Vector6<S> pa;
    if (m == 1) {  // revolute and prismatic joints: D and u are scalars
      const Vector6<S> U = ws.IA[i] * Sm.col(k);
      const S Dinv = S(1) / (Sm.col(k).dot(U) + model.armature()(k));
      ws.U.col(k) = U;
      ws.Dinv[i].setConstant(1, 1, Dinv);
      ws.u(k) = tau(k) - Sm.col(k).dot(ws.pA[i]);
      if (L.parent < 0) continue;
      Ia = ws.IA[i] - (Dinv * U) * U.transpose();
      pa = ws.pA[i] + Ia * ws.c[i] + (Dinv * ws.u(k)) * U;
    } else {
      auto Si = Sm.middleCols(k, m);
      auto Ui = ws.U.middleCols(k, m);
      Ui.noalias() = ws.IA[i] * Si;
      typename Workspace<S>::SmallMatrix D = Si.transpose() * Ui;
      D.diagonal() += model.armature().segment(k, m);
      ws.Dinv[i] = D.inverse();
      ws.u.segment(k, m) = tau.segment(k, m) - Si.transpose() * ws.pA[i];
      if (L.parent < 0) continue;
      Ia = ws.IA[i] - Ui * ws.Dinv[i] * Ui.transpose();
      pa = ws.pA[i] + Ia * ws.c[i] + Ui * (ws.Dinv[i] * ws.u.segment(k, m));
    }
    ws.IA[L.parent] += ws.Xup[i].transformInertiaToParent(Ia);
    ws.pA[L.parent] += ws.Xup[i].applyTransposeForce(pa);
  }

  // Pass 3, root to leaves: accelerations, the base accelerating at -g.
  Vector6<S> a0 = Vector6<S>::Zero();
  a0.template tail<3>() = -model.gravity;
  for (int i = 0; i < n; ++i) {
    const Link<S>& L = model.link(i);
    const int k = L.vIndex, m = L.nv;
    const Vector6<S> aParent = ws.Xup[i].apply(L.parent < 0 ? a0 : ws.a[L.parent]) + ws.c[i];
    if (m == 1) {
      qdd(k) = ws.Dinv[i](0, 0) * (ws.u(k) - ws.U.col(k).dot(aParent));
      ws.a[i] = aParent + Sm.col(k) * qdd(k);
      continue;
    }
    qdd.segment(k, m) =
        ws.Dinv[i] * (ws.u.segment(k, m) - ws.U.middleCols(k, m).transpose() * aParent);
    ws.a[i] = aParent + Sm.middleCols(k, m) * qdd.segment(k, m);
  }
}

template <class S>
VectorX<S> aba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
               const ConstRef<S>& tau) {
  Workspace<S> ws(model);
  VectorX<S> qdd(model.nv());
  aba<S>(model, q, qd, tau, qdd, ws);
  return qdd;
}

#define INERTIA_INSTANTIATE(S)                                                        \
  template void aba<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&,       \
                       const ConstRef<S>&, Ref<S>, Workspace<S>&);                    \
  template VectorX<S> aba<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&, \
                             const ConstRef<S>&);
INERTIA_INSTANTIATE(float)
INERTIA_INSTANTIATE(double)
#undef INERTIA_INSTANTIATE

}  // namespace inertia::articulation
