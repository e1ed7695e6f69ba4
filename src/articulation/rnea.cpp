// Recursive Newton-Euler inverse dynamics (Rigid Body Dynamics Algorithms, Table 5.1), O(n).
#include "inertia/articulation/dynamics.h"

namespace inertia::articulation {

template <class S>
void rnea(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
          const ConstRef<S>& qdd, Ref<S> tau, Workspace<S>& ws) {
  const int n = model.linkCount();
  const Matrix6X<S>& Sm = model.motionSubspace();
  if (static_cast<int>(ws.f.size()) != n) ws.resize(model);
  parentTransforms<S>(model, q, ws.Xup);

  // Forward pass: velocities, accelerations (the base at -g) and the net forces each link needs.
  Vector6<S> a0 = Vector6<S>::Zero();
  a0.template tail<3>() = -model.gravity;
  for (int i = 0; i < n; ++i) {
    const Link<S>& L = model.link(i);
    const int k = L.vIndex, m = L.nv;
    const Vector6<S> vJ = Sm.middleCols(k, m) * qd.segment(k, m);
    const Vector6<S> vParent = L.parent < 0 ? Vector6<S>::Zero() : ws.v[L.parent];
    const Vector6<S> aParent = L.parent < 0 ? a0 : ws.a[L.parent];
    ws.v[i] = ws.Xup[i].apply(vParent) + vJ;
    ws.a[i] = ws.Xup[i].apply(aParent) + Sm.middleCols(k, m) * qdd.segment(k, m) +
              crossMotion(ws.v[i], vJ);
    ws.f[i] = L.I * ws.a[i] + crossForce(ws.v[i], Vector6<S>(L.I * ws.v[i]));
  }

  // Backward pass: each joint transmits its link's force plus its children's.
  for (int i = n - 1; i >= 0; --i) {
    const Link<S>& L = model.link(i);
    const int k = L.vIndex, m = L.nv;
    tau.segment(k, m) = Sm.middleCols(k, m).transpose() * ws.f[i] +
                        model.armature().segment(k, m).cwiseProduct(qdd.segment(k, m));
    if (L.parent >= 0) ws.f[L.parent] += ws.Xup[i].applyTransposeForce(ws.f[i]);
  }
}

template <class S>
VectorX<S> rnea(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                const ConstRef<S>& qdd) {
  Workspace<S> ws(model);
  VectorX<S> tau(model.nv());
  rnea<S>(model, q, qd, qdd, tau, ws);
  return tau;
}

#define INERTIA_INSTANTIATE(S)                                                         \
  template void rnea<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&,       \
                        const ConstRef<S>&, Ref<S>, Workspace<S>&);                    \
  template VectorX<S> rnea<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&, \
                              const ConstRef<S>&);
INERTIA_INSTANTIATE(float)
INERTIA_INSTANTIATE(double)
#undef INERTIA_INSTANTIATE

}  // namespace inertia::articulation
