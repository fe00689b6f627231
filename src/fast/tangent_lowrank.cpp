// The low-rank tangent solver (docs/design.md §4, the dense/sparse Newton step): the
// factor of A = c M + K_Theta is reused through contact and T = A + B D P^T is
// solved by the Woodbury identity over the k active points,
//   T^{-1} x = y - Z w,  (I + D G) w = D P^T y,  y = A^{-1} x,  Z = A^{-1} B,  G = P^T Z.
// The scaled capacitance I + D G (non-symmetric unless Theta = 1) needs no
// 1/D and is solved by LAPACK's LU. det T = det A det(I + D G), so it is
// singular exactly when T is.
//
// Past its rank limit, T is solved by the updated factor (make_updown_tangent)
// where it applies, else refactored.
//
// Cached for the solver's lifetime (A is fixed per step size, solve/
// contact_columns.hpp): Z_q = A^{-1} b_q per point, made on first activation,
// and G over the last active set, of which the entries of points that stay
// active are kept. A Newton iteration in persistent contact costs
// one solve with A's factor, k sparse dot products, the k x k triangular solves
// with the capacitance's LU (kept while the active set and D stay) and n k for
// Z w (or, past two_solve_rank, and always when the columns are held at the
// points' DOFs alone, a second solve). Only D changes between iterations (the
// slopes), so only I + D G is rebuilt.
#include <lapacke.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "nitschedyn.h"
#include "fast/contact_columns.hpp"
#include "fast/tangents.hpp"

namespace nd {

void require_rank_one_updates(const ContactLaw &law, const char *who) {
  if (!rank_one_updates_apply(law.traits()))
    fail(ND_ERR_INTERNAL, std::string(who) + " adds rank-one terms with a nonnegative slope, which the contact law " +
                              law.law_object().name() +
                              " does not promise (LawTraits): the refactoring tangent serves it");
}
namespace {

class LowRankTangent : public TangentSolver {
 public:
  LowRankTangent(const Csr &A, const Factorization &A_factor, int solver, Structure s, int64_t max_rank,
                 int64_t two_solve_rank, Counters *counters, const DofGeometry *geometry, ContactColumns *shared)
      : A_(A), A_factor_(A_factor), solver_(solver), structure_(s), max_rank_(max_rank),
        two_solve_rank_(two_solve_rank), counters_(counters), geometry_(geometry) {
    if (!shared)  // the memory bound: past 2 max_rank columns, those of inactive points are dropped
      own_columns_ = std::make_unique<ContactColumns>(A_factor, A.n, max_rank >= 0 ? 2 * max_rank : INT64_MAX);
    columns_ = shared ? shared : own_columns_.get();
  }

  void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
             const double *guess, const std::vector<double> *P_U) override {
    ++stats.calls;
    if (solved_without_contact(A_factor_, any_active, x, guess)) return;
    require_rank_one_updates(law, "the low-rank tangent");
    if (columns_->bind(*law.cp, law.theta)) lu_valid_ = false;
    theta_ = law.theta;
    const ContactPoints &cp = *law.cp;
    active_.clear();
    d_.clear();
    const std::vector<double> &P = law.P_at(U, P_U, P_scratch_);
    const bool pp = law.positive_part();
    for (size_t q = 0; q < cp.size(); ++q) {
      double value, slope;
      law.law(q, P[q], value, slope, pp);
      if (slope == 0) continue;
      active_.push_back(static_cast<int64_t>(q));
      d_.push_back(kappa * cp.w[q] / cp.gamma[q] * slope);
    }
    const int64_t k = static_cast<int64_t>(active_.size());
    stats.max_rank = std::max(stats.max_rank, k);
    if (k == 0) {
      solve_y(x);
      return;
    }
    if (max_rank_ >= 0 && k > max_rank_) {  // the refactorization is cheaper here
      if (!fallback_) {
        fallback_ = updown_tangent_applies(solver_, structure_)
                        ? make_updown_tangent(A_, A_factor_, counters_)
                        : make_refactoring_tangent(A_, A_factor_, solver_, structure_, counters_, geometry_);
        fallback_->begin_step(committed_);
      }
      const TangentStats before = fallback_->stats;
      fallback_->solve(law, kappa, U, true, x, nullptr, &P);  // (the points just read)
      stats.refactorizations += fallback_->stats.refactorizations - before.refactorizations;
      stats.restarts += fallback_->stats.restarts - before.restarts;
      return;
    }
    ++stats.lowrank;
    columns_->require(active_);
    stats.columns = columns_->computed();
    // (columns held at the points' DOFs alone: Z w is not whole, the second solve is)
    const bool two_solves = (two_solve_rank_ >= 0 && k > two_solve_rank_) || !columns_->sums_whole();
    if (two_solves) x0_.assign(x, x + A_.n);
    solve_y(x);  // y
    // (I + D G) w = D P^T y; its LU is kept while the active set and D stay
    // (persistent contact: the slopes are piecewise constant), so such an
    // iteration pays k^2, not 2/3 k^3; the same LU gives the same bits
    factor_capacitance(k, columns_->G(active_));
    w_.resize(static_cast<size_t>(k));
    for (int64_t i = 0; i < k; ++i) w_[i] = d_[i] * p_dot(cp, active_[i], x);
    const lapack_int info = LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', static_cast<lapack_int>(k), 1, C_.data(),
                                           static_cast<lapack_int>(k), ipiv_.data(), w_.data(),
                                           static_cast<lapack_int>(k));
    if (info < 0) fail(ND_ERR_INTERNAL, "LAPACKE_dgetrs: argument " + std::to_string(-info));
    if (two_solves) {  // x = A^{-1} (x0 - B w): a second solve instead of the n k of Z w
      for (int64_t j = 0; j < k; ++j) add_b(cp, theta_, static_cast<size_t>(active_[j]), -w_[j], x0_.data());
      std::copy(x0_.begin(), x0_.end(), x);
      solve_y(x);
      return;
    }
    columns_->subtract_blocked(active_, w_.data(), x);  // the n k of Z w: the largest cost after the solve
    columns_->complete(x);
  }
  const char *name() const override { return "lowrank"; }
  // the history is the fallback's (the updated factor's), kept for it until it is made
  void begin_step(const TangentLog &committed) override {
    if (fallback_) fallback_->begin_step(committed);
    else if (committed != committed_) committed_ = committed;
  }
  const TangentLog *log() const override { return fallback_ ? fallback_->log() : &committed_; }

 private:
  // x <- A^{-1} x: whole, or at a distributed state's rows when the columns
  // are held there (all a step reads: no completion)
  void solve_y(double *x) const {
    if (columns_->holds_state()) columns_->solve_held(x);
    else A_factor_.solve(x);
  }
  // the LU of I + D G into C_, ipiv_, unless it is that of this active set and D
  void factor_capacitance(int64_t k, const std::vector<double> &G) {
    if (lu_valid_ && lu_active_ == active_ && lu_d_ == d_) return;
    lu_valid_ = false;  // stays false if anything below throws
    count(counters_, &Counters::tangent_updates);  // a capacitance build
    C_.resize(static_cast<size_t>(k * k));  // every entry is written below
    for (int64_t j = 0; j < k; ++j)
      for (int64_t i = 0; i < k; ++i) C_[i + j * k] = d_[i] * G[i + j * k] + (i == j ? 1.0 : 0.0);
    ipiv_.resize(static_cast<size_t>(k));
    // the _work variants skip LAPACKE's NaN scan of the k x k input (a pass
    // over k^2 entries for nothing); a NaN would reach Newton's residual,
    // which is checked
    const lapack_int info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, static_cast<lapack_int>(k), static_cast<lapack_int>(k),
                                           C_.data(), static_cast<lapack_int>(k), ipiv_.data());
    if (info > 0)
      fail(ND_ERR_SINGULAR, "the Newton tangent is singular (capacitance pivot " + std::to_string(info) + " of " +
                                std::to_string(k) + " active contact points is zero)");
    if (info < 0) fail(ND_ERR_INTERNAL, "LAPACKE_dgetrf: argument " + std::to_string(-info));
    lu_active_ = active_;
    lu_d_ = d_;
    lu_valid_ = true;
  }
  const Csr &A_;
  const Factorization &A_factor_;
  int solver_;
  Structure structure_;
  int64_t max_rank_, two_solve_rank_;
  Counters *counters_;
  const DofGeometry *geometry_;
  std::unique_ptr<TangentSolver> fallback_;
  TangentLog committed_;  // the step's starting history, until fallback_ is made
  std::unique_ptr<ContactColumns> own_columns_;
  ContactColumns *columns_;  // own_columns_, or the integrator's (shared with the condensed Newton)
  double theta_ = 0;
  std::vector<int64_t> active_;
  std::vector<double> d_, C_, w_, x0_;
  std::vector<double> P_scratch_;  // P_q at U when the caller has none (reused)
  std::vector<lapack_int> ipiv_;
  // the capacitance LU in C_, ipiv_ holds for this active set and D
  bool lu_valid_ = false;
  std::vector<int64_t> lu_active_;
  std::vector<double> lu_d_;
};

}  // namespace

std::unique_ptr<TangentSolver> make_lowrank_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                    Structure structure, int64_t max_rank,
                                                    int64_t two_solve_rank, Counters *counters,
                                                    const DofGeometry *geometry, ContactColumns *columns) {
  return std::make_unique<LowRankTangent>(A, A_factor, solver, structure, max_rank, two_solve_rank, counters,
                                          geometry, columns);
}

// The k x k LU (2/3 k^3) grows faster than a refactorization's cost: the
// limit 16 sqrt(n) stays below every crossover measured with
// bench/tangent_bench (docs/performance.md, "Low-rank tangent's rank
// limit"). The cached columns take n doubles each; at most
// 2 max_rank are kept, and max_rank <= 2^24 / n keeps them under 256 MB
// (on large 3D meshes this bound is the one that applies).
int64_t lowrank_rank_limit(int64_t n, const ContactPoints &cp) {
  const double by_time = 16.0 * std::sqrt(static_cast<double>(n));
  const double by_memory = static_cast<double>(int64_t(1) << 24) / static_cast<double>(std::max<int64_t>(n, 1));
  return std::max<int64_t>(1, static_cast<int64_t>(std::min(by_time, by_memory)));
}

}  // namespace nd
