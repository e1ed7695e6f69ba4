// Kinematics of an articulation: joint transforms, link poses, the configuration's derivative
// and its integration (quaternions for spherical and floating joints), point Jacobians.
#pragma once

#include <type_traits>
#include <vector>

#include "inertia/articulation/model.h"

namespace inertia::articulation {

// Vector arguments as Eigen::Ref (any vector or segment, no copy), outside template argument
// deduction: the scalar comes from the model. The stride is spelt out (it is Ref's default for
// a vector): left to the default, it is a dependent expression in these functions' mangled
// names, which clang spells after the first Ref of the unit (in Eigen's IncompleteCholesky,
// `VectorSx`, where the viewer's unit met one first), so a caller's name and the library's
// explicit instantiation differed and did not link.
template <class S>
using ConstRef = std::type_identity_t<Eigen::Ref<const VectorX<S>, 0, Eigen::InnerStride<1>>>;
template <class S>
using Ref = std::type_identity_t<Eigen::Ref<VectorX<S>, 0, Eigen::InnerStride<1>>>;
template <class S>
using Scalar = std::type_identity_t<S>;

/// The joint transform X_J of link `link` at configuration q (Featherstone's jcalc): from the
/// joint frame to the link's frame.
template <class S>
PluckerTransform<S> jointTransform(const Link<S>& link, const ConstRef<S>& q);

/// i_X_lambda(i) for every link: from the parent's (or the base's) frame to link i's,
/// X_J(q_i) X_T(i). `Xup` is resized to the link count.
template <class S>
void parentTransforms(const Model<S>& model, const ConstRef<S>& q,
                      std::vector<PluckerTransform<S>>& Xup);

/// i_X_0 for every link, from the base frame to link i's, given the parent transforms.
template <class S>
void baseTransforms(const Model<S>& model, const std::vector<PluckerTransform<S>>& Xup,
                    std::vector<PluckerTransform<S>>& X0);

/// The pose of link `link`'s frame in the base frame at configuration q.
template <class S>
PluckerTransform<S> linkPose(const Model<S>& model, const ConstRef<S>& q, int link);

/// The world position (m) of `point` (m, in link `link`'s frame).
template <class S>
Vector3<S> pointPosition(const Model<S>& model, const ConstRef<S>& q, int link,
                         const Vector3<S>& point);

/// The Jacobian of a point fixed on a link: [w; v] = J qd, with w the link's angular velocity
/// and v the point's velocity, both in base axes (6 x nv, angular rows first).
template <class S>
Matrix6X<S> pointJacobian(const Model<S>& model, const ConstRef<S>& q, int link,
                          const Vector3<S>& point);

/// dq/dt for velocity qd (size nq): qd itself for revolute and prismatic joints;
/// 1/2 q (0, w) for quaternions (w in the link's axes); R v for a floating base's position.
template <class S>
void configurationDerivative(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                             Ref<S> qdot);

/// q <- q (+) h qd: scalar joints add h qd; quaternions are multiplied by the exact rotation
/// exp(h w / 2) (on the right: w is in the link's axes); a floating base's position moves by
/// h R v with R its orientation at the start of the step (first order, as semi-implicit Euler).
template <class S>
void integrateConfiguration(const Model<S>& model, Ref<S> q, const ConstRef<S>& qd, Scalar<S> h);

/// Scales every quaternion in q to unit length (after an integrator's linear combinations).
template <class S>
void normalizeConfiguration(const Model<S>& model, Ref<S> q);

}  // namespace inertia::articulation
