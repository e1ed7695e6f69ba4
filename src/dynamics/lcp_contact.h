// Internal: the contact rows of a substep solved as one LCP per island, directly (Dantzig or
// Lemke, see lcp.h), in place of the Gauss-Seidel iterations of the pgs solver. Joints add
// their rows to their island's LCP (joint_solver.h's appendJointLcpRows): bilateral rows are
// free in Dantzig's box and two directions without a slack in Lemke's form; limits are
// one-sided as normals; boxed rows (motors, joint friction) have a fixed box, in Lemke's form
// two directions whose slack's limit is the bound.
//
// The rows are those of contact_solver.h, rigid, with the pgs solver's right-hand side: the
// normal row asks for J v+ + bias >= 0 with Baumgarte's bias on the overlap beyond the slop
// (speculative rows: the gap over the substep); restitution is applied after the substeps as
// in pgs. From the island's rows the Delassus matrix A = J M^-1 J^T (dense) and b = J v + bias.
// - lcp_dantzig: a boxed LCP. Per point: normal in [0, inf), the two friction rows each in
//   [-mu z_n, mu z_n] (a friction pyramid of four faces, the square circumscribing Coulomb's
//   disc); per manifold the two rolling rows and the spinning row in
//   [-c sum z_n, c sum z_n] with c the lever arm.
// - lcp_lemke: a standard LCP in the Stewart-Trinkle / Anitescu-Potra form: each friction row
//   pair becomes four direction impulses beta >= 0 (+-t1, +-t2) and a slack gamma (the
//   sliding speed) with 0 <= beta _|_ D^T v+ + gamma >= 0 and 0 <= gamma _|_ mu z_n - sum beta
//   >= 0: the inscribed pyramid |z_t1| + |z_t2| <= mu z_n. Rolling rows likewise (four
//   directions), spinning with two.
// Both are warm started from the last substep's impulses: the active set they imply is solved
// with one factorisation and kept only if it passes the complementarity check (a stack at
// rest keeps its set, so the pivoting runs only when contacts change).
// Both solve the rows Jacobi-scaled (unit diagonal) with A + 1e-8 I: a box resting on four
// points has 12 rows on 6 degrees of freedom, so A is only semidefinite and the split of the
// load between the points is not unique; the regularisation picks the least-squares split and
// changes the velocities by 1e-8 of an impulse's effect.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "contact_solver.h"
#include "islands.h"

namespace inertia::detail {

enum class LcpMethod { Dantzig, Lemke };

/// Largest LCP (number of unknowns) an island is solved with directly. A Dantzig pass costs
/// O(n) pivots of an O(n^3) factorisation, so beyond this the direct solve stops being "small";
/// such islands, and islands whose LCP fails (a pivot cap, an infeasible problem), fall back
/// to the pgs iterations for that substep.
inline constexpr int kMaxLcpUnknowns = 192;

struct LcpContactStats {
  int islands = 0;         ///< Islands with constraints, summed over calls.
  int direct = 0;          ///< Of those, solved by the LCP.
  int fallbacks = 0;       ///< Solved by pgs instead (too large, or the LCP failed).
  int largest = 0;         ///< Most unknowns of one island's LCP.
  double maxResidual = 0;  ///< Largest natural residual of a direct solve (scaled units).
};

/// One substep's contact solve: every island of `cs` (constraints sharing a solver body) as
/// one LCP; the impulses are applied to `bodies` and stored in the constraints (normalImpulse,
/// tangentImpulse, rollingImpulse, spinningImpulse, maxNormalImpulse), so events and the
/// next substep's fallback warm start see them. `fallbackIterations` pgs iterations for the
/// islands that are not solved directly.
/// Contact rows (Normal, Tangent, Rolling, Spinning) and joint rows: Bilateral (a locked row or
/// a spring, z free), Limit (z >= 0) and Boxed (a motor or friction, |z| <= bound).
enum class LcpRowKind : unsigned char {
  Normal,
  Tangent,
  Rolling,
  Spinning,
  Bilateral,
  Limit,
  Boxed
};

/// One Jacobian row of an island's LCP: the relative velocity
/// J v = linB.vB + angB.wB + linA.vA + angA.wA.
struct LcpRow {
  int a = -1, b = -1;  ///< Solver bodies, -1 static.
  Eigen::Vector3d linA = Eigen::Vector3d::Zero(), angA = Eigen::Vector3d::Zero();
  Eigen::Vector3d linB = Eigen::Vector3d::Zero(), angB = Eigen::Vector3d::Zero();
  double rhs = 0;  ///< J v + bias.
  LcpRowKind kind = LcpRowKind::Normal;
  int constraint = 0;  ///< Index into cs.
  int point = 0;       ///< Point (normal, tangent) or axis (tangent, rolling).
  int axis = 0;
  double coefficient = 0;  ///< Friction coefficient or lever arm (tangent, rolling, spinning).
  int group = -1;          ///< Friction group (Lemke) of tangent, rolling, spinning, boxed rows.
  /// Joint rows: a soft row's compliance, added to its diagonal (ODE's CFM: the soft
  /// constraint's fixed point J v+ + bias + cfm z = 0), a boxed row's bound (N s), and the
  /// accumulated impulse the row reads its warm start from and stores its impulse in.
  double cfm = 0;
  double bound = 0;
  Real* store = nullptr;
};

/// The relative velocity J v of a row.
double lcpRowVelocity(const LcpRow& r, const std::vector<SolverBody>& bodies);
/// J_i M^-1 J_j^T of two rows.
double lcpDelassus(const LcpRow& i, const LcpRow& j, const std::vector<SolverBody>& bodies);
/// The rows of contact constraint `c` (index `ci`) with the pgs solver's right-hand side; their
/// friction groups are numbered from `groups` on.
void appendContactRows(const ContactConstraint& c, int ci, const std::vector<SolverBody>& bodies,
                       const BiasMode& mode, std::vector<LcpRow>& rows, int& groups);
/// One island's rows (contacts' and joints') as one LCP: false when it is larger than
/// kMaxLcpUnknowns or the solver fails. `cs` gives the contact rows' warm start.
bool solveLcpRows(const std::vector<LcpRow>& rows, const std::vector<ContactConstraint>& cs,
                  const std::vector<SolverBody>& bodies, LcpMethod method,
                  Eigen::VectorXd& impulses, LcpContactStats* stats);
/// Applies a solved island's impulses to the bodies and stores them (the contacts' in `cs`,
/// a joint row's through its store), after clearing the contacts' old ones.
void applyLcpImpulses(const std::vector<LcpRow>& rows, const Eigen::VectorXd& impulses,
                      std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies);

/// What solveContactsLcp keeps from call to call, so that the rows and the fallback's copies
/// are not allocated every substep (the dense solve of an island still allocates).
struct LcpWorkspace {
  std::vector<LcpRow> rows;
  std::vector<ContactConstraint> scratch;
  Eigen::VectorXd impulses;
};

/// The same on islands grouped once a step (groupConstraints over the constraints' solver
/// bodies), with a workspace kept from step to step.
void solveContactsLcp(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      const BiasMode& mode, LcpMethod method, int fallbackIterations,
                      const ConstraintIslands& islands, LcpWorkspace& ws,
                      LcpContactStats* stats = nullptr);

void solveContactsLcp(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      const BiasMode& mode, LcpMethod method, int fallbackIterations,
                      LcpContactStats* stats = nullptr);

}  // namespace inertia::detail
