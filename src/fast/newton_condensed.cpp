#include "fast/newton_condensed.hpp"

#include <lapacke.h>

#include <string>

#include "common/error.hpp"
#include "fast/tangents.hpp"
#include "nitschedyn.h"

namespace nd {

struct CondensedCache::Lu {
  bool valid = false;
  std::vector<int64_t> S;
  std::vector<double> slope, LU;
  std::vector<lapack_int> ipiv;
};

CondensedCache::CondensedCache(ContactColumns &c) : columns(c) {}
CondensedCache::~CondensedCache() = default;

CondensedCache::Lu &CondensedCache::lu() {
  if (!lu_) lu_ = std::make_unique<Lu>();
  return *lu_;
}

namespace {

// U = y0 - sum_{j in S} c_j phi_j Z_j at the columns' held rows (every row
// but on split operators: then complete() gives the rest)
void form_U(const std::vector<double> &y0, const std::vector<int64_t> &S, const std::vector<double> &phi,
            const std::vector<double> &c, const ContactColumns &columns, std::vector<double> &f,
            std::vector<double> &U) {
  U = y0;
  f.resize(S.size());
  for (size_t j = 0; j < S.size(); ++j) f[j] = c[S[j]] * phi[j];
  columns.subtract_blocked(S, f.data(), U.data());
}

// U = y0 - A^{-1} sum_{j in S} c_j phi_j b_j, form_U's sum in exact
// arithmetic, for columns held at the points' DOFs alone: one solve of a
// right-hand side with the active points' few nonzeros (solve_many: its
// forward solve only where they reach)
void solve_U(const Factorization &A_factor, const ContactLaw &law, const std::vector<double> &y0,
             const std::vector<int64_t> &S, const std::vector<double> &phi, const std::vector<double> &c,
             std::vector<double> &U) {
  const int64_t n = static_cast<int64_t>(y0.size());
  U.assign(y0.size(), 0.0);
  for (size_t j = 0; j < S.size(); ++j)
    if (phi[j] != 0) add_b(*law.cp, law.theta, static_cast<size_t>(S[j]), c[S[j]] * phi[j], U.data());
  A_factor.solve_many(U.data(), n, 1);
  for (int64_t i = 0; i < n; ++i) U[i] = y0[i] - U[i];
}

}  // namespace

CondensedResult newton_condensed(const NewtonSystem &sys, const Factorization &A_factor, CondensedCache &cache,
                                 int64_t max_rank, const std::vector<double> &r, const NewtonOptions &opt,
                                 std::vector<double> &U, PointValues *points,
                                 const std::function<const Products &()> *products_at) {
  const ContactLaw &law = *sys.law;
  require_rank_one_updates(law, "the condensed Newton");
  const bool pp = law.positive_part();  // (asked once: law(..., pp) below)
  const ContactPoints &cp = *law.cp;
  const int64_t n = static_cast<int64_t>(U.size()), nq = static_cast<int64_t>(cp.size());
  ContactColumns &columns = cache.columns;
  if (columns.bind(cp, law.theta)) cache.lu().valid = false;
  CondensedResult out;
  NewtonResult &res = out.newton;

  CondensedCache::Work &w = cache.work;
  // S: the points active at the predictor; their P start there. c_q =
  // kappa w_q / gamma_q, read at S's points only, set as they join it
  std::vector<double> &P = w.P, &c = w.c;
  P.assign(static_cast<size_t>(nq), 0.0);
  c.resize(static_cast<size_t>(nq));
  std::vector<int64_t> &S = w.S;
  S.clear();
  auto join = [&](int64_t q) {
    S.push_back(q);
    c[q] = sys.kappa * cp.w[q] / cp.gamma[q];
  };
  std::vector<char> &active = w.active, &previous = w.previous;
  active.assign(static_cast<size_t>(nq), 0);
  if (!law.certainly_free(U)) {  // (shown free: S is empty, and P is P0 below)
    law.P_all(U.data(), P);
    for (int64_t q = 0; q < nq; ++q) {
      double v, s;
      law.law(q, P[q], v, s, pp);
      if (s != 0) join(q), active[q] = 1;
    }
  }
  // many points active already: the set will likely outgrow max_rank, and the
  // full Newton's tangent (refactoring there) does better; nothing done yet
  if (max_rank >= 0 && 2 * static_cast<int64_t>(S.size()) > max_rank) {
    out.too_large = true;
    return out;
  }
  std::vector<double> &y0 = w.y0;
  y0 = r;
  // points active at the predictor: y0 is read where the columns are held
  // (their P, the sums of columns), so on split rows only those rows travel
  bool y0_held = false;
  // (an iterative solve starts at the predictor; a distributed state's rows are all a step reads)
  if (S.empty() && !columns.holds_state()) A_factor.solve_from(y0.data(), U.data());
  else y0_held = columns.solve_held(y0.data(), S.empty() ? U.data() : nullptr);
  if (S.empty() && law.certainly_free(y0)) {
    // no point active at the predictor nor at U = A^{-1} r: the first
    // iteration below would find the set empty and stop there, with U = y0
    U.swap(y0);
    res.iterations = 1;
    res.converged = true;
    res.bounded = true;
    return out;
  }
  std::vector<double> &P0 = w.P0;
  law.P_all(y0.data(), P0);
  if (S.empty())  // no point active at the predictor: the linear step's P
    for (int64_t q = 0; q < nq; ++q) P[q] = P0[q];

  std::vector<double> &F = w.F, &phi = w.phi, &slope = w.slope, &dP = w.dP;
  std::vector<double> &Ut = w.Ut, &off_S = w.off_S;
  std::vector<char> &in_S = w.in_S;
  in_S.assign(static_cast<size_t>(nq), 0);
  for (int64_t q : S) in_S[q] = 1;
  for (int it = 1; it <= opt.max_iter; ++it) {
    res.iterations = it;
    const int64_t k = static_cast<int64_t>(S.size());
    if (max_rank >= 0 && k > max_rank) {
      out.too_large = true;
      return out;
    }
    columns.require(S);
    const std::vector<double> &G = columns.G(S);
    phi.resize(k), slope.resize(k), F.resize(k);
    for (int64_t j = 0; j < k; ++j) law.law(S[j], P[S[j]], phi[j], slope[j], pp);
    for (int64_t i = 0; i < k; ++i) {
      double sum = P[S[i]] - P0[S[i]];
      for (int64_t j = 0; j < k; ++j) sum += G[i + j * k] * c[S[j]] * phi[j];
      F[i] = sum;
    }
    // J dP = -F, J = I + G C diag(slope); its LU kept while S and the slopes stay
    dP.resize(k);
    for (int64_t i = 0; i < k; ++i) dP[i] = -F[i];
    if (k > 0) {
      CondensedCache::Lu &lu = cache.lu();
      if (!(lu.valid && lu.S == S && lu.slope == slope)) {
        lu.valid = false;  // stays false if anything below throws
        count(law.counters, &Counters::tangent_updates);
        lu.LU.resize(static_cast<size_t>(k * k));
        for (int64_t j = 0; j < k; ++j)
          for (int64_t i = 0; i < k; ++i)
            lu.LU[i + j * k] = G[i + j * k] * c[S[j]] * slope[j] + (i == j ? 1.0 : 0.0);
        lu.ipiv.resize(static_cast<size_t>(k));
        const lapack_int info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, static_cast<lapack_int>(k),
                                                    static_cast<lapack_int>(k), lu.LU.data(),
                                                    static_cast<lapack_int>(k), lu.ipiv.data());
        if (info > 0)
          fail(ND_ERR_SINGULAR, "the Newton tangent is singular (condensed pivot " + std::to_string(info) + " of " +
                                    std::to_string(k) + " contact points is zero)");
        if (info < 0) fail(ND_ERR_INTERNAL, "LAPACKE_dgetrf: argument " + std::to_string(-info));
        lu.S = S;
        lu.slope = slope;
        lu.valid = true;
      }
      const lapack_int info = LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', static_cast<lapack_int>(k), 1,
                                                  lu.LU.data(), static_cast<lapack_int>(k), lu.ipiv.data(),
                                                  dP.data(), static_cast<lapack_int>(k));
      if (info < 0) fail(ND_ERR_INTERNAL, "LAPACKE_dgetrs: argument " + std::to_string(-info));
    }
    for (int64_t i = 0; i < k; ++i) P[S[i]] += dP[i];
    // every point at the new iterate: on S as iterated, off S through G
    for (int64_t j = 0; j < k; ++j) law.law(S[j], P[S[j]], phi[j], slope[j], pp);
    previous.swap(active);
    active.assign(static_cast<size_t>(nq), 0);
    for (int64_t j = 0; j < k; ++j) active[S[j]] = slope[j] != 0;
    bool grew = false;
    // off S: through G's rows (k reads each where the columns keep their
    // dots, else 12 k), or through U where that is less
    bool any_force = false;
    for (int64_t j = 0; j < k; ++j) any_force |= phi[j] != 0;
    if (any_force) count(law.counters, &Counters::contact_evaluations);  // (none: P0's pass above)
    const bool through_U = any_force && !columns.keeps_dots() && (nq - k) * 24 > n;  // (no force: P = P0 off S)
    if (through_U) form_U(y0, S, phi, c, columns, w.f, Ut);
    // with the dots kept, P0 - sum_j (p_q . Z_j) c_j phi_j for every point,
    // column after column: each point's terms in the order of j, as the
    // point-by-point sum below adds them (the same bits), the kept dots read
    // as streams (point by point, the column lookups would dominate)
    const bool by_columns = any_force && !through_U && columns.keeps_dots();
    if (by_columns) {
      off_S.assign(P0.begin(), P0.end());
      for (int64_t j = 0; j < k; ++j) {
        if (phi[j] == 0) continue;
        const double *D = columns.kept_dots(S[j]), cj = c[S[j]], fj = phi[j];
        double *o = off_S.data();
        if (D)
          for (int64_t q = 0; q < nq; ++q) o[q] -= D[q] * cj * fj;
        else  // (a column whose dots are not kept: evaluated, as dot() does)
          for (int64_t q = 0; q < nq; ++q) o[q] -= columns.dot(static_cast<size_t>(q), S[j]) * cj * fj;
      }
    }
    if (any_force) {  // off S, each rank its own points, then gathered (on S, P as iterated)
      law.evaluate(in_S, P.data(), [&](size_t q) {
        if (through_U) return law.P(q, Ut.data());
        if (by_columns) return off_S[q];
        double Pq = P0[q];
        for (int64_t j = 0; j < k; ++j)
          if (phi[j] != 0) Pq -= columns.dot(q, S[j]) * c[S[j]] * phi[j];
        return Pq;
      });
    }
    for (int64_t q = 0; q < nq; ++q) {
      if (in_S[q]) continue;
      if (!any_force) P[q] = P0[q];
      const double Pq = P[q];
      double v, s;
      law.law(q, Pq, v, s, pp);
      if (s != 0) {
        join(q);
        in_S[q] = 1;
        active[q] = 1;
        grew = true;
      }
    }
    if (grew || active != previous) continue;
    // the set held through an iteration: F is linear there and the step solved it
    if (!any_force) U.swap(y0);  // no contact force: U = A^{-1} r
    else if (!columns.sums_whole()) solve_U(A_factor, law, y0, S, phi, c, U);
    else if (through_U) U.swap(Ut);
    else form_U(y0, S, phi, c, columns, w.f, U);
    if (any_force || y0_held) columns.complete(U.data());  // (Ut read only the points' DOFs, which are held)
    if (!any_force) {  // U = A^{-1} r with N(U) = 0: exact to the solve's round-off
      res.converged = true;
      return out;
    }
    // the full residual, docs/design.md §3's test: from the new state's products
    // where the caller makes them (G's bits differ from newton_residual's by
    // round-off; G only decides convergence here), else a pass over A and M
    std::vector<double> Gr, MU;
    PointValues at;
    const std::vector<double> *MU_at = &MU;
    if (products_at) {
      const Products &p = (*products_at)();
      res.residual = newton_residual_from_products(sys, p, U, r, w.G);
      MU_at = &p.MU;
    } else {
      Gr.resize(U.size()), MU.resize(U.size());
      res.residual = newton_residual(sys, r, U, Gr, nullptr, MU, &at);
    }
    res.tolerance = newton_tolerance(sys, opt, rhs_norm(sys, r), *MU_at);
    res.converged = res.residual <= res.tolerance;
    if (res.converged && points && !at.P.empty() && at.un.size() == at.P.size()) *points = std::move(at);
    return out;
  }
  return out;
}

}  // namespace nd
