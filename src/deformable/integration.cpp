// The integration stage of a deformable's step: the ode layer's explicit methods on the whole
// vertex state, or Baraff and Witkin's implicit step (implicit_euler.cpp).
#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

#include "deformable/scratch.h"
#include "deformable/spring_forces.h"
#include "dynamics/integrate.h"
#include "inertia/ode/step.h"

namespace inertia {

namespace {

// The drag coefficient k (kg/s) of a field linear in v (F = -k v + ...: linear drag and wind),
// which the implicit step's dF/dv holds; none for the other fields.
std::optional<Real> linearCoefficient(const ForceField& f) {
  if (const auto* drag = std::get_if<LinearDragField>(&f.field)) return drag->k;
  if (const auto* wind = std::get_if<WindField>(&f.field)) return wind->k;
  return std::nullopt;
}

// A field's linear drag coefficient on a vertex at x, for the implicit step's dF/dv (0 outside
// its region or for fields that are not linear in v).
Real linearDamping(const ForceField& f, const Vec3& x) {
  if (f.region && !f.region->contains(x)) return 0;
  return linearCoefficient(f).value_or(Real(0));
}

// A guard against float's range, not a cap: 1000 times a rigid body's default speed cap (m/s).
// An explicit method on springs too stiff for its step diverges (why implicit Euler is the
// default): unguarded, the vertices overflowed within a few steps and the collision stages met
// infinities (the world fuzz target's world-deformable-explicit-runaway inputs: a ray cast, a
// tree update, a body struck to 1e22 m/s). A vertex's speed and its displacement over the step
// are held to this bound, so a divergence grows positions at most linearly and stays finite.
// No sane motion comes near it, and the implicit step does not diverge.
constexpr Real kRunawaySpeed = 4e5;

void guardRunaways(std::vector<Real>& x, const std::vector<Real>& start, std::vector<Real>& v,
                   Real h) {
  for (std::size_t i = 0; 3 * i < v.size(); ++i) {
    Eigen::Map<Vec3> vi(&v[3 * i]), xi(&x[3 * i]);
    Vec3 u = vi;
    if (detail::capSpeed(u, kRunawaySpeed)) vi = u;
    const Vec3 from = Eigen::Map<const Vec3>(&start[3 * i]);
    Vec3 d = xi - from;
    if (detail::capSpeed(d, h * kRunawaySpeed)) xi = from + d;
  }
}
}  // namespace

// x'' = (fields + springs) / m, pinned vertices held (a = 0, and their v is 0).
void Deformable::integrateExplicit(Real h) {
  Scratch& w = *scratch_;
  const std::size_t n3 = x_.size();
  w.forces.resize(n3);
  auto accel = [&](Real t, ode::ConstView<Real> x, ode::ConstView<Real> v, ode::View<Real> a) {
    a.setZero();
    applyFields(fields_,
                FieldBatch{t, {x.data(), n3}, {v.data(), n3}, masses_, {a.data(), n3},
                           dragStep(settings_.integrator, h)});
    std::fill(w.forces.begin(), w.forces.end(), Real(0));
    detail::addSpringForces<Real>(springs_, broken_, x.data(), v.data(), w.forces.data());
    // Attachments: their points move on at their velocities from the step's start.
    for (std::size_t k = 0; k < attachments_.size(); ++k) {
      const Attachment& at = attachments_[k];
      const Vec3 p = attachmentPositions_[k] + (t - Real(time_)) * attachmentVelocities_[k];
      Eigen::Map<Vec3>(&w.forces[3 * at.vertex]) -=
          at.stiffness * (Eigen::Map<const Vec3>(x.data() + 3 * at.vertex) - p) +
          at.damping *
              (Eigen::Map<const Vec3>(v.data() + 3 * at.vertex) - attachmentVelocities_[k]);
    }
    for (std::size_t i = 0; i < n3; ++i)
      a[Eigen::Index(i)] =
          pinned_[i / 3] ? Real(0) : a[Eigen::Index(i)] + w.forces[i] / masses_[i / 3];
  };
  w.startVelocity = v_;
  ode::step(settings_.integrator, accel, Real(time_), h, x_, v_, w.workspace);
  // Past its stability limit (w h > 2 for symplectic Euler) an explicit method diverges: the
  // step is undone rather than let infinities and NaN in, and reported.
  const bool finite = std::all_of(x_.begin(), x_.end(), [](Real c) { return std::isfinite(c); }) &&
                      std::all_of(v_.begin(), v_.end(), [](Real c) { return std::isfinite(c); });
  lastSolve_ = ImplicitSolveReport{};
  if (!finite) {
    x_ = w.start;
    v_ = w.startVelocity;
    lastSolve_.converged = false;
  }
  guardRunaways(x_, w.start, v_, h);
}

void Deformable::integrateImplicit(Real h, detail::StepWorkers& workers) {
  Scratch& w = *scratch_;
  const std::size_t n = vertexCount(), n3 = x_.size();
  w.fieldAcceleration.assign(n3, Real(0));
  // Linear drag and wind enter dF/dv below, which holds them at any rate (FieldBatch::step 0);
  // the other fields act explicitly within the step, a quadratic drag's or a vortex's rate
  // capped at 1 / h: uncapped, a cloth of 0.4 g vertices in a quadratic drag of 1 reached 1e23 m
  // within 3 s. Field by field, in order, as applyFields sums them: the same bits.
  for (const ForceField& f : fields_)
    applyFields({&f, 1}, FieldBatch{Real(time_), x_, v_, masses_, w.fieldAcceleration,
                                    linearCoefficient(f) ? 0 : h});
  w.fieldDamping.assign(n, Real(0));
  for (const ForceField& f : fields_)
    for (std::size_t i = 0; i < n; ++i)
      w.fieldDamping[i] += linearDamping(f, Eigen::Map<const Vec3>(&x_[3 * i]));
  w.attachments.clear();
  for (std::size_t k = 0; k < attachments_.size(); ++k) {
    const Attachment& a = attachments_[k];
    w.attachments.push_back(
        {a.vertex, double(a.stiffness), double(a.damping),
         (attachmentPositions_[k] + h * attachmentVelocities_[k]).cast<double>(),
         attachmentVelocities_[k].cast<double>()});
  }
  const detail::ImplicitEulerInput input{.springs = springs_,
                                         .broken = broken_,
                                         .masses = masses_,
                                         .pinned = pinned_,
                                         .fieldAcceleration = w.fieldAcceleration,
                                         .fieldDamping = w.fieldDamping,
                                         .attachments = w.attachments,
                                         .contacts = w.contacts,
                                         .tolerance = settings_.solverTolerance,
                                         .maxIterations = settings_.solverMaxIterations,
                                         .maxNewtonIterations = settings_.newtonMaxIterations,
                                         .linearSolver = settings_.linearSolver};
  lastSolve_ = w.implicit.step(input, h, x_, v_, workers);
}

}  // namespace inertia
