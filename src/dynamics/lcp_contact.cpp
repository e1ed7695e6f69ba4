#include "lcp_contact.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

#include "lcp.h"

namespace inertia::detail {

namespace {

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;

constexpr double kRegularisation = 1e-8;

using RowKind = LcpRowKind;
using Row = LcpRow;

const SolverBody& bodyOf(const std::vector<SolverBody>& bodies, int i) {
  static const SolverBody kStatic{};
  return i >= 0 ? bodies[static_cast<std::size_t>(i)] : kStatic;
}

double rowVelocity(const Row& r, const std::vector<SolverBody>& bodies) {
  const SolverBody& a = bodyOf(bodies, r.a);
  const SolverBody& b = bodyOf(bodies, r.b);
  return r.linA.dot(a.v.cast<double>()) + r.angA.dot(a.w.cast<double>()) +
         r.linB.dot(b.v.cast<double>()) + r.angB.dot(b.w.cast<double>());
}

// A_ij = J_i M^-1 J_j^T over the bodies the two rows share.
double delassus(const Row& i, const Row& j, const std::vector<SolverBody>& bodies) {
  double sum = 0;
  auto side = [&](int bi, const Vec3d& li, const Vec3d& ai, int bj, const Vec3d& lj,
                  const Vec3d& aj) {
    if (bi < 0 || bi != bj) return;
    const SolverBody& s = bodyOf(bodies, bi);
    sum += double(s.invMass) * li.dot(lj) + ai.dot(s.invInertia.cast<double>() * aj);
  };
  side(i.a, i.linA, i.angA, j.a, j.linA, j.angA);
  side(i.a, i.linA, i.angA, j.b, j.linB, j.angB);
  side(i.b, i.linB, i.angB, j.a, j.linA, j.angA);
  side(i.b, i.linB, i.angB, j.b, j.linB, j.angB);
  return sum;
}

void applyRow(const Row& r, double impulse, std::vector<SolverBody>& bodies) {
  auto apply = [&](int bi, const Vec3d& lin, const Vec3d& ang) {
    if (bi < 0) return;
    SolverBody& s = bodies[static_cast<std::size_t>(bi)];
    s.v += (double(s.invMass) * impulse * lin).cast<Real>();
    s.w += (s.invInertia.cast<double>() * (impulse * ang)).cast<Real>();
  };
  apply(r.a, r.linA, r.angA);
  apply(r.b, r.linB, r.angB);
}

}  // namespace

double lcpRowVelocity(const LcpRow& r, const std::vector<SolverBody>& bodies) {
  return rowVelocity(r, bodies);
}

double lcpDelassus(const LcpRow& i, const LcpRow& j, const std::vector<SolverBody>& bodies) {
  return delassus(i, j, bodies);
}

// The rows of one constraint, with the pgs solver's right-hand side (contact_solver.cpp).
void appendContactRows(const ContactConstraint& c, int ci, const std::vector<SolverBody>& bodies,
                       const BiasMode& mode, std::vector<LcpRow>& rows, int& groups) {
  const SolverBody& a = bodyOf(bodies, c.bodyA);
  const SolverBody& b = bodyOf(bodies, c.bodyB);
  const Vec3d n = c.normal.cast<double>();
  auto linear = [&](const ConstraintPoint& p, const Vec3d& d, RowKind kind, int point, int axis) {
    Row r;
    r.a = c.bodyA;
    r.b = c.bodyB;
    const Vec3d rA = p.rA.cast<double>(), rB = p.rB.cast<double>();
    r.linA = -d;
    r.angA = -rA.cross(d);
    r.linB = d;
    r.angB = rB.cross(d);
    r.kind = kind;
    r.constraint = ci;
    r.point = point;
    r.axis = axis;
    return r;
  };
  auto angular = [&](const Vec3d& axisDir, RowKind kind, int axis) {
    Row r;
    r.a = c.bodyA;
    r.b = c.bodyB;
    r.angA = -axisDir;
    r.angB = axisDir;
    r.kind = kind;
    r.constraint = ci;
    r.axis = axis;
    return r;
  };
  const Vec3d dp = (b.dp - a.dp).cast<double>();
  for (int i = 0; i < c.pointCount; ++i) {
    const ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
    if (p.normalMass <= 0) continue;
    // The separation now, from the bodies' motion since the step's start; the bias as pgs.
    const Vec3 d = (b.dq * p.rB - a.dq * p.rA);
    const double s = (dp + d.cast<double>()).dot(n) + double(p.adjustedSeparation);
    double bias = 0;
    if (s > 0) {
      bias = s * double(mode.invH);
    } else if (mode.useBias) {
      bias = std::max(
          double(mode.baumgarte) * double(mode.invH) * std::min(s + double(mode.linearSlop), 0.0),
          -double(mode.pushVelocity));
    }
    Row r = linear(p, n, RowKind::Normal, i, 0);
    r.rhs = rowVelocity(r, bodies) + bias;
    rows.push_back(r);
    if (c.friction > 0) {
      const int g = groups++;
      for (int k = 0; k < 2; ++k) {
        if (p.tangentMass[static_cast<std::size_t>(k)] <= 0) continue;
        Row t = linear(p, c.tangent[static_cast<std::size_t>(k)].cast<double>(), RowKind::Tangent,
                       i, k);
        t.rhs = rowVelocity(t, bodies);
        t.coefficient = c.friction;
        t.group = g;
        rows.push_back(t);
      }
    }
  }
  if (c.rolling > 0) {
    const int g = groups++;
    for (int k = 0; k < 2; ++k) {
      if (c.rollingMass[static_cast<std::size_t>(k)] <= 0) continue;
      Row r = angular(c.tangent[static_cast<std::size_t>(k)].cast<double>(), RowKind::Rolling, k);
      r.rhs = rowVelocity(r, bodies);
      r.coefficient = c.rolling;
      r.group = g;
      rows.push_back(r);
    }
  }
  if (c.spinning > 0 && c.spinningMass > 0) {
    Row r = angular(n, RowKind::Spinning, 0);
    r.rhs = rowVelocity(r, bodies);
    r.coefficient = c.spinning;
    r.group = groups++;
    rows.push_back(r);
  }
}

namespace {

// The normal rows that bound row `i`'s box: its point's normal (friction) or every normal of
// its constraint (rolling, spinning).
template <class F>
void forEachSource(const std::vector<Row>& rows, std::size_t i, F&& f) {
  const Row& r = rows[i];
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const Row& s = rows[j];
    if (s.kind != RowKind::Normal || s.constraint != r.constraint) continue;
    if (r.kind == RowKind::Tangent && s.point != r.point) continue;
    f(j);
  }
}

// The previous impulse of a row (the warm start), for Dantzig's first friction bounds.
double storedImpulse(const Row& r, const std::vector<ContactConstraint>& cs) {
  if (r.store != nullptr) return double(*r.store);
  const ContactConstraint& c = cs[static_cast<std::size_t>(r.constraint)];
  const ConstraintPoint& p = c.points[static_cast<std::size_t>(r.point)];
  switch (r.kind) {
    case RowKind::Normal:
      return p.normalImpulse;
    case RowKind::Tangent:
      return p.tangentImpulse[static_cast<std::size_t>(r.axis)];
    case RowKind::Rolling:
      return c.rollingImpulse[static_cast<std::size_t>(r.axis)];
    case RowKind::Spinning:
      return c.spinningImpulse;
    default:
      return 0;
  }
}

// Dantzig's box of a row that no normal row bounds.
void fixedBounds(const Row& r, double& lo, double& hi) {
  switch (r.kind) {
    case RowKind::Bilateral:
      lo = -kUnbounded;
      hi = kUnbounded;
      return;
    case RowKind::Boxed:
      lo = -r.bound;
      hi = r.bound;
      return;
    default:  // Normal, Limit
      lo = 0;
      hi = kUnbounded;
  }
}

bool oneSided(const Row& r) { return r.kind == RowKind::Normal || r.kind == RowKind::Limit; }
bool frictionLike(const Row& r) {
  return r.kind == RowKind::Tangent || r.kind == RowKind::Rolling || r.kind == RowKind::Spinning;
}

}  // namespace

// Physical impulses (z = D y) from the solution of the chosen LCP.
bool solveLcpRows(const std::vector<Row>& rows, const std::vector<ContactConstraint>& cs,
                  const std::vector<SolverBody>& bodies, LcpMethod method,
                  Eigen::VectorXd& impulses, LcpContactStats* stats) {
  const auto n = static_cast<Eigen::Index>(rows.size());
  if (n > kMaxLcpUnknowns) return false;
  // Jacobi scaling: A' = D A D + eps I with D = diag(A)^-1/2, b' = D b, z = D y; a soft row's
  // compliance on its diagonal first.
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j <= i; ++j)
      A(i, j) = A(j, i) =
          delassus(rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(j)], bodies);
  for (Eigen::Index i = 0; i < n; ++i) A(i, i) += rows[static_cast<std::size_t>(i)].cfm;
  Eigen::VectorXd D(n), b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    D[i] = A(i, i) > 0 ? 1 / std::sqrt(A(i, i)) : 1.0;
    b[i] = D[i] * rows[static_cast<std::size_t>(i)].rhs;
  }
  A = D.asDiagonal() * A * D.asDiagonal();
  A.diagonal().array() += kRegularisation;

  if (method == LcpMethod::Dantzig) {
    if (stats) stats->largest = std::max(stats->largest, static_cast<int>(n));
    BoxedLcp p;
    p.A = std::move(A);
    p.b = b;
    p.lo = Eigen::VectorXd::Zero(n);
    p.hi = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd y(n);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      y[ii] = storedImpulse(rows[i], cs) / D[ii];
      if (!frictionLike(rows[i])) {
        fixedBounds(rows[i], p.lo[ii], p.hi[ii]);
        p.lo[ii] /= D[ii];  // y = z / D
        p.hi[ii] /= D[ii];
        continue;
      }
      // |z_i| <= c sum z_n  <=>  |y_i| <= c sum (D_n / D_i) y_n
      forEachSource(rows, i, [&](std::size_t j) {
        p.links.push_back({static_cast<int>(i), static_cast<int>(j),
                           rows[i].coefficient * D[static_cast<Eigen::Index>(j)] / D[ii]});
      });
    }
    const LcpResult r = solveDantzig(p, y);
    if (!r.converged) return false;
    if (stats) stats->maxResidual = std::max(stats->maxResidual, r.residual);
    impulses = D.cwiseProduct(y);
    return true;
  }

  // Lemke, Stewart-Trinkle form. Unknowns: the normal rows, then per friction row two
  // directions (+ and -), then one slack per group.
  std::vector<Eigen::Index> normalRows, dirRow, groupOf;
  std::vector<double> dirSign;
  int groupCount = 0;
  // A bilateral row is two directions without a slack (z+ _|_ w >= 0, z- _|_ -w >= 0 hold w
  // at 0); a boxed one two directions whose slack's limit is its bound.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (oneSided(rows[i])) {
      normalRows.push_back(static_cast<Eigen::Index>(i));
      continue;
    }
    for (double sign : {1.0, -1.0}) {
      dirRow.push_back(static_cast<Eigen::Index>(i));
      dirSign.push_back(sign);
      groupOf.push_back(rows[i].kind == RowKind::Bilateral ? -1 : rows[i].group);
    }
    groupCount = std::max(groupCount, rows[i].group + 1);
  }
  // Groups are numbered over all constraints; renumber the island's densely.
  std::vector<int> groupIndex(static_cast<std::size_t>(groupCount), -1);
  int groups = 0;
  for (Eigen::Index& g : groupOf) {
    if (g < 0) continue;
    int& slot = groupIndex[static_cast<std::size_t>(g)];
    if (slot < 0) slot = groups++;
    g = slot;
  }
  const auto nn = static_cast<Eigen::Index>(normalRows.size());
  const auto nd = static_cast<Eigen::Index>(dirRow.size());
  const Eigen::Index m = nn + nd + groups;
  if (stats) stats->largest = std::max(stats->largest, static_cast<int>(m));
  if (m > kMaxLcpUnknowns) return false;
  // Unknown k's physical row and sign.
  auto rowOf = [&](Eigen::Index k) {
    return k < nn ? normalRows[static_cast<std::size_t>(k)]
                  : dirRow[static_cast<std::size_t>(k - nn)];
  };
  auto signOf = [&](Eigen::Index k) {
    return k < nn ? 1.0 : dirSign[static_cast<std::size_t>(k - nn)];
  };
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m);
  for (Eigen::Index i = 0; i < nn + nd; ++i) {
    q[i] = signOf(i) * b[rowOf(i)];
    for (Eigen::Index j = 0; j < nn + nd; ++j)
      M(i, j) = signOf(i) * signOf(j) * A(rowOf(i), rowOf(j));
  }
  for (Eigen::Index k = 0; k < nd; ++k) {
    if (groupOf[static_cast<std::size_t>(k)] < 0) continue;
    const Eigen::Index g = nn + nd + groupOf[static_cast<std::size_t>(k)];
    const double scale = D[dirRow[static_cast<std::size_t>(k)]];
    M(nn + k, g) = scale;   // w_beta = D^T v+ + gamma (times the row's scale)
    M(g, nn + k) = -scale;  // w_gamma = c z_n - sum beta
  }
  std::vector<char> linked(static_cast<std::size_t>(groups), 0);
  for (Eigen::Index k = 0; k < nd; ++k) {
    if (groupOf[static_cast<std::size_t>(k)] < 0) continue;
    const auto g = static_cast<std::size_t>(groupOf[static_cast<std::size_t>(k)]);
    if (linked[g]) continue;
    linked[g] = 1;
    const auto i = static_cast<std::size_t>(dirRow[static_cast<std::size_t>(k)]);
    if (rows[i].kind == RowKind::Boxed) {  // w_gamma = bound - sum beta
      q[nn + nd + static_cast<Eigen::Index>(g)] = rows[i].bound;
      continue;
    }
    forEachSource(rows, i, [&](std::size_t j) {
      const auto jn = static_cast<Eigen::Index>(
          std::find(normalRows.begin(), normalRows.end(), static_cast<Eigen::Index>(j)) -
          normalRows.begin());
      M(nn + nd + static_cast<Eigen::Index>(g), jn) +=
          rows[i].coefficient * D[static_cast<Eigen::Index>(j)];
    });
  }
  // Warm start from the stored impulses: normals, each direction's share of its friction
  // row, and a positive slack where the friction was at its limit (sliding).
  Eigen::VectorXd x = Eigen::VectorXd::Zero(m);
  for (Eigen::Index k = 0; k < nn + nd; ++k) {
    const Eigen::Index row = rowOf(k);
    x[k] =
        std::max(signOf(k) * storedImpulse(rows[static_cast<std::size_t>(row)], cs) / D[row], 0.0);
  }
  for (Eigen::Index g = 0; g < groups; ++g) {
    const Eigen::Index slack = nn + nd + g;
    const double limit = q[slack] + M.row(slack).head(nn).dot(x.head(nn));
    const double used = -M.row(slack).segment(nn, nd).dot(x.segment(nn, nd));
    if (limit > 0 && used >= (1 - 1e-6) * limit) x[slack] = 1;
  }
  const LcpResult r = solveLemke(M, q, x);
  if (!r.converged) return false;
  if (stats) stats->maxResidual = std::max(stats->maxResidual, r.residual);
  impulses = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < nn + nd; ++k) impulses[rowOf(k)] += signOf(k) * x[k];
  impulses = D.cwiseProduct(impulses);
  return true;
}

namespace {

void storeImpulse(const Row& r, double impulse, std::vector<ContactConstraint>& cs) {
  const auto value = static_cast<Real>(impulse);
  if (r.store != nullptr) {
    *r.store = value;
    return;
  }
  ContactConstraint& c = cs[static_cast<std::size_t>(r.constraint)];
  ConstraintPoint& p = c.points[static_cast<std::size_t>(r.point)];
  switch (r.kind) {
    case RowKind::Normal:
      p.normalImpulse = value;
      p.maxNormalImpulse = std::max(p.maxNormalImpulse, value);
      break;
    case RowKind::Tangent:
      p.tangentImpulse[static_cast<std::size_t>(r.axis)] = value;
      break;
    case RowKind::Rolling:
      c.rollingImpulse[static_cast<std::size_t>(r.axis)] = value;
      break;
    case RowKind::Spinning:
      c.spinningImpulse = value;
      break;
    default:
      break;
  }
}

void clearImpulses(ContactConstraint& c) {
  for (ConstraintPoint& p : c.points) {
    p.normalImpulse = 0;
    p.tangentImpulse = {};
  }
  c.rollingImpulse = {};
  c.spinningImpulse = 0;
}

}  // namespace

void applyLcpImpulses(const std::vector<LcpRow>& rows, const Eigen::VectorXd& impulses,
                      std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies) {
  for (const Row& r : rows)
    if (r.store == nullptr) clearImpulses(cs[static_cast<std::size_t>(r.constraint)]);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double z = impulses[static_cast<Eigen::Index>(r)];
    applyRow(rows[r], z, bodies);
    storeImpulse(rows[r], z, cs);
  }
}

void solveContactsLcp(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      const BiasMode& mode, LcpMethod method, int fallbackIterations,
                      const ConstraintIslands& islands, LcpWorkspace& ws, LcpContactStats* stats) {
  BiasMode rigid = mode;
  rigid.soft = false;
  std::vector<Row>& rows = ws.rows;
  std::vector<ContactConstraint>& scratch = ws.scratch;
  Eigen::VectorXd& impulses = ws.impulses;
  for (std::size_t i = 0; i + 1 < islands.offsets.size(); ++i) {
    const std::span<const std::uint32_t> island(islands.constraints.data() + islands.offsets[i],
                                                islands.offsets[i + 1] - islands.offsets[i]);
    if (stats) ++stats->islands;
    rows.clear();
    int groups = 0;
    for (std::uint32_t ci : island) appendContactRows(cs[ci], int(ci), bodies, rigid, rows, groups);
    if (solveLcpRows(rows, cs, bodies, method, impulses, stats)) {
      if (stats) ++stats->direct;
      applyLcpImpulses(rows, impulses, cs, bodies);
      continue;
    }
    // Fallback: the pgs iterations on this island, warm started as the pgs solver is.
    if (stats) ++stats->fallbacks;
    scratch.clear();
    for (std::uint32_t ci : island) scratch.push_back(cs[ci]);
    warmStart(scratch, bodies);
    for (int it = 0; it < fallbackIterations; ++it) solve(scratch, bodies, rigid);
    for (std::size_t k = 0; k < scratch.size(); ++k) cs[island[k]] = scratch[k];
  }
}

void solveContactsLcp(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      const BiasMode& mode, LcpMethod method, int fallbackIterations,
                      LcpContactStats* stats) {
  // Islands: constraints connected through a shared solver body (static bodies do not link).
  std::vector<GraphEdge> edges;
  for (const ContactConstraint& c : cs) edges.push_back({c.bodyA, c.bodyB});
  ConstraintIslands islands;
  groupConstraints(edges, bodies.size(), islands);
  LcpWorkspace ws;
  solveContactsLcp(cs, bodies, mode, method, fallbackIterations, islands, ws, stats);
}

}  // namespace inertia::detail
