// Kinetic and potential energy, centre of mass and momentum of an articulation.
#include "inertia/articulation/dynamics.h"

namespace inertia::articulation {

namespace {

// Link velocities in link coordinates (the first pass of rnea without accelerations).
template <class S>
std::vector<Vector6<S>> linkVelocities(const Model<S>& model,
                                       const std::vector<PluckerTransform<S>>& Xup,
                                       const ConstRef<S>& qd) {
  std::vector<Vector6<S>> v(model.linkCount());
  for (int i = 0; i < model.linkCount(); ++i) {
    const Link<S>& L = model.link(i);
    const Vector6<S> vJ =
        model.motionSubspace().middleCols(L.vIndex, L.nv) * qd.segment(L.vIndex, L.nv);
    v[i] = L.parent < 0 ? vJ : Vector6<S>(Xup[i].apply(v[L.parent]) + vJ);
  }
  return v;
}

template <class S>
std::vector<PluckerTransform<S>> worldTransforms(const Model<S>& model, const ConstRef<S>& q) {
  std::vector<PluckerTransform<S>> Xup, X0;
  parentTransforms<S>(model, q, Xup);
  baseTransforms(model, Xup, X0);
  return X0;
}

}  // namespace

template <class S>
S kineticEnergy(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd) {
  std::vector<PluckerTransform<S>> Xup;
  parentTransforms<S>(model, q, Xup);
  const std::vector<Vector6<S>> v = linkVelocities(model, Xup, qd);
  S T = S(0.5) * model.armature().dot(qd.cwiseAbs2());
  for (int i = 0; i < model.linkCount(); ++i) T += S(0.5) * v[i].dot(model.link(i).I * v[i]);
  return T;
}

template <class S>
S potentialEnergy(const Model<S>& model, const ConstRef<S>& q) {
  const std::vector<PluckerTransform<S>> X0 = worldTransforms(model, q);
  S V = S(0);
  for (int i = 0; i < model.linkCount(); ++i) {
    const Vector3<S> c = X0[i].r + X0[i].E.transpose() * model.link(i).centerOfMass;
    V -= model.link(i).mass * model.gravity.dot(c);
  }
  return V;
}

template <class S>
Vector3<S> centerOfMass(const Model<S>& model, const ConstRef<S>& q) {
  const std::vector<PluckerTransform<S>> X0 = worldTransforms(model, q);
  Vector3<S> sum = Vector3<S>::Zero();
  S mass = S(0);
  for (int i = 0; i < model.linkCount(); ++i) {
    sum += model.link(i).mass * (X0[i].r + X0[i].E.transpose() * model.link(i).centerOfMass);
    mass += model.link(i).mass;
  }
  return mass > 0 ? Vector3<S>(sum / mass) : Vector3<S>::Zero();
}

template <class S>
Vector6<S> momentum(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd) {
  std::vector<PluckerTransform<S>> Xup, X0;
  parentTransforms<S>(model, q, Xup);
  baseTransforms(model, Xup, X0);
  const std::vector<Vector6<S>> v = linkVelocities(model, Xup, qd);
  Vector6<S> h = Vector6<S>::Zero();
  for (int i = 0; i < model.linkCount(); ++i)
    h += X0[i].applyTransposeForce(Vector6<S>(model.link(i).I * v[i]));
  return h;
}

#define INERTIA_INSTANTIATE(S)                                                          \
  template S kineticEnergy<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&); \
  template S potentialEnergy<S>(const Model<S>&, const ConstRef<S>&);                   \
  template Vector3<S> centerOfMass<S>(const Model<S>&, const ConstRef<S>&);             \
  template Vector6<S> momentum<S>(const Model<S>&, const ConstRef<S>&, const ConstRef<S>&);
INERTIA_INSTANTIATE(float)
INERTIA_INSTANTIATE(double)
#undef INERTIA_INSTANTIATE

}  // namespace inertia::articulation
