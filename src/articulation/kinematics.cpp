// Joint transforms (Featherstone's jcalc), link poses, point Jacobians and the configuration's
// derivative and integration.
#include "inertia/articulation/kinematics.h"

#include <cmath>

namespace inertia::articulation {

namespace {

template <class S>
Quaternion<S> quaternionAt(const ConstRef<S>& q, int i) {
  return Quaternion<S>(q(i), q(i + 1), q(i + 2), q(i + 3));
}

template <class S>
void storeQuaternion(Ref<S> q, int i, const Quaternion<S>& r) {
  q(i) = r.w();
  q(i + 1) = r.x();
  q(i + 2) = r.y();
  q(i + 3) = r.z();
}

// The rotation exp(theta / 2) of a rotation vector theta (rad).
template <class S>
Quaternion<S> exponential(const Vector3<S>& theta) {
  const S angle = theta.norm();
  if (angle < std::numeric_limits<S>::epsilon())
    return Quaternion<S>(S(1), theta.x() / 2, theta.y() / 2, theta.z() / 2).normalized();
  return Quaternion<S>(Eigen::AngleAxis<S>(angle, theta / angle));
}

// dq/dt = 1/2 q (0, w), w in the rotated frame's axes.
template <class S>
Vector6<S> quaternionRate(const Quaternion<S>& q, const Vector3<S>& w) {
  const Quaternion<S> d = q * Quaternion<S>(S(0), w.x(), w.y(), w.z());
  Vector6<S> out = Vector6<S>::Zero();
  out.template head<4>() << d.w() / 2, d.x() / 2, d.y() / 2, d.z() / 2;
  return out;
}

}  // namespace

template <class S>
PluckerTransform<S> jointTransform(const Link<S>& link, const ConstRef<S>& q) {
  PluckerTransform<S> X;
  const int i = link.qIndex;
  switch (link.joint) {
    case JointType::Revolute:
      X.E = Eigen::AngleAxis<S>(q(i), link.axis).toRotationMatrix().transpose();
      break;
    case JointType::Prismatic:
      X.r = link.axis * q(i);
      break;
    case JointType::Spherical:
      X.E = quaternionAt<S>(q, i).normalized().toRotationMatrix().transpose();
      break;
    case JointType::Floating:
      X.E = quaternionAt<S>(q, i + 3).normalized().toRotationMatrix().transpose();
      X.r = q.template segment<3>(i);
      break;
    case JointType::Fixed:
      break;
  }
  return X;
}

template <class S>
void parentTransforms(const Model<S>& model, const ConstRef<S>& q,
                      std::vector<PluckerTransform<S>>& Xup) {
  Xup.resize(model.linkCount());
  for (int i = 0; i < model.linkCount(); ++i)
    Xup[i] = jointTransform<S>(model.link(i), q) * model.link(i).Xtree;
}

template <class S>
void baseTransforms(const Model<S>& model, const std::vector<PluckerTransform<S>>& Xup,
                    std::vector<PluckerTransform<S>>& X0) {
  X0.resize(model.linkCount());
  for (int i = 0; i < model.linkCount(); ++i) {
    const int p = model.link(i).parent;
    X0[i] = p < 0 ? Xup[i] : Xup[i] * X0[p];
  }
}

template <class S>
PluckerTransform<S> linkPose(const Model<S>& model, const ConstRef<S>& q, int link) {
  PluckerTransform<S> X;
  for (int i = link; i >= 0; i = model.link(i).parent)
    X = X * (jointTransform<S>(model.link(i), q) * model.link(i).Xtree);
  return X;
}

template <class S>
Vector3<S> pointPosition(const Model<S>& model, const ConstRef<S>& q, int link,
                         const Vector3<S>& point) {
  const PluckerTransform<S> X0 = linkPose<S>(model, q, link);
  return X0.r + X0.E.transpose() * point;
}

template <class S>
Matrix6X<S> pointJacobian(const Model<S>& model, const ConstRef<S>& q, int link,
                          const Vector3<S>& point) {
  std::vector<PluckerTransform<S>> Xup, X0;
  parentTransforms<S>(model, q, Xup);
  baseTransforms(model, Xup, X0);
  const Vector3<S> p = X0[link].r + X0[link].E.transpose() * point;
  Matrix6X<S> J = Matrix6X<S>::Zero(6, model.nv());
  for (int j = link; j >= 0; j = model.link(j).parent) {
    for (int k = model.link(j).vIndex; k < model.link(j).vIndex + model.link(j).nv; ++k) {
      // The joint's motion in base coordinates, [w; velocity of the base origin], moved to p.
      const Vector6<S> m = X0[j].applyInverse(model.motionSubspace().col(k));
      J.col(k) << m.template head<3>(), m.template tail<3>() + m.template head<3>().cross(p);
    }
  }
  return J;
}

template <class S>
void configurationDerivative(const Model<S>& model, const ConstRef<S>& q, const ConstRef<S>& qd,
                             Ref<S> qdot) {
  for (const Link<S>& l : model.links()) {
    const int i = l.qIndex, k = l.vIndex;
    switch (l.joint) {
      case JointType::Revolute:
      case JointType::Prismatic:
        qdot(i) = qd(k);
        break;
      case JointType::Spherical:
        qdot.template segment<4>(i) =
            quaternionRate<S>(quaternionAt<S>(q, i), qd.template segment<3>(k)).template head<4>();
        break;
      case JointType::Floating: {
        const Quaternion<S> r = quaternionAt<S>(q, i + 3);
        qdot.template segment<3>(i) = r.normalized() * Vector3<S>(qd.template segment<3>(k + 3));
        qdot.template segment<4>(i + 3) =
            quaternionRate<S>(r, qd.template segment<3>(k)).template head<4>();
        break;
      }
      case JointType::Fixed:
        break;
    }
  }
}

template <class S>
void integrateConfiguration(const Model<S>& model, Ref<S> q, const ConstRef<S>& qd, Scalar<S> h) {
  for (const Link<S>& l : model.links()) {
    const int i = l.qIndex, k = l.vIndex;
    switch (l.joint) {
      case JointType::Revolute:
      case JointType::Prismatic:
        q(i) += h * qd(k);
        break;
      case JointType::Spherical: {
        const Vector3<S> w = qd.template segment<3>(k);
        storeQuaternion<S>(q, i, (quaternionAt<S>(q, i) * exponential<S>(h * w)).normalized());
        break;
      }
      case JointType::Floating: {
        const Quaternion<S> r = quaternionAt<S>(q, i + 3).normalized();
        const Vector3<S> w = qd.template segment<3>(k), v = qd.template segment<3>(k + 3);
        q.template segment<3>(i) += h * (r * v);
        storeQuaternion<S>(q, i + 3, (r * exponential<S>(h * w)).normalized());
        break;
      }
      case JointType::Fixed:
        break;
    }
  }
}

template <class S>
void normalizeConfiguration(const Model<S>& model, Ref<S> q) {
  for (const Link<S>& l : model.links()) {
    if (l.joint == JointType::Spherical) q.template segment<4>(l.qIndex).normalize();
    if (l.joint == JointType::Floating) q.template segment<4>(l.qIndex + 3).normalize();
  }
}

#define INERTIA_INSTANTIATE(S)                                                                     \
  template PluckerTransform<S> jointTransform<S>(const Link<S>&, const ConstRef<S>&);              \
  template void parentTransforms<S>(const Model<S>&, const ConstRef<S>&,                           \
                                    std::vector<PluckerTransform<S>>&);                            \
  template void baseTransforms<S>(const Model<S>&, const std::vector<PluckerTransform<S>>&,        \
                                  std::vector<PluckerTransform<S>>&);                              \
  template PluckerTransform<S> linkPose<S>(const Model<S>&, const ConstRef<S>&, int);              \
  template Vector3<S> pointPosition<S>(const Model<S>&, const ConstRef<S>&, int,                   \
                                       const Vector3<S>&);                                         \
  template Matrix6X<S> pointJacobian<S>(const Model<S>&, const ConstRef<S>&, int,                  \
                                        const Vector3<S>&);                                        \
  template void configurationDerivative<S>(const Model<S>&, const ConstRef<S>&,                    \
                                           const ConstRef<S>&, Ref<S>);                            \
  template void integrateConfiguration<S>(const Model<S>&, Ref<S>, const ConstRef<S>&, Scalar<S>); \
  template void normalizeConfiguration<S>(const Model<S>&, Ref<S>);
INERTIA_INSTANTIATE(float)
INERTIA_INSTANTIATE(double)
#undef INERTIA_INSTANTIATE

}  // namespace inertia::articulation
