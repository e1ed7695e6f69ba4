#include "deformable/implicit_euler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deformable/spring_forces.h"

namespace inertia::detail {

namespace {

template <class T>
Eigen::Ref<const Eigen::Vector3d> seg(const Eigen::VectorXd& v, T i) {
  return v.segment<3>(3 * Eigen::Index(i));
}

SurrogateSpring surrogate(const Spring& s, const Eigen::Vector3d& u0) {
  return {double(s.stiffness), double(s.restLength), u0};
}

// Armijo's sufficient decrease (Nocedal and Wright, 3.1) and the line search's floor.
constexpr double kArmijo = 1e-4;
constexpr double kSmallestStep = 1e-8;
// Automatic picks the direct solve where its factors hold at most this many times the
// matrices' non-zeros: strands and ropes (0.9 for the benchmark's hair), not sheets or volumes
// (6.3 for 40 x 40 cloth cells, 9.4 for 100 x 100, where PCG was 4 times faster at 40).
constexpr double kDirectFill = 2;
// The relative tolerance the contacts' modes are settled at (ImplicitEuler::step).
constexpr double kModeTolerance = 1e-3;

// Items per block of a parallel pass, and springs per partial sum of Psi's change (fixed, never
// derived from the number of workers: it sets the sum's association).
constexpr std::size_t kSpringGrain = 1024, kVertexGrain = 512, kChunk = 1024;

}  // namespace

namespace {

// f(i) for i in [0, count), in blocks of `grain` on the step's workers (in sequence without).
template <class F>
void parallelItems(StepWorkers* workers, std::size_t count, std::size_t grain, F&& f) {
  const auto block = [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) f(i);
  };
  if (workers)
    workers->parallelFor(count, grain,
                         [&](std::size_t first, std::size_t last) { block(first, last); });
  else
    block(0, count);
}

}  // namespace

template <class F>
void ImplicitEuler::forSprings(F&& f) const {
  parallelItems(workers_, in_->springs.size(), kSpringGrain, f);
}

template <class F>
void ImplicitEuler::forVertices(F&& f) const {
  parallelItems(workers_, in_->masses.size(), kVertexGrain, f);
}

void ImplicitEuler::gatherTerms(double* out) const {
  forVertices([&](std::size_t i) {
    double* o = out + 3 * i;
    double o0 = o[0], o1 = o[1], o2 = o[2];
    for (std::uint32_t e = firstIncident_[i]; e < firstIncident_[i + 1]; ++e) {
      // x + (-1 t) is x - t exactly: no branch on the side.
      const Incidence& c = incident_[e];
      const std::array<double, 3>& t = terms_[c.spring];
      o0 += c.sign * t[0], o1 += c.sign * t[1], o2 += c.sign * t[2];
    }
    o[0] = o0, o[1] = o1, o[2] = o2;
  });
}

// Each vertex's springs, in spring order (a counting sort).
void ImplicitEuler::connect() {
  const std::size_t n = in_->masses.size();
  firstIncident_.assign(n + 1, 0);
  for (const Spring& s : in_->springs) ++firstIncident_[s.a + 1], ++firstIncident_[s.b + 1];
  for (std::size_t i = 0; i < n; ++i) firstIncident_[i + 1] += firstIncident_[i];
  incident_.resize(firstIncident_[n]);
  // firstIncident_[i] is vertex i's fill cursor, which ends at i + 1's start: shift back after.
  for (std::uint32_t k = 0; k < in_->springs.size(); ++k) {
    const Spring& s = in_->springs[k];
    incident_[firstIncident_[s.a]++] = {k, 1.0};
    incident_[firstIncident_[s.b]++] = {k, -1.0};
  }
  for (std::size_t i = n; i > 0; --i) firstIncident_[i] = firstIncident_[i - 1];
  firstIncident_[0] = 0;
  terms_.resize(in_->springs.size());
  partials_.resize((in_->springs.size() + kChunk - 1) / kChunk);
}

// The step's constants: x0, v0, each spring's start direction u0, M^ = M + h k_drag and the
// fields' other forces f0 = m a - (-k v0) at the start.
void ImplicitEuler::start(const ImplicitEulerInput& in, double h, std::span<const Real> x,
                          std::span<const Real> v) {
  in_ = &in;
  h_ = h;
  const std::size_t n = in.masses.size();
  const Eigen::Index n3 = Eigen::Index(x.size());
  x0_ = Eigen::Map<const VecX>(x.data(), n3).cast<double>();
  v0_ = Eigen::Map<const VecX>(v.data(), n3).cast<double>();
  massDiagonal_.resize(n3);
  f0_.resize(n3);
  for (std::size_t i = 0; i < n; ++i) {
    const double m = double(in.masses[i]), kd = double(in.fieldDamping[i]);
    for (std::size_t c = 0; c < 3; ++c) {
      const Eigen::Index j = Eigen::Index(3 * i + c);
      massDiagonal_[j] = m + h * kd;
      f0_[j] = m * double(in.fieldAcceleration[3 * i + c]) + kd * v0_[j];
    }
  }
  anchorDiagonal_.setZero(n3);
  for (const AttachmentTerm& a : in.attachments)
    if (!in.pinned[a.vertex])
      anchorDiagonal_.segment<3>(3 * Eigen::Index(a.vertex)).array() += h * h * a.k + h * a.c;
  pinnedList_.clear();
  for (std::size_t i = 0; i < in.pinned.size(); ++i)
    if (in.pinned[i]) pinnedList_.push_back(std::uint32_t(i));
  u0_.resize(in.springs.size());
  blocks_.resize(in.springs.size());
  connect();
  forSprings([&](std::size_t k) {
    const Spring& s = in.springs[k];
    const Eigen::Vector3d d = seg(x0_, s.a) - seg(x0_, s.b);
    const double l = d.norm();
    u0_[k] = l > 0 ? Eigen::Vector3d(d / l) : Eigen::Vector3d::Zero();
  });
}

// G = M^ (v - v0) - h f0 - h F~(x0 + h v) + h sum c u0 u0^T v_ab, pinned components zeroed.
const Eigen::VectorXd& ImplicitEuler::gradient(const Eigen::VectorXd& v) {
  const double h = h_;
  x_ = x0_ + h * v;
  g_ = massDiagonal_.cwiseProduct(v - v0_) - h * f0_;
  // -h f at a, +h f at b, f the spring's force on a.
  forSprings([&](std::size_t k) {
    if (in_->broken[k]) {
      terms_[k] = {0, 0, 0};
      return;
    }
    const Spring& s = in_->springs[k];
    const Eigen::Vector3d& u0 = u0_[k];
    const Eigen::Vector3d f = surrogate(s, u0).force(seg(x_, s.a) - seg(x_, s.b)) -
                              double(s.damping) * u0 * u0.dot(seg(v, s.a) - seg(v, s.b));
    const Eigen::Vector3d t = -(h * f);
    terms_[k] = {t[0], t[1], t[2]};
  });
  gatherTerms(g_.data());
  for (const AttachmentTerm& a : in_->attachments)
    g_.segment<3>(3 * Eigen::Index(a.vertex)) +=
        h * (a.k * (seg(x_, a.vertex) - a.target) + a.c * (seg(v, a.vertex) - a.velocity));
  // What holds a contact: M (v - v0) = h F + lambda there, so G = lambda where it sticks. A
  // sliding one's friction impulse f enters G as -f, and G = lambda_n n there.
  for (std::size_t k = 0; k < in_->contacts.size(); ++k) {
    VertexContact& c = in_->contacts[k];
    auto gk = g_.segment<3>(3 * Eigen::Index(c.vertex));
    switch (modes_[k]) {
      case ContactMode::Released:
        c.impulse.setZero();
        break;
      case ContactMode::Sliding:
        gk -= slideImpulses_[k];
        c.impulse = c.normal * c.normal.dot(gk) + slideImpulses_[k];
        break;
      case ContactMode::Sticking:
        c.impulse = gk;
        break;
    }
  }
  filter(g_);
  return g_;
}

// Psi's Hessian H = M^ + h^2 K~(x) + h C at the current iterate: each spring's block enters at
// (a, a), (b, b) with + and at (a, b), (b, a) with -.
void ImplicitEuler::assemble(const Eigen::VectorXd& v) {
  const double h = h_;
  x_ = x0_ + h * v;
  diagonal_ = massDiagonal_ + anchorDiagonal_;
  forSprings([&](std::size_t k) {
    if (in_->broken[k]) {
      blocks_[k] = {};
      return;
    }
    const Spring& s = in_->springs[k];
    const Eigen::Vector3d& u0 = u0_[k];
    const Eigen::Matrix3d b = h * h * surrogate(s, u0).stiffness(seg(x_, s.a) - seg(x_, s.b)) +
                              h * double(s.damping) * u0 * u0.transpose();
    blocks_[k] = {b(0, 0), b(1, 1), b(2, 2), b(0, 1), b(0, 2), b(1, 2)};
  });
}

// The PCG's preconditioner: H's 3 x 3 diagonal blocks, inverted (block Jacobi: a stretched
// spring couples a vertex's three components).
void ImplicitEuler::invertDiagonalBlocks() {
  inverseBlocks_.resize(in_->masses.size());
  forVertices([&](std::size_t i) {
    const double* g = diagonal_.data() + 3 * i;
    SymmetricBlock d = {g[0], g[1], g[2], 0, 0, 0};
    for (std::uint32_t e = firstIncident_[i]; e < firstIncident_[i + 1]; ++e)
      for (std::size_t c = 0; c < 6; ++c) d[c] += blocks_[incident_[e].spring][c];
    Eigen::Matrix3d m;
    m << d[0], d[3], d[4], d[3], d[1], d[5], d[4], d[5], d[2];
    const Eigen::Matrix3d inverse = m.inverse();
    inverseBlocks_[i] = {inverse(0, 0), inverse(1, 1), inverse(2, 2),
                         inverse(0, 1), inverse(0, 2), inverse(1, 2)};
  });
}

// out = P^-1 r, P the Hessian's 3 x 3 diagonal blocks.
void ImplicitEuler::precondition(const Eigen::VectorXd& r, Eigen::VectorXd& out) const {
  out.resize(r.size());
  forVertices([&](std::size_t i) {
    const SymmetricBlock& b = inverseBlocks_[i];
    const double* ri = r.data() + 3 * i;
    double* oi = out.data() + 3 * i;
    oi[0] = b[0] * ri[0] + b[3] * ri[1] + b[4] * ri[2];
    oi[1] = b[3] * ri[0] + b[1] * ri[1] + b[5] * ri[2];
    oi[2] = b[4] * ri[0] + b[5] * ri[1] + b[2] * ri[2];
  });
}

// H w, the product the conjugate gradients spend their time in: y = B (w_a - w_b) per spring,
// added at a and subtracted at b. In sequence, one scatter over the springs; on several
// workers, a pass over the springs writing each y, then a pass over the vertices adding
// sign * y in spring order (gatherTerms), which are the scatter's sums: x + (-1 y) is x - y,
// zeros' signs included, so both give the same bytes.
void ImplicitEuler::apply(const Eigen::VectorXd& w, Eigen::VectorXd& out) const {
  const double* wp = w.data();
  const auto term = [&](std::size_t k) {
    const Spring& s = in_->springs[k];
    const SymmetricBlock& b = blocks_[k];  // zero for a broken spring
    const double* wa = wp + 3 * std::size_t(s.a);
    const double* wb = wp + 3 * std::size_t(s.b);
    const double d0 = wa[0] - wb[0], d1 = wa[1] - wb[1], d2 = wa[2] - wb[2];
    return std::array<double, 3>{b[0] * d0 + b[3] * d1 + b[4] * d2,
                                 b[3] * d0 + b[1] * d1 + b[5] * d2,
                                 b[4] * d0 + b[5] * d1 + b[2] * d2};
  };
  out = diagonal_.cwiseProduct(w);
  if (!workers_ || workers_->threadCount() == 1) {
    double* op = out.data();
    for (std::size_t k = 0; k < in_->springs.size(); ++k) {
      const Spring& s = in_->springs[k];
      const std::array<double, 3> y = term(k);
      double* oa = op + 3 * std::size_t(s.a);
      double* ob = op + 3 * std::size_t(s.b);
      oa[0] += y[0], oa[1] += y[1], oa[2] += y[2];
      ob[0] -= y[0], ob[1] -= y[1], ob[2] -= y[2];
    }
    return;
  }
  forSprings([&](std::size_t k) { terms_[k] = term(k); });
  gatherTerms(out.data());
}

void ImplicitEuler::filterPinned(Eigen::VectorXd& w) const {
  for (std::uint32_t i : pinnedList_) w.segment<3>(3 * Eigen::Index(i)).setZero();
}

// Baraff-Witkin's filter with S_i = 0 for a pinned vertex or one sticking to a body (all three
// directions constrained), and S_i = I - n n^T for a vertex sliding on a body along n.
void ImplicitEuler::filter(Eigen::VectorXd& w) const {
  filterPinned(w);
  for (std::size_t k = 0; k < in_->contacts.size(); ++k) {
    const VertexContact& c = in_->contacts[k];
    auto wi = w.segment<3>(3 * Eigen::Index(c.vertex));
    if (modes_[k] == ContactMode::Sticking)
      wi.setZero();
    else if (modes_[k] == ContactMode::Sliding)
      wi -= c.normal * c.normal.dot(wi);
  }
}

// Psi(v + alpha p) - Psi(v), term by term from differences (no cancellation of large values).
double ImplicitEuler::psiChange(const Eigen::VectorXd& p, double alpha) const {
  const double h = h_;
  double change = alpha * p.dot(massDiagonal_.cwiseProduct(v_ - v0_)) +
                  0.5 * alpha * alpha * p.dot(massDiagonal_.cwiseProduct(p)) -
                  alpha * h * f0_.dot(p);
  const std::size_t springs = in_->springs.size();
  parallelItems(workers_, partials_.size(), 1, [&](std::size_t chunk) {
    {
      double sum = 0;
      for (std::size_t k = chunk * kChunk; k < std::min(springs, (chunk + 1) * kChunk); ++k) {
        if (in_->broken[k]) continue;
        const Spring& s = in_->springs[k];
        const Eigen::Vector3d pab = seg(p, s.a) - seg(p, s.b);
        const double w = u0_[k].dot(seg(v_, s.a) - seg(v_, s.b)), q = u0_[k].dot(pab);
        sum += 0.5 * h * double(s.damping) * alpha * q * (2 * w + alpha * q);
        sum += surrogate(s, u0_[k]).energyChange(seg(x_, s.a) - seg(x_, s.b), alpha * h * pab);
      }
      partials_[chunk] = sum;
    }
  });
  for (double partial : partials_) change += partial;
  for (const AttachmentTerm& a : in_->attachments) {
    const Eigen::Vector3d pa = seg(p, a.vertex);
    change +=
        alpha * h *
            pa.dot(a.k * (seg(x_, a.vertex) - a.target) + a.c * (seg(v_, a.vertex) - a.velocity)) +
        0.5 * alpha * alpha * (h * h * a.k + h * a.c) * pa.squaredNorm();
  }
  // The sliding contacts' friction impulses: Psi's term -f . v.
  for (std::size_t k = 0; k < in_->contacts.size(); ++k)
    if (modes_[k] == ContactMode::Sliding)
      change -= alpha * slideImpulses_[k].dot(seg(p, in_->contacts[k].vertex));
  return change;
}

// Backtracking from the full Newton step until Armijo's condition holds; 0 when none does
// (the iterate is as good as rounding lets it be).
double ImplicitEuler::lineSearch(const Eigen::VectorXd& p) {
  const double slope = g_.dot(p);
  if (!(slope < 0)) return 0;
  for (double alpha = 1; alpha >= kSmallestStep; alpha *= 0.5)
    if (psiChange(p, alpha) <= kArmijo * alpha * slope) return alpha;
  return 0;
}

// Whether this step's Newton systems are solved by the sparse LDL^T: as the settings say, or,
// when automatic, where its factors stay sparse.
bool ImplicitEuler::useDirectSolve() {
  switch (in_->linearSolver) {
    case DeformableLinearSolver::ConjugateGradient:
      return false;
    case DeformableLinearSolver::Direct:
      return direct_.connect(in_->springs, in_->masses.size(),
                             std::numeric_limits<double>::infinity());
    case DeformableLinearSolver::Automatic:
      break;
  }
  return direct_.connect(in_->springs, in_->masses.size(), kDirectFill);
}

// The filter's 3 x 3 block per constrained vertex, for the direct solve.
void ImplicitEuler::buildProjections() {
  projectionOf_.assign(in_->masses.size(), -1);
  projections_.clear();
  const auto add = [&](std::uint32_t vertex, const Eigen::Matrix3d& s) {
    projectionOf_[vertex] = std::int32_t(projections_.size());
    projections_.push_back(s);
  };
  for (std::uint32_t i : pinnedList_) add(i, Eigen::Matrix3d::Zero());
  for (std::size_t k = 0; k < in_->contacts.size(); ++k) {
    const VertexContact& c = in_->contacts[k];
    if (modes_[k] == ContactMode::Sticking)
      add(c.vertex, Eigen::Matrix3d::Zero());
    else if (modes_[k] == ContactMode::Sliding)
      add(c.vertex, Eigen::Matrix3d::Identity() - c.normal * c.normal.transpose());
  }
}

// p_ = the Newton step, H p = -G on the filter's range: by the sparse LDL^T (filtered_ldlt.h),
// or by the modified PCG to a relative residual `forcing`. Returns the PCG iterations (1 for a
// direct solve; PCG when its factorisation failed).
int ImplicitEuler::solveNewtonSystem(double forcing, bool direct) {
  trial_ = -g_;
  if (direct) {
    const ProjectionOf projection = [](const void* self, std::uint32_t i) {
      const ImplicitEuler& e = *static_cast<const ImplicitEuler*>(self);
      const std::int32_t k = e.projectionOf_[i];
      return k < 0 ? nullptr : &e.projections_[std::size_t(k)];
    };
    if (direct_.solve(diagonal_, blocks_, projection, this, trial_, p_, workers_)) {
      filter(p_);
      return 1;
    }
  }
  invertDiagonalBlocks();
  const auto applyH = [this](const Eigen::VectorXd& w, Eigen::VectorXd& out) { apply(w, out); };
  const auto filterS = [this](Eigen::VectorXd& w) { filter(w); };
  const auto blockJacobi = [this](const Eigen::VectorXd& r, Eigen::VectorXd& out) {
    precondition(r, out);
  };
  p_.setZero(trial_.size());
  return modifiedPcg(applyH, filterS, blockJacobi, trial_, p_, forcing, in_->maxIterations, pcg_)
      .iterations;
}

// Newton's method on Psi from v_, with the contacts held as they are; false when it failed to
// give finite values.
bool ImplicitEuler::newton(const ImplicitEulerInput& in, double reference, double tolerance,
                           ImplicitSolveReport& report) {
  gradient(v_);
  const bool direct = useDirectSolve();
  if (direct) buildProjections();
  const double target = tolerance * reference;
  report.converged = false;
  double previous = g_.norm();
  for (int iteration = 0; iteration < in.maxNewtonIterations; ++iteration) {
    const double norm = g_.norm(), ratio = iteration == 0 ? 1.0 : norm / previous;
    previous = norm;
    if (norm <= target) {
      report.converged = true;
      break;
    }
    assemble(v_);
    // Inexact Newton (Eisenstat and Walker 1996, choice 2): loose while far, tighter as the
    // gradient falls, never finer than the target needs.
    const double forcing =
        std::clamp(std::max(0.9 * ratio * ratio, 0.1 * target / norm), tolerance, 0.1);
    report.iterations += solveNewtonSystem(forcing, direct);
    ++report.newtonIterations;
    if (!p_.allFinite()) return false;
    x_ = x0_ + h_ * v_;
    const double alpha = lineSearch(p_);
    if (alpha == 0) break;
    v_ += alpha * p_;
    gradient(v_);
  }
  report.error = reference > 0 ? g_.norm() / reference : 0.0;
  report.energySlack = std::max(0.0, g_.dot(v_));
  return v_.allFinite();
}

// Newton's tolerance is relative to |filter(M^ v0 + h f0)| + |G| at the velocities it starts
// from: the step's momentum and how far the start is from balanced.
double ImplicitEuler::reference() {
  gradient(v_);
  trial_ = massDiagonal_.cwiseProduct(v0_) + h_ * f0_;
  filter(trial_);
  return trial_.norm() + g_.norm();
}

// Newton starts from the lowest Psi of three guesses: the start's velocities, the fields' free
// motion v0 + h M^-1 f0 (a cloth in free fall) and v0 plus the last step's change (a cloth
// settling or swinging at a steady rate). Only the start moves: the minimiser, and so the step,
// are those of Psi whichever guess wins, to the tolerance.
void ImplicitEuler::predict() {
  x_ = x0_ + h_ * v_;
  trial_ = h_ * f0_.cwiseQuotient(massDiagonal_);
  filter(trial_);
  p_.setZero(v_.size());
  double best = 0;
  if (const double change = psiChange(trial_, 1); change < best) best = change, p_ = trial_;
  if (previousChange_.size() == v_.size()) {
    trial_ = previousChange_;
    filter(trial_);
    if (const double change = psiChange(trial_, 1); change < best) best = change, p_ = trial_;
  }
  v_ += p_;
}

// Coulomb's active set, one pass per solve: a contact whose impulse came out pulling is let go;
// a sticking one whose impulse across the normal passes mu times the one along it slides, with
// that much friction in that direction (against the motion its holding prevented). True when
// any changed.
bool ImplicitEuler::updateContactModes() {
  bool changed = false;
  for (std::size_t k = 0; k < in_->contacts.size(); ++k) {
    if (modes_[k] == ContactMode::Released) continue;
    VertexContact& c = in_->contacts[k];
    const double along = c.normal.dot(c.impulse);
    if (along < 0) {
      modes_[k] = ContactMode::Released;
      slideImpulses_[k].setZero();
      c.impulse.setZero();
      changed = true;
    } else if (modes_[k] == ContactMode::Sticking) {
      const Eigen::Vector3d across = c.impulse - along * c.normal;
      const double limit = c.friction * along, size = across.norm();
      if (size > limit) {
        modes_[k] = ContactMode::Sliding;
        slideImpulses_[k] = across * (limit / size);
        changed = true;
      }
    }
  }
  return changed;
}

ImplicitSolveReport ImplicitEuler::step(const ImplicitEulerInput& in, Real h, std::span<Real> x,
                                        std::span<Real> v) {
  ImplicitSolveReport report;
  StepWorkers::run(nullptr, [&](StepWorkers& workers) { report = step(in, h, x, v, workers); });
  return report;
}

ImplicitSolveReport ImplicitEuler::step(const ImplicitEulerInput& in, Real hr, std::span<Real> x,
                                        std::span<Real> v, StepWorkers& workers) {
  workers_ = &workers;
  struct Release {
    StepWorkers*& workers;
    ~Release() { workers = nullptr; }
  } release{workers_};
  const Eigen::Index n3 = Eigen::Index(x.size());
  start(in, double(hr), x, v);
  modes_.resize(in.contacts.size());
  slideImpulses_.assign(in.contacts.size(), Eigen::Vector3d::Zero());
  ImplicitSolveReport report;
  v_ = v0_;
  // Held vertices start at their prescribed velocities (the filter keeps them there): a
  // sticking one at the surface's, plus the normal velocity; pinned ones at rest.
  for (std::size_t k = 0; k < in.contacts.size(); ++k) {
    const VertexContact& c = in.contacts[k];
    auto vi = v_.segment<3>(3 * Eigen::Index(c.vertex));
    modes_[k] = c.friction > 0 ? ContactMode::Sticking : ContactMode::Sliding;
    if (modes_[k] == ContactMode::Sticking) vi = c.surfaceVelocity;
    vi += c.normal * (c.normalVelocity - c.normal.dot(vi));
  }
  filterPinned(v_);
  const double first = reference();
  predict();
  // Coulomb's active set is settled on solves to a relative kModeTolerance (the modes need the
  // impulses' signs and sizes, not their last digits); the last modes are then solved to the
  // tolerance. A later solve's reference is the first one's unless larger: a pass starts from
  // a solved state, whose small |G| would ask for more than the step needs.
  const double modeTolerance =
      in.contacts.empty() ? in.tolerance : std::max(in.tolerance, kModeTolerance);
  bool finite = newton(in, first, modeTolerance, report);
  for (int pass = 0; finite && pass < 4 && updateContactModes(); ++pass)
    finite = newton(in, std::max(first, reference()), modeTolerance, report);
  if (finite && modeTolerance > in.tolerance)
    finite = newton(in, std::max(first, reference()), in.tolerance, report);
  if (!finite) {
    report.converged = false;
    for (VertexContact& c : in.contacts) c.impulse.setZero();
    previousChange_.resize(0);
    return report;
  }
  previousChange_ = v_ - v0_;
  x_ = x0_ + h_ * v_;
  Eigen::Map<VecX>(v.data(), n3) = v_.cast<Real>();
  Eigen::Map<VecX>(x.data(), n3) = x_.cast<Real>();
  return report;
}

}  // namespace inertia::detail
