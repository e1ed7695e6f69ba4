// The composite-rigid-body algorithm (Rigid Body Dynamics Algorithms, Table 6.2): the
// joint-space mass matrix H(q), and forward dynamics by its Cholesky factorisation.
#include "inertia/articulation/dynamics.h"

namespace inertia::articulation {

template <class S>
void crba(const Model<S>& model, const ConstRef<S>& q, Workspace<S>& ws) {
  const int n = model.linkCount();
  const Matrix6X<S>& Sm = model.motionSubspace();
  if (static_cast<int>(ws.IA.size()) != n || ws.H.rows() != model.nv()) ws.resize(model);
  parentTransforms<S>(model, q, ws.Xup);

  // Composite inertias IC_i: link i and everything below it, in link i's coordinates.
  for (int i = 0; i < n; ++i) ws.IA[i] = model.link(i).I;
  for (int i = n - 1; i >= 0; --i)
    if (model.link(i).parent >= 0)
      ws.IA[model.link(i).parent] += ws.Xup[i].transformInertiaToParent(ws.IA[i]);

  // H_ii = S_i^T IC_i S_i; F = IC_i S_i carried up to each ancestor j gives H_ji = S_j^T F.
  ws.H.setZero();
  for (int i = 0; i < n; ++i) {
    const Link<S>& L = model.link(i);
    const int k = L.vIndex, m = L.nv;
    if (m == 0) continue;
    Eigen::Matrix<S, 6, Eigen::Dynamic, 0, 6, 6> F = ws.IA[i] * Sm.middleCols(k, m);
    // Symmetrised: S^T (IC S) is symmetric only to rounding for multi-dof joints.
    const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> Hii =
        Sm.middleCols(k, m).transpose() * F;
    ws.H.block(k, k, m, m) = S(0.5) * (Hii + Hii.transpose());
    ws.H.diagonal().segment(k, m) += model.armature().segment(k, m);
    for (int j = i; model.link(j).parent >= 0;) {
      for (int col = 0; col < m; ++col)
        F.col(col) = ws.Xup[j].applyTransposeForce(Vector6<S>(F.col(col)));
      j = model.link(j).parent;
      const Link<S>& P = model.link(j);
      if (P.nv == 0) continue;
      ws.H.block(P.vIndex, k, P.nv, m) = Sm.middleCols(P.vIndex, P.nv).transpose() * F;
      ws.H.block(k, P.vIndex, m, P.nv) = ws.H.block(P.vIndex, k, P.nv, m).transpose();
    }
  }
}

template <class S>
MatrixX<S> crba(const Model<S>& model, const ConstRef<S>& q) {
  Workspace<S> ws(model);
  crba<S>(model, q, ws);
  return ws.H;
}

template <class S>
void forwardDynamicsCrba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                         const ConstRef<S>& tau, Ref<S> qdd, Workspace<S>& ws) {
  crba<S>(model, q, ws);
  // C(q, qd): the joint forces that give zero acceleration (gravity, Coriolis, centrifugal).
  ws.rhs.setZero(model.nv());
  rnea<S>(model, q, qd, ws.rhs, ws.bias, ws);
  ws.rhs = tau - ws.bias;
  ws.llt.compute(ws.H);
  qdd = ws.llt.solve(ws.rhs);
}

template <class S>
VectorX<S> forwardDynamicsCrba(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                               const ConstRef<S>& tau) {
  Workspace<S> ws(model);
  VectorX<S> qdd(model.nv());
  forwardDynamicsCrba<S>(model, q, qd, tau, qdd, ws);
  return qdd;
}

#define INERTIA_INSTANTIATE(S)                                                                  \
  template void crba<S>(const Model<S>&, const ConstRef<S>&, Workspace<S>&);                    \
  template MatrixX<S> crba<S>(const Model<S>&, const ConstRef<S>&);                             \
  template void forwardDynamicsCrba<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&, \
                                       const ConstRef<S>&, Ref<S>, Workspace<S>&);              \
  template VectorX<S> forwardDynamicsCrba<S>(const Model<S>&, const ConstRef<S>&,               \
                                             const ConstRef<S>&, const ConstRef<S>&);
INERTIA_INSTANTIATE(float)
INERTIA_INSTANTIATE(double)
#undef INERTIA_INSTANTIATE

}  // namespace inertia::articulation
