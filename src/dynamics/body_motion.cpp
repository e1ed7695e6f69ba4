#include "body_motion.h"

#include <algorithm>
#include <cmath>

#include "inertia/core/math.h"
#include "integrate.h"

namespace inertia::detail {

namespace {

// Scales v and w down to the body's speed limits; true when w was.
bool capSpeeds(const BodyRecord& b, Vec3& v, Vec3& w) {
  capSpeed(v, b.maxLinearSpeed);
  return capSpeed(w, b.maxAngularSpeed);
}

}  // namespace

void capStartSpeeds(RigidBodyData& D, StepWorkers& workers) {
  const std::size_t n = D.bodies.size();
  workers.parallelFor(n, workers.grainFor(n, 256), [&](std::size_t first, std::size_t last) {
    for (std::size_t bi = first; bi < last; ++bi) {
      BodyRecord& b = D.bodies[bi];
      // A free body's rotation follows its momentum: taken again from the capped w.
      if (b.alive && b.awake && b.type == BodyType::Dynamic && capSpeeds(b, b.v, b.w))
        b.wasFree = false;
    }
  });
}

void finalizeBodies(RigidBodyData& D, const DynamicsSettings& s, Real dt, StepWorkers& workers,
                    void (*beside)(RigidBodyData&)) {
  const std::uint32_t bodyCount = static_cast<std::uint32_t>(D.bodies.size());
  const ContactTuning& tuning = s.contact;
  const Real h = dt / Real(s.substeps);
  // 6. Finalise: write back the solver's motion; free bodies fly with the chosen method.
  const Real sleepSpeed = tuning.sleepSpeed;
  // Each body on its own: the workers take blocks of bodies, and one of them beside(D).
  workers.parallelForBeside(
      [&] { beside(D); }, bodyCount, workers.grainFor(bodyCount, 32),
      [&](std::size_t first, std::size_t last) {
        for (std::uint32_t bi = std::uint32_t(first); bi < last; ++bi) {
          BodyRecord& b = D.bodies[bi];
          if (!b.alive || b.type == BodyType::Static || !b.awake) continue;
          // A driven body: its owner moves it after the step (setDrivenState).
          if (b.group >= 0) continue;
          const int k = D.solverIndex[bi];
          if (k >= 0) {
            const SolverBody& sb = D.solverBodies[static_cast<std::size_t>(k)];
            b.v = sb.v;
            b.w = sb.w;
            // The positions moved at capped speeds (integratePositions); the velocities left by
            // the relax and restitution passes are capped too, so that no step starts beyond
            // the caps (a feather struck by a far-reaching spinning hull).
            if (b.type == BodyType::Dynamic) capSpeeds(b, b.v, b.w);
            b.com = D.startCom[static_cast<std::size_t>(k)] + sb.dp;
            b.pose.q = (sb.dq * D.startRotation[static_cast<std::size_t>(k)]).normalized();
            b.wasFree = false;
          } else if (b.type == BodyType::Kinematic) {
            b.com += dt * b.v;
            b.pose.q = integrateRotationExact(b.pose.q, b.w, dt);
          } else {
            // Free flight: the linear motion by the world's ode method (exact for constant
            // acceleration with rk4 or velocity Verlet), the rotation by the momentum-conserving
            // splitting.
            const Vec3 accel = b.gravityScale * s.gravity + b.invMass * b.force;
            const Real c = b.linearDamping;
            auto a = [&](Real, const auto&, const auto& v, auto out) { out = accel - c * Vec3(v); };
            auto dadv = [c](Real, const auto&, const auto&, const auto& dir, auto out) {
              out = -c * dir;
            };
            // Template arguments spelled out: clang before 17 has no aggregate deduction.
            ode::SecondOrderSystem<decltype(a), ode::ZeroJacobian, decltype(dadv)> system{
                a, ode::ZeroJacobian{}, dadv};
            ode::Workspace<Real>& ws = D.workspaces[bi];
            if (!b.wasFree) ws.resetHistory();
            Vec3 x = b.com;
            Vec3 v = b.v;
            // Carried from step to step while the body flies free, so that rounding in the
            // conversions between w and L does not accumulate.
            const Mat3 R = b.pose.q.toRotationMatrix();
            Vec3 L = b.wasFree ? b.momentum : worldMomentum(R, b.inertiaLocal, b.w);
            Quat principal = b.pose.q * b.principalAxes;
            for (int sub = 0; sub < s.substeps; ++sub) {
              ode::step(s.integrator, system, Real(0), h, x, v, ws);
              L += h * b.torque;
              L *= 1 / (1 + h * b.angularDamping);
              if (b.isotropic)
                // I = c 1 (a sphere, a cube): w = L / c keeps its axis, and the flow is one exact
                // rotation, one sine and cosine where the splitting takes five.
                principal = integrateRotationExact(principal, L / b.inertiaLocal(0, 0), h);
              else
                detail::splitFreeRotation(principal, b.principalMoments, L, h);
            }
            b.com = x;
            b.v = v;
            b.pose.q = (principal * b.principalAxes.conjugate()).normalized();
            if (b.isotropic) {
              b.w = L / b.inertiaLocal(0, 0);
            } else {
              const Vec3 Lb = principal.conjugate() * L;
              b.w = principal * Vec3(Lb.array() / b.principalMoments.array());
            }
            b.momentum = L;
            b.wasFree = true;
            if (capSpeeds(b, b.v, b.w)) b.wasFree = false;
          }
          b.pose.p = b.com - b.pose.q * b.localCom;
          b.force.setZero();
          b.torque.setZero();
          // Sleep timers: the speed of the farthest point bounds how fast anything on the body
          // moves.
          const Real speed = std::max(b.v.norm(), b.w.norm() * b.extent);
          if (!s.sleeping || !b.allowSleep || b.type == BodyType::Kinematic || speed > sleepSpeed)
            b.sleepTime = 0;
          else
            b.sleepTime += dt;
        }
      });
}

}  // namespace inertia::detail
