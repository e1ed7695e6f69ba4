// Baraff and Witkin's modified preconditioned conjugate gradients (1998, section 5.3): CG on
// A dv = b where the constrained directions are filtered out of every search direction, so a
// pinned vertex's velocity change stays what the constraint prescribes (dv = z there).
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "inertia/ode/implicit.h"

namespace inertia::detail {

/// Work vectors of the solve, kept between steps (no allocation once sized).
struct PcgBuffers {
  Eigen::VectorXd r, c, q, s, filteredB;
  void resize(Eigen::Index n) {
    for (Eigen::VectorXd* v : {&r, &c, &q, &s, &filteredB})
      if (v->size() != n) v->resize(n);
  }
};

/// Solves A dv = b for the free components, dv holding the prescribed values z on entry
/// (zero where nothing is prescribed). `apply(w, out)` writes A w; `filter(w)` zeroes the
/// constrained components of w; `precondition(r, out)` writes P^-1 r for a symmetric positive
/// definite P (Jacobi's diagonal, or its 3 x 3 blocks).
/// Stops when r^T P^-1 r <= tolerance^2 * (filter(b)^T P^-1 filter(b)) or after maxIterations.
/// Reports the iterations and the relative residual |filter(b - A dv)| / |filter(b)|.
template <class Apply, class Filter, class Precondition>
ode::LinearSolveReport modifiedPcg(const Apply& apply, const Filter& filter,
                                   const Precondition& precondition, const Eigen::VectorXd& b,
                                   Eigen::VectorXd& dv, double tolerance, int maxIterations,
                                   PcgBuffers& w) {
  w.resize(b.size());
  w.filteredB = b;
  filter(w.filteredB);
  precondition(w.filteredB, w.s);
  const double delta0 = w.filteredB.dot(w.s);
  apply(dv, w.q);
  w.r = b - w.q;
  filter(w.r);
  precondition(w.r, w.c);
  filter(w.c);
  double deltaNew = w.r.dot(w.c);
  ode::LinearSolveReport report;
  while (deltaNew > tolerance * tolerance * delta0 && report.iterations < maxIterations) {
    apply(w.c, w.q);
    filter(w.q);
    const double curvature = w.c.dot(w.q);
    if (!(curvature > 0)) break;  // A not positive definite on the search direction
    const double alpha = deltaNew / curvature;
    dv += alpha * w.c;
    w.r -= alpha * w.q;
    precondition(w.r, w.s);
    const double deltaOld = deltaNew;
    deltaNew = w.r.dot(w.s);
    w.c = w.s + (deltaNew / deltaOld) * w.c;
    filter(w.c);
    ++report.iterations;
  }
  const double bNorm = w.filteredB.norm();
  report.error = bNorm > 0 ? w.r.norm() / bNorm : 0.0;
  report.converged = deltaNew <= tolerance * tolerance * delta0 && dv.allFinite();
  return report;
}

}  // namespace inertia::detail
