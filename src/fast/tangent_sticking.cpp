// The Newton tangent of friction in 3D (docs/performance.md, "Friction"):
// a landing activates hundreds of points of d values each, so the columns
// of the Woodbury identity (tangent_blocks.cpp) cost more than a factor,
// and T itself changes at every iteration (the sliding directions) while
// most of it does not. So T is solved by GMRES, preconditioned by the
// factor of a sticking tangent
//   S = A + kappa sum_q (w_q/gamma_q) B_q diag(s_q, c, .., c) P_q^T
// over a set of points with their normal slopes s_q (c the rule's
// tangential weight, on the points whose tangential block was not zero):
// T - S is the sliding points' blocks less c I and the points that
// changed since S was made. S is kept while GMRES reaches its tolerance
// in kKeep iterations, and made anew from the current points when it does
// not; where GMRES with that S does not converge either, T is refactored
// (the reference tangent). T is applied without assembly: A x plus the
// points' blocks.
//
// Which points and slopes S was made from is the step's tangent history
// (TangentLog, time/state.hpp, in the updated factor's layout: nb, the
// points, then per point s_q + 2 [tangential]): a restart or a retried step
// makes the same S from its state, so the trajectories are bitwise those of
// the uninterrupted run.
#include <algorithm>

#include "contact/friction.hpp"
#include "linalg/gmres.hpp"
#include "fast/tangents.hpp"
#include "linalg/node_blocks.hpp"

namespace nd {
namespace {

// Relative residual of the linear Newton step: far below Newton's own
// tolerance (1e-10 by default), so that the iterates are Newton's to
// round-off as far as the solve decides; and the most iterations before T
// is refactored (a solve with S costs a small fraction of a factorization).
constexpr double kTolerance = 1e-13;
constexpr int kKeep = 20, kIterations = 40;
// GMRES keeps 2 k vectors of n: at most 2^23 values (64 MiB), whatever n
int iterations_for(int64_t n, int wanted) {
  return static_cast<int>(std::clamp<int64_t>((int64_t(1) << 22) / std::max<int64_t>(n, 1), 4, wanted));
}

class StickingTangent : public TangentSolver {
 public:
  StickingTangent(const Csr &A, const Factorization &A_factor, int solver, Structure s, Counters *c,
                  const DofGeometry *g, const NodeBlocks *A_blocks)
      : A_(A),
        A_blocks_(A_blocks),
        A_factor_(A_factor),
        solver_(solver),
        structure_(s),
        counters_(c),
        geometry_(g),
        S_(A) {}

  void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
             const double *guess, const std::vector<double> *P_U) override {
    ++stats.calls;
    if (solved_without_contact(A_factor_, any_active, x, guess)) return;
    const ContactPoints &cp = *law.cp;
    const int m = cp.m;
    const std::vector<double> &P = law.P_at(U, P_U, P_scratch_);
    const double c = tangential_weight(law.rule());
    // the active points' blocks kappa (w/gamma) J_q, and S's key
    active_.clear();
    D_.clear();
    key_.clear();
    double value[3], J[9];
    for (size_t q = 0; q < cp.size(); ++q) {
      law.law_m(q, P, value, J);
      bool normal = J[0] != 0, tangential = false;
      for (int k = 1; k < m * m; ++k) tangential = tangential || J[k] != 0;
      if (!normal && !tangential) continue;
      active_.push_back(q);
      const double f = kappa * cp.w[q] / cp.gamma[q];
      for (int k = 0; k < m * m; ++k) D_.push_back(f * J[k]);
      key_.push_back(J[0] + (tangential ? 2.0 : 0.0));
    }
    point_rows(cp, law.theta);
    stats.max_rank = std::max(stats.max_rank, static_cast<int64_t>(active_.size()) * m);
    if (active_.empty()) return A_factor_.solve(x);
    const int64_t n = A_.n;
    b_.assign(x, x + n);
    auto apply = [&](const double *v, double *y) { apply_T(cp, law.theta, v, y); };
    auto precondition = [&](double *v) { S_factor_->solve(v); };
    // with the S of the history, then with one made from the current points
    for (int attempt = 0; attempt < 2; ++attempt) {
      const bool fresh = attempt == 1 || log_.i.empty();
      if (fresh) current_log();
      if (fresh || !S_factor_ || S_log_ != log_ || kappa != S_kappa_ || law.theta != S_theta_)
        factor_S(law, kappa, c);
      if (attempt == 1) std::copy(b_.begin(), b_.end(), x);
      const GmresResult r = gmres(n, apply, precondition, x, kTolerance, iterations_for(n, fresh ? kIterations : kKeep),
                                  work_);
      stats.krylov += r.iterations;
      if (r.converged) {
        ++stats.lowrank;
        return;
      }
      if (fresh) break;
    }
    std::copy(b_.begin(), b_.end(), x);  // the reference: T refactored
    if (!fallback_) fallback_ = make_refactoring_tangent(A_, A_factor_, solver_, structure_, counters_, geometry_);
    const TangentStats before = fallback_->stats;
    fallback_->solve(law, kappa, U, true, x, nullptr, &P);
    stats.refactorizations += fallback_->stats.refactorizations - before.refactorizations;
  }
  void begin_step(const TangentLog &committed) override { log_ = committed; }
  const TangentLog *log() const override { return &log_; }
  const char *name() const override { return "sticking"; }

 private:
  // the history: S from the current points (nb, the points, their keys)
  void current_log() {
    log_.i.assign(1, static_cast<int64_t>(active_.size()));
    for (size_t q : active_) log_.i.push_back(static_cast<int64_t>(q));
    log_.x = key_;
  }
  // S's factor from the history's points and keys
  void factor_S(const ContactLaw &law, double kappa, double c) {
    const ContactPoints &cp = *law.cp;
    const int m = cp.m;
    // two bodies: a pair's point couples its slave and master cells, which
    // A's pattern lacks: S on A's pattern widened by the pairs, A's entries
    // scattered into it (as the refactoring tangent's T)
    if (!cp.pairing.empty() && widened_for_ != &cp) {
      S_ = widened_pattern(A_, cp, place_);
      S_factor_.reset();
      widened_for_ = &cp;
    }
    if (place_.empty()) {
      S_.val = A_.val;
    } else {
      std::fill(S_.val.begin(), S_.val.end(), 0.0);
      for (size_t k = 0; k < place_.size(); ++k) S_.val[place_[k]] = A_.val[k];
    }
    // symmetric positive definite with Theta = 1 (rows a - gamma s on both sides, blocks >= 0);
    // (analysed with A's values, as before pairs: an analysis may read them)
    const Structure s = law.theta == 1 ? Structure::SymmetricPositiveDefinite : Structure::General;
    if (!S_factor_ || s != S_structure_)
      S_factor_ = make_factorization(solver_, place_.empty() ? A_ : S_, s, counters_, geometry_);
    double Jd[9];
    const int64_t nb = log_.i[0];
    for (int64_t j = 0; j < nb; ++j) {
      const size_t q = static_cast<size_t>(log_.i[static_cast<size_t>(1 + j)]);
      const double key = log_.x[static_cast<size_t>(j)];
      const bool tangential = key >= 2;
      std::fill(Jd, Jd + m * m, 0.0);
      Jd[0] = tangential ? key - 2 : key;
      for (int k = 1; k < m; ++k) Jd[k * m + k] = tangential ? c : 0.0;
      add_block_tangent(cp, law.theta, q, kappa * cp.w[q] / cp.gamma[q], Jd, S_, rows_b_, rows_p_);
    }
    S_factor_->refactor(S_, s);
    S_structure_ = s, S_log_ = log_, S_kappa_ = kappa, S_theta_ = law.theta;
    ++stats.refactorizations;
  }
  // the active points' rows p_qk = a_qk - gamma s_qk and b_qk = a_qk -
  // Theta gamma s_qk, made once a solve rather than at each GMRES
  // iteration: the values apply_T made itself, so the same bits
  void point_rows(const ContactPoints &cp, double theta) {
    const int m = cp.m;
    start_.assign(1, 0);
    rows_.clear();
    for (size_t q : active_) {
      const double g = cp.gamma[q], tg = theta * g;
      const size_t len = cp.a[q].idx.size();
      for (int l = 0; l < m; ++l) {
        const SparseRow &a = cp.a_row(q, l), &s = cp.s_row(q, l);
        for (size_t i = 0; i < len; ++i) rows_.push_back(a.val[i] - g * s.val[i]);
        if (theta == 1) continue;  // (b_qk = p_qk)
        for (size_t i = 0; i < len; ++i) rows_.push_back(a.val[i] - tg * s.val[i]);
      }
      start_.push_back(rows_.size());
    }
  }
  // y = T v = A v + sum_q B_q D_q (P_q^T v)
  void apply_T(const ContactPoints &cp, double theta, const double *v, double *y) const {
    // (A v by nodes, four lanes wide where the CPU has them: GMRES's most
    // frequent pass over A, the bits of A's CSR product)
    auto keep = [&](int64_t i, double Av, double, double, double) __attribute__((always_inline)) { y[i] = Av; };
    if (!for_node_rows<false, false>(A_blocks_, v, nullptr, nullptr, keep)) A_.multiply(v, y);
    const int m = cp.m;
    const size_t per = theta == 1 ? 1 : 2;  // rows a value: p_qk (and b_qk)
    for (size_t j = 0; j < active_.size(); ++j) {
      const size_t q = active_[j];
      const int64_t *idx = cp.a[q].idx.data();
      const size_t len = cp.a[q].idx.size();
      const double *rows = &rows_[start_[j]];
      double pv[3] = {0, 0, 0};
      for (int l = 0; l < m; ++l) {
        const double *p = rows + static_cast<size_t>(l) * per * len;
        for (size_t i = 0; i < len; ++i) pv[l] += p[i] * v[idx[i]];
      }
      const double *D = &D_[j * static_cast<size_t>(m * m)];
      for (int k = 0; k < m; ++k) {
        double dk = 0;
        for (int l = 0; l < m; ++l) dk += D[k * m + l] * pv[l];
        if (dk == 0) continue;
        const double *b = rows + (static_cast<size_t>(k) * per + per - 1) * len;
        for (size_t i = 0; i < len; ++i) y[idx[i]] += dk * b[i];
      }
    }
  }

  const Csr &A_;
  const NodeBlocks *A_blocks_;
  const Factorization &A_factor_;
  int solver_;
  Structure structure_;
  Counters *counters_;
  const DofGeometry *geometry_;
  Csr S_;
  std::vector<int64_t> place_;  // A's entry k is S's place_[k] (empty: S has A's pattern)
  const ContactPoints *widened_for_ = nullptr;
  std::unique_ptr<Factorization> S_factor_;
  Structure S_structure_ = Structure::General;
  TangentLog log_, S_log_;  // the step's history, and the one S was made from
  std::vector<double> key_;
  double S_kappa_ = 0, S_theta_ = 0;
  std::unique_ptr<TangentSolver> fallback_;
  std::vector<size_t> active_;
  std::vector<double> D_, P_scratch_, b_, rows_b_, rows_p_, rows_;
  std::vector<size_t> start_;  // point j's rows at rows_[start_[j]]
  GmresWork work_;
};

}  // namespace

std::unique_ptr<TangentSolver> make_sticking_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                     Structure structure, Counters *counters,
                                                     const DofGeometry *geometry, const NodeBlocks *A_blocks) {
  return std::make_unique<StickingTangent>(A, A_factor, solver, structure, counters, geometry, A_blocks);
}

}  // namespace nd
