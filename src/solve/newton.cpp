#include "solve/newton.hpp"

#include <cfloat>
#include <cmath>

#include "common/error.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"

namespace nd {

namespace {

// ||x|| over the rows of `rows`, each rank's sum of squares added rank after
// rank (the same bits on every rank); no share: norm2 over all n. Collective
// with a share.
double norm2_rows(const Share *rows, int64_t n, const double *x) {
  if (!rows) return norm2(n, x);
  double sum = 0;
  for (const int64_t *i = rows->own_begin(); i != rows->own_end(); ++i) sum += x[*i] * x[*i];
  gather(*rows, {}, &sum, 1);
  return std::sqrt(sum);
}

}  // namespace

double newton_residual(const NewtonSystem &sys, const std::vector<double> &r, const std::vector<double> &U,
                       std::vector<double> &G, std::vector<char> *active, std::vector<double> &MU,
                       PointValues *points, bool known) {
  count(sys.law->counters, &Counters::spmv);
  auto keep = [&](int64_t i, double AU, double MUi) __attribute__((always_inline)) {
    G[i] = AU;
    MU[i] = MUi;
  };
  auto keep_block = [&](int64_t i, double AU, double MUi, double, double) __attribute__((always_inline)) {
    keep(i, AU, MUi);
  };
  // by nodes in one process (the same bits), else on the CSR pattern
  if (!for_node_rows<true, false>(sys.rows ? nullptr : sys.blocks, U.data(), U.data(), nullptr, keep_block))
    multiply_pair(*sys.A, U.data(), *sys.M, U.data(), keep, own_rows(sys.rows));
  if (sys.rows && !sys.split) gather(*sys.rows, {G.data(), MU.data()});
  if (points && known) {
    points->un.clear();
    sys.law->add_force_from(points->P, sys.kappa, G.data(), active);
  } else if (points) {
    sys.law->add_force(U.data(), sys.kappa, G.data(), active, &points->P, &points->un);
  } else {
    sys.law->add_force(U.data(), sys.kappa, G.data(), active);
  }
  const RowSet rows = own_rows(sys.held_rows());
  for (int64_t k = 0, m = rows.size(static_cast<int64_t>(G.size())); k < m; ++k) G[rows[k]] -= r[rows[k]];
  return rhs_norm(sys, G);
}

double newton_residual_from_products(const NewtonSystem &sys, const Products &p, const std::vector<double> &U,
                                     const std::vector<double> &r, std::vector<double> &G) {
  static const std::vector<double> none;
  StepInputs{p, *sys.law->cp, sys.law->theta, none, none}.k_theta_u(U, G);  // K_Theta U
  for (size_t i = 0; i < G.size(); ++i) G[i] += sys.c * p.MU[i];
  sys.law->add_force_from(p.points.P, sys.kappa, G.data(), nullptr);
  for (size_t i = 0; i < G.size(); ++i) G[i] -= r[i];
  return rhs_norm(sys, G);
}

double newton_tolerance(const NewtonSystem &sys, const NewtonOptions &opt, double r_norm,
                        const std::vector<double> &MU) {
  return opt.rtol * (r_norm + sys.c * rhs_norm(sys, MU)) + opt.atol;
}

double rhs_norm(const NewtonSystem &sys, const std::vector<double> &r) {
  return norm2_rows(sys.held_rows(), static_cast<int64_t>(r.size()), r.data());
}

std::vector<int64_t> newton_held_rows(const Csr &A, const Share &rows, const ContactPoints &cp,
                                      const std::vector<const Csr *> &also, const std::vector<int64_t> *points) {
  return rows_and_points(A.n, rows, cp, &A, also, points);
}

namespace {

// partial: set when a solve left U right at the tangent's held rows only
NewtonResult iterate(const NewtonSystem &sys, const std::vector<double> &r, const NewtonOptions &opt,
                     std::vector<double> &U, bool &partial, PointValues *points) {
  const int64_t n = static_cast<int64_t>(U.size());
  NewtonResult res;
  int first = 1;
  NewtonWork own;
  NewtonWork &w = sys.work ? *sys.work : own;
  // the points at U, from the residual (or the check) there: for the tangent
  // at U, and at the solution the new state's
  PointValues &at = w.at;
  clear_keeping_memory(at);
  // docs/design.md §4: no point active at the predictor, so none can start unless the
  // linear step says so: one solve U = A^{-1} r and one check. Where no point
  // is active at U either, N vanishes there and U solves G(U) = 0 exactly
  // (to the solve's round-off): Newton's first iteration would only repeat it.
  if (opt.max_iter >= 1 && sys.law->contact_free(U, &at.P)) {
    // the predictor: where the solve is iterative, its start (a copy for
    // the step: nothing n long is kept between steps, none made for a
    // direct solve, which would not read it)
    std::vector<double> predictor;
    if (sys.guess) predictor = U;
    U = r;
    sys.tangent->solve(*sys.law, sys.kappa, U.data(), false, U.data(), sys.guess ? predictor.data() : nullptr);
    res.iterations = 1;
    if (sys.law->contact_free(U, &at.P, &res.bounded)) {
      res.converged = true;
      return res;
    }
    first = 2;  // contact starts within the step: Newton from the linear step
  }
  std::vector<double> &G = w.G, &MU = w.MU;
  G.assign(U.size(), 0.0), MU.assign(U.size(), 0.0);
  std::vector<char> &active = w.active, &previous = w.previous;
  active.clear(), previous.clear();
  const double r_norm = rhs_norm(sys, r);
  // (the check's pass at this U, if it made one: P_q is not evaluated twice)
  res.residual = newton_residual(sys, r, U, G, &active, MU, &at, !at.P.empty());
  bool any_active = false, changed = true;
  sys.law->summarize(active, previous, any_active, changed);
  // the line search of laws with more than one value per point (friction); the
  // others' iterates, and their bits, are Newton's own
  const bool search = sys.law->cp->m > 1;
  for (int it = first; it <= opt.max_iter; ++it) {
    if (!std::isfinite(res.residual))
      fail(ND_ERR_NONFINITE_STATE, "the Newton residual is not finite at iteration " + std::to_string(it));
    for (auto &g : G) g = -g;
    sys.tangent->solve(*sys.law, sys.kappa, U.data(), any_active, G.data(), nullptr, &at.P);
    partial |= any_active && sys.tangent->held();
    if (search) w.direction = G, w.from = U;
    for (int64_t i = 0; i < n; ++i) U[i] += G[i];
    // (the full update's size, whatever the line search takes of it: an
    // update at round-off is Newton's, not a short step's)
    const double step = norm2_rows(sys.held_rows(), n, G.data());
    previous.swap(active);
    const double before = res.residual;
    res.residual = newton_residual(sys, r, U, G, &active, MU, &at);
    // (friction) a step that raised the residual is halved until it lowers it
    // (Armijo): the semi-smooth Newton of a point between sticking and
    // sliding otherwise may alternate between two iterates for ever
    for (double lambda = 0.5; search && !(res.residual <= (1 - 1e-4 * 2 * lambda) * before) && lambda > 1e-3;
         lambda *= 0.5) {
      for (int64_t i = 0; i < n; ++i) U[i] = w.from[i] + lambda * w.direction[i];
      res.residual = newton_residual(sys, r, U, G, &active, MU, &at);
    }
    sys.law->summarize(active, previous, any_active, changed);
    res.iterations = it;
    const double u_norm = norm2_rows(sys.held_rows(), n, U.data());
    res.tolerance = newton_tolerance(sys, opt, r_norm, MU);
    // A point whose P_q sits at zero to round-off can flip at every
    // iteration without changing G or U (seen in a test: P_q = +-5e-18,
    // flipping until the iteration limit): a small residual with an update
    // at round-off is converged whatever the flips.
    const bool small = res.residual <= res.tolerance, still = step <= 64 * DBL_EPSILON * u_norm;
    if ((!changed && (small || still)) || (small && still)) {
      res.converged = true;
      // the points at the solution, every one of them (un made with P; with
      // friction P also holds the tangential values, at the slip reference
      // the new state starts with): the new state's
      if (points && !partial && !at.P.empty() && at.P.size() == sys.law->values() &&
          at.un.size() == sys.law->cp->size())
        std::swap(*points, at);
      return res;
    }
  }
  return res;
}

}  // namespace

NewtonResult newton_solve(const NewtonSystem &sys, const std::vector<double> &r, const NewtonOptions &opt,
                          std::vector<double> &U, PointValues *points) {
  bool partial = false;
  const NewtonResult res = iterate(sys, r, opt, U, partial, points);
  if (partial && sys.complete) gather(*sys.rows, {U.data()});  // the rows other ranks own
  return res;
}

}  // namespace nd
