// Sizing of the algorithms' scratch for one model.
#include "inertia/articulation/dynamics.h"

namespace inertia::articulation {

template <class S>
void Workspace<S>::resize(const Model<S>& model) {
  const auto n = static_cast<std::size_t>(model.linkCount());
  Xup.resize(n);
  for (auto* vs : {&v, &a, &c, &pA, &f}) vs->resize(n);
  IA.resize(n);
  Dinv.resize(n);
  U.resize(6, model.nv());
  u.resize(model.nv());
  bias.resize(model.nv());
  rhs.resize(model.nv());
  H.resize(model.nv(), model.nv());
  // A factor of nothing, so that the factor has a status: Eigen leaves a default-constructed
  // LLT's info uninitialised, and copying the workspace (an articulation in a snapshot) before
  // the first factorisation would read it.
  llt.compute(MatrixX<S>::Zero(0, 0));
}

template struct Workspace<float>;
template struct Workspace<double>;

}  // namespace inertia::articulation
