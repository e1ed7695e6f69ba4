// An articulation stepping in time: the smooth dynamics by ABA under semi-implicit Euler or the
// ode layer's RK4, and the joint-space constraint rows (joint_rows.cpp).
#include "inertia/articulation/articulation.h"

#include <cmath>
#include <string>

#include "inertia/core/error.h"
#include "inertia/ode/explicit.h"

namespace inertia::articulation {

template <class S>
Articulation<S>::Articulation(Model<S> model, const ArticulationSettings<S>& settings)
    : model_(std::move(model)), settings_(settings), ws_(model_) {
  require(settings.constraintIterations >= 1 && settings.constraintIterations <= 1000,
          "articulation: settings.constraintIterations must be in 1..1000");
  require(settings.limitBaumgarte >= 0 && settings.limitBaumgarte <= 1,
          "articulation: settings.limitBaumgarte must be in [0, 1]");
  require(std::isfinite(settings.maxLinearSpeed) && settings.maxLinearSpeed > 0 &&
              std::isfinite(settings.maxAngularSpeed) && settings.maxAngularSpeed > 0,
          "articulation: settings.maxLinearSpeed and maxAngularSpeed must be finite and > 0");
  if (const int i = firstLinkMovingNoMass(model_); i >= 0)
    require(false, "articulation: link " + std::to_string(i) + " '" + model_.link(i).name +
                       "': its joint moves no mass (the link and its descendants are massless)");
  q_ = model_.neutralConfiguration();
  qd_ = tau_ = qdd_ = impulse_ = VectorX<S>::Zero(model_.nv());
  y_.resize(model_.nq() + model_.nv());
  base_ = lowStop_ = highStop_ = VectorX<S>::Zero(model_.nv());
  Minv_.resize(model_.nv(), model_.nv());
  columnReady_.assign(model_.nv(), 0);
  hasLimitRow_.assign(2 * model_.nv(), 0);
  lastImpulse_.assign(std::size_t(kRowKinds * model_.nv()), S(0));
}

template <class S>
void Articulation<S>::setState(const ConstRef<S>& q, const ConstRef<S>& qd) {
  require(q.size() == model_.nq(), "articulation: setState: q has " + std::to_string(q.size()) +
                                       " coordinates, the model " + std::to_string(model_.nq()));
  require(qd.size() == model_.nv(), "articulation: setState: qd has " + std::to_string(qd.size()) +
                                        " coordinates, the model " + std::to_string(model_.nv()));
  require(q.allFinite() && qd.allFinite(), "articulation: setState: q and qd must be finite");
  for (const Link<S>& l : model_.links()) {
    const int i = l.qIndex + (l.joint == JointType::Floating ? 3 : 0);
    if (l.joint == JointType::Spherical || l.joint == JointType::Floating)
      require(q.template segment<4>(i).norm() > S(1e-6),
              "articulation: setState: the quaternion of link '" + l.name + "' is zero");
  }
  q_ = q;
  qd_ = qd;
  normalizeConfiguration<S>(model_, q_);
}

template <class S>
void Articulation<S>::setJointForces(const ConstRef<S>& tau) {
  require(tau.size() == model_.nv() && tau.allFinite(),
          "articulation: setJointForces: tau must be finite with one entry per degree of freedom");
  tau_ = tau;
}

template <class S>
void Articulation<S>::setDriveTarget(int dof, S position, S velocity) {
  require(dof >= 0 && dof < model_.nv(),
          "articulation: setDriveTarget: no degree of freedom " + std::to_string(dof));
  Drive<S> d = model_.drives()[dof];
  d.targetPosition = position;
  d.targetVelocity = velocity;
  model_.setDrive(dof, d);
}

template <class S>
void Articulation<S>::setDrive(int dof, const Drive<S>& drive) {
  model_.setDrive(dof, drive);
}

template <class S>
void Articulation<S>::step(S h) {
  require(std::isfinite(h) && h > 0, "articulation: step: h must be finite and > 0");
  if (settings_.integrator == Integrator::SemiImplicitEuler) {
    smoothVelocity(h);
    buildJointRows(h);
    solveJointRows();
    integratePosition(h);
    return;
  }
  // RK4 predicts (p, qd*); the rows then move the position with the velocity they change:
  // q(t + h) = p (+) h (w - qd*).
  clampSpeeds();
  qStart_ = q_;
  integrateRk4(h);
  qdSmooth_ = qd_;
  aimLimits(qStart_, h, true);
  buildJointRows(h);
  solveJointRows();
  gatherImpulses();
  clampSpeeds();
  qdSmooth_ = qd_ - qdSmooth_;
  integrateConfiguration<S>(model_, q_, qdSmooth_, h);
  recoverLimits();
}

template <class S>
void Articulation<S>::integrateVelocity(S h) {
  smoothVelocity(h);
  buildJointRows(h);
  warmStartJointRows();
}

// Semi-implicit Euler's velocity update by ABA; the substep's rows end q at q + h w.
template <class S>
void Articulation<S>::smoothVelocity(S h) {
  clampSpeeds();  // what the last substep's relax sweeps and contacts left
  qStart_ = q_;
  aba<S>(model_, q_, qd_, tau_, qdd_, ws_);
  qd_ += h * qdd_;
  aimLimits(q_, h, false);
}

template <class S>
void Articulation<S>::integratePosition(S h) {
  clampSpeeds();
  integrateConfiguration<S>(model_, q_, qd_, h);
  recoverLimits();
  gatherImpulses();
  aimLimits(q_, h, false);
  retargetLimitRows();
}

// Each joint's speed scaled down to the settings' guards (a vector's norm, not per component,
// so its direction is kept).
template <class S>
void Articulation<S>::clampSpeeds() {
  // The rule of the bodies' capSpeed (dynamics/integrate.h, private to that layer): a vector
  // whose squared norm overflows is measured by stableNorm, not scaled to zero.
  const auto clamp = [](auto v, S limit) {
    S n = v.norm();
    if (!(n > limit)) return;
    if (std::isinf(n)) n = v.stableNorm();
    v *= limit / n;
  };
  const S linear = settings_.maxLinearSpeed, angular = settings_.maxAngularSpeed;
  for (const Link<S>& l : model_.links()) {
    switch (l.joint) {
      case JointType::Revolute:
        clamp(qd_.segment(l.vIndex, 1), angular);
        break;
      case JointType::Prismatic:
        clamp(qd_.segment(l.vIndex, 1), linear);
        break;
      case JointType::Spherical:
        clamp(qd_.template segment<3>(l.vIndex), angular);
        break;
      case JointType::Floating:  // [w; v]
        clamp(qd_.template segment<3>(l.vIndex), angular);
        clamp(qd_.template segment<3>(l.vIndex + 3), linear);
        break;
      case JointType::Fixed:
        break;
    }
  }
}

// RK4 on y = (q, qd): y' = (dq/dt(q, qd), aba(q, qd, tau)); quaternions renormalised after.
template <class S>
void Articulation<S>::integrateRk4(S h) {
  const int nq = model_.nq(), nv = model_.nv();
  y_ << q_, qd_;
  auto f = [&](S, ode::ConstView<S> y, ode::View<S> dy) {
    configurationDerivative<S>(model_, y.head(nq), y.tail(nv), dy.head(nq));
    aba<S>(model_, y.head(nq), y.tail(nv), tau_, dy.tail(nv), ws_);
  };
  ode::rk4(f, S(0), h, y_, odeWs_);
  q_ = y_.head(nq);
  qd_ = y_.tail(nv);
  normalizeConfiguration<S>(model_, q_);
}

template class Articulation<float>;
template class Articulation<double>;

}  // namespace inertia::articulation
