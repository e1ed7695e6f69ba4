// Implicit (backward) Euler for mass-spring systems, after Baraff and Witkin (1998, "Large steps
// in cloth simulation", sections 4 and 5): the springs' analytic Jacobians, the system
// (M - h dF/dv - h^2 dF/dx) dv = -G solved matrix-free (3 x 3 blocks per spring) by their
// modified preconditioned conjugate gradients, which keep pinned vertices still.
//
// Baraff and Witkin take one such Newton step, linearised about the start of the step. At stiff
// springs (1e6 N/m at 1/60 s) that one step gains energy: a spring that turns by h v across it
// is stretched by (h v)^2 / 2L by the linearisation, k (h v)^4 / 8 L^2 of spring energy (tens
// of joules per spring on a falling cloth). Here the step is instead solved to convergence, as
// the minimisation of the incremental potential (Martin et al. 2011, Gast et al. 2015)
//     Psi(v) = 1/2 (v - v0)^T M^ (v - v0) - h f0 . v + U~(x0 + h v) + h/2 sum c (u0 . v_ab)^2
// by Newton's method with a backtracking line search, M^ = M + h k_drag the mass and the
// fields' linear drag, f0 the fields' other forces at the step's start. U~ is a convex
// majorant of the springs' energy that touches it at the step's start: per spring
//     U~ = k/2 (max(l - L, 0)^2 + max(L - u0 . d, 0)^2),   d = x_a - x_b, l = |d|,
// u0 the spring's direction at the start: the true energy while the spring is stretched, a
// spring along u0 against compression (whose Hessian k u0 u0^T is Choi and Ko's clamped
// Jacobian). U~ >= U and U~(x0) = U(x0), with U~ convex, make the step dissipative: at a
// stationary point of Psi,
//     E(x1, v1) <= E(x0, v0) - 1/2 |v1 - v0|_M^2 - h (damping's power) + G . v1,
// E kinetic plus spring plus gravity energy, G the gradient of Psi left by the inexact solve
// (reported as the energy slack). The damping force keeps the start's direction u0 too, as in
// Baraff and Witkin. Assembled and solved in double whatever Real is.
//
// Each Newton system is solved by the modified PCG, or, where the springs' graph lets a sparse
// factor stay sparse (strands: ropes and hair), by a sparse LDL^T of the same filtered system
// (filtered_ldlt.h): a hair strand resting on a head is long, nearly inextensible and held at
// many points, and block-Jacobi PCG needed some 600 iterations per solve there.
//
// Threads: the passes over springs and vertices (the Hessian's product, its assembly, the
// gradient, Psi's change) run on the step's workers. A pass over the springs writes one term
// per spring, then each vertex sums its springs' terms in spring order, the order a serial
// scatter over the springs adds them, and Psi's change is summed in fixed chunks of springs;
// the direct solve factors its parts (groups of whole components, fixed by the springs) one
// per task: the result is the same bytes whatever the number of workers.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "deformable/filtered_ldlt.h"
#include "deformable/modified_pcg.h"
#include "dynamics/step_workers.h"
#include "inertia/core/types.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/model.h"
#include "inertia/ode/implicit.h"

namespace inertia::detail {

/// A zero-length spring from a vertex to a point moving at `velocity` that reaches `target` at
/// the step's end: the term k/2 |x - target|^2 + h c/2 |v - velocity|^2 of Psi (an attachment).
struct AttachmentTerm {
  std::uint32_t vertex = 0;
  double k = 0, c = 0;
  Eigen::Vector3d target = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero();
};

/// A vertex touching a body, held in the solve (Baraff and Witkin's constrained vertices,
/// section 5.3) with Coulomb friction as an active set. A sticking vertex is held in all three
/// directions (the filter S = 0) to the surface's velocity, with `normalVelocity` (m/s) along
/// `normal`; a sliding one only along the normal (S = I - n n^T), with a friction impulse of mu
/// times its normal impulse against the direction that holding it needed; a released one is
/// free. The solve's unbalanced gradient at a held vertex is the contact's impulse, handed to
/// the body. Every contact starts sticking (sliding when mu is 0); between Newton solves one
/// whose impulse would pull is released, and one whose holding impulse leaves the friction
/// cone slides.
/// (Not `ContactConstraint`: the dynamics layer's struct of that name lives in this namespace
/// too, and two definitions of one name broke the one-definition rule: the vectors of both
/// shared one instantiation, which overflowed a buffer under the fuzzer's ASan build.)
struct VertexContact {
  std::uint32_t vertex = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  double normalVelocity = 0;
  /// The surface's velocity at the vertex (m/s): a sticking vertex moves with its tangential
  /// part.
  Eigen::Vector3d surfaceVelocity = Eigen::Vector3d::Zero();
  double friction = 0;  ///< Coulomb's coefficient mu (>= 0)
  /// Out: the contact's impulse on the vertex (N s): along `normal` >= 0, across it within
  /// mu times that.
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
};

/// What one implicit step reads besides the state.
struct ImplicitEulerInput {
  std::span<const Spring> springs;
  std::span<const std::uint8_t> broken;     ///< one per spring
  std::span<const Real> masses;             ///< kg, one per vertex
  std::span<const std::uint8_t> pinned;     ///< one per vertex
  std::span<const Real> fieldAcceleration;  ///< m/s^2, 3 per vertex, at the step's start
  /// Per vertex, the linear drag coefficient k (kg/s) of the fields (F = -k v), taken
  /// implicitly so that strong drag is stable too.
  std::span<const Real> fieldDamping;
  /// Newton stops when |G| <= tolerance * (|filter(M^ v0 + h f0)| + |G(v0)|) (with contacts,
  /// each active-set pass to 1e-3 first, the last one then to the tolerance); each Newton
  /// step's PCG stops at a relative residual between tolerance and 0.1 (inexact Newton).
  std::span<const AttachmentTerm> attachments = {};
  /// In and out: each one's impulse is written (0 for one released because it would pull).
  std::span<VertexContact> contacts = {};
  double tolerance = 1e-6;
  int maxIterations = 1000;  ///< PCG iterations per Newton step
  int maxNewtonIterations = 20;
  DeformableLinearSolver linearSolver = DeformableLinearSolver::Automatic;
};

class ImplicitEuler {
 public:
  /// One step of h seconds; updates x and v (3 per vertex) in place unless the solve gave
  /// non-finite values, which leaves them as they were (the report says so). On `workers`
  /// when given (the result is the same without).
  ImplicitSolveReport step(const ImplicitEulerInput& in, Real h, std::span<Real> x,
                           std::span<Real> v);
  ImplicitSolveReport step(const ImplicitEulerInput& in, Real h, std::span<Real> x,
                           std::span<Real> v, StepWorkers& workers);

  /// The last Newton system: out = H w, H = M^ + h^2 K~ + h C at the last iterate.
  void apply(const Eigen::VectorXd& w, Eigen::VectorXd& out) const;
  void filter(Eigen::VectorXd& w) const;
  /// out = P^-1 r with P the block diagonal of the last Newton system.
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& out) const;
  void filterPinned(Eigen::VectorXd& w) const;
  /// Psi's gradient G at velocities v (N s), pinned components zeroed.
  const Eigen::VectorXd& gradient(const Eigen::VectorXd& v);

 private:
  void start(const ImplicitEulerInput& in, double h, std::span<const Real> x,
             std::span<const Real> v);
  void assemble(const Eigen::VectorXd& v);
  void invertDiagonalBlocks();
  bool useDirectSolve();
  double reference();
  bool newton(const ImplicitEulerInput& in, double reference, double tolerance,
              ImplicitSolveReport& report);
  bool updateContactModes();
  void buildProjections();
  int solveNewtonSystem(double forcing, bool direct);
  double lineSearch(const Eigen::VectorXd& p);
  double psiChange(const Eigen::VectorXd& p, double alpha) const;

  void predict();
  void connect();
  template <class F>
  void forSprings(F&& f) const;
  template <class F>
  void forVertices(F&& f) const;
  // Adds each vertex's springs' terms_ (+ at a, - at b) to `out`, in spring order.
  void gatherTerms(double* out) const;

  const ImplicitEulerInput* in_ = nullptr;
  double h_ = 0;
  // Per contact: how the solve holds it (VertexContact), and a sliding one's friction impulse.
  enum class ContactMode : std::uint8_t { Released, Sliding, Sticking };
  std::vector<ContactMode> modes_;
  std::vector<Eigen::Vector3d> slideImpulses_;
  std::vector<Eigen::Vector3d> u0_;     // each spring's direction at the start (0: collapsed)
  std::vector<SymmetricBlock> blocks_;  // h^2 K~ + h c u0 u0^T per spring, at the last iterate
  std::vector<SymmetricBlock> inverseBlocks_;  // per vertex: H's diagonal block, inverted
  std::vector<std::uint32_t> pinnedList_;      // the pinned vertices, for the filters
  // Each vertex's springs in spring order, with the sign of the spring's term at this end (+1
  // at a, -1 at b); vertex i's run is incident_[firstIncident_[i] .. firstIncident_[i + 1]).
  struct Incidence {
    std::uint32_t spring;
    double sign;
  };
  std::vector<std::uint32_t> firstIncident_;
  std::vector<Incidence> incident_;
  // Scratch of the passes: one vector per spring (written by a pass over springs, summed by
  // gatherTerms), and Psi's change per chunk of springs.
  mutable std::vector<std::array<double, 3>> terms_;
  mutable std::vector<double> partials_;
  StepWorkers* workers_ = nullptr;  // during a step; in sequence otherwise
  // State carried from step to step (copied with the deformable): the last step's velocity
  // change, Newton's second starting guess (implicit_euler.cpp, predict).
  Eigen::VectorXd previousChange_;
  Eigen::VectorXd anchorDiagonal_;  // h^2 k + h c of the attachments, per component
  Eigen::VectorXd diagonal_;        // M^ + the attachments' part: H's diagonal before springs
  Eigen::VectorXd x0_, v0_, v_, x_, f0_, massDiagonal_, g_, p_, trial_;
  PcgBuffers pcg_;
  // The direct solve (filtered_ldlt.h) and the filter's block per vertex it reads: -1 where
  // free, else an index into projections_.
  FilteredDirectSolve direct_;
  std::vector<std::int32_t> projectionOf_;
  std::vector<Eigen::Matrix3d> projections_;
};

}  // namespace inertia::detail
