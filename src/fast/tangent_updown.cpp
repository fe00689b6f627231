// The updated factor of the Newton tangent (Theta = 1): T = A + sum_{q in S}
// d_q p_q p_q^T, d_q = kappa w_q/gamma_q phi'_q, is symmetric positive
// definite, and a point entering or leaving S (or changing its slope)
// changes it by +-c p_q p_q^T: a rank-one update or downdate of T's factor
// (linalg/updatable_cholesky.hpp), a fraction of a solve with A's factor
// per point, against a hundred solves or more for a refactorization in 3D.
// Where hundreds of points are active (a 3D body presses a whole cap on the
// plane) and a few change per step, the low-rank tangent's k x k capacitance
// (2/3 k^3 per new set) and the refactoring tangent both cost many solves
// per Newton iteration; this costs one solve plus the changes.
//
// The factor is kept across steps, so its bits depend on the updates made
// since its last factorization: they are written to the state
// (TangentLog) and replayed when the factor does not hold the history the
// step starts from (a restored checkpoint, a step after a failed one, a new
// time step size), so that every run is bitwise the uninterrupted one.
//
// When to refactor instead: a batch of changes is applied by updates only
// when they cost less than a factorization, and the updates since the last
// factorization are bounded (by kReplayFactorizations factorizations' cost,
// and by updown_max_updates columns), which bounds a replay's cost and the
// history's room in a checkpoint. The costs are the factor's model
// (UpdatableCholesky::factor_cost, modify_cost): functions of the
// structure, not timings, so the choice is the same in every run. A fixed
// count of columns does not fit every mesh: an update's cost relative to a
// factorization falls as the mesh is refined, while an impact changes more
// points per Newton iteration, so a count that suits a coarse mesh makes a
// fine one refactor at every iteration.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "linalg/updatable_cholesky.hpp"
#include "nitschedyn.h"
#include "fast/tangents.hpp"

namespace nd {
namespace {

// Updates since the factorization cost at most this many factorizations:
// a replay (a restart, a retried step) costs at most one more than that.
// A bound of one made a bounce refactor several times, each time a whole
// factorization for nothing, where the set changes by tens of points per step.
constexpr double kReplayFactorizations = 8;

// A step's first Newton iteration updates the factor from the last step's
// final set to the predictor's, the second from there to the iterate's.
// Where the predictor misjudges the patch's edge, the second undoes much of
// the first, most on fine meshes. So when the predictor's
// changes would cost more than this many solves (the factor's model), the
// first iteration keeps the factor as the last step left it (a chord step:
// the residual is the predictor's, the tangent the last step's), and the
// second updates it once, to the iterate's set. Newton's last iteration
// solves its final set's linear system either way, so the solution agrees
// to round-off (tests/unit_tangent.cpp); the choice reads the state and the
// structure only, so a resumed or retried step chooses alike. (As the
// low-rank tangent's fallback, "first" is the fallback's first solve in the
// step, which may be a later Newton iteration: a chord step there too.)
// Three solves: with fewer, a lagged step whose predictor was right pays one
// more iteration; with more, mid-sized meshes no longer lag
// (docs/performance.md, "Lagged first tangent").
constexpr double kLagSolves = 3;

class UpdownTangent : public TangentSolver {
 public:
  UpdownTangent(const Csr &A, const Factorization &A_factor, Counters *counters, double factor_weight)
      : A_(A), A_factor_(A_factor), counters_(counters), factor_weight_(factor_weight), T_(A) {}

  void begin_step(const TangentLog &committed) override {
    first_ = true;
    if (committed == log_) return;
    log_ = committed;  // the factor no longer holds it: replayed at the first need
    synced_ = false;
  }
  const TangentLog *log() const override { return &log_; }

  void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
             const double *guess, const std::vector<double> *P_U) override {
    ++stats.calls;
    if (law.theta != 1) fail(ND_ERR_INTERNAL, "the updated tangent factor needs Theta = 1");
    require_rank_one_updates(law, "the updated tangent factor");
    if (!law.traits().symmetric) fail(ND_ERR_INTERNAL, "the updated tangent factor needs a symmetric law");
    const ContactPoints &cp = *law.cp;
    d_new_.assign(cp.size(), 0.0);
    int64_t k = 0;
    if (any_active) {
      const std::vector<double> &P = law.P_at(U, P_U, P_);
      const bool pp = law.positive_part();
      for (size_t q = 0; q < cp.size(); ++q) {
        double value, slope;
        law.law(q, P[q], value, slope, pp);
        if (slope != 0) d_new_[q] = kappa * cp.w[q] / cp.gamma[q] * slope, ++k;
      }
    }
    stats.max_rank = std::max(stats.max_rank, k);
    const bool first = first_;
    first_ = false;
    if (k == 0) {
      A_factor_.solve_from(x, guess);
      return;
    }
    if (!factor_) {
      // (pairs: T on the widened pattern, its own analysis: A's factor, whose
      // rows hold no coupling of the bodies, is not a start; a new pairing
      // makes a new integrator, and this again)
      if (!cp.pairing.empty()) T_ = widened_pattern(A_, cp, place_);
      factor_ = std::make_unique<UpdatableCholesky>(T_, counters_, place_.empty() ? &A_factor_ : nullptr);
    }
    if (!synced_) replay(cp, d_new_);
    if (!update_to(cp, d_new_, first)) count(counters_, &Counters::lagged_steps);
    ++stats.lowrank;
    factor_->solve(x);
  }
  const char *name() const override { return "updown"; }

 private:
  // the factor of A + sum_q d_q p_q p_q^T, and the history that starts
  // there: A's own factor updated by the set's columns where they cost
  // less than a factorization of T (a first contact, a small set), else T
  // factored. The choice reads the cost model only, so a replay makes it
  // the same way.
  void factor_at(const ContactPoints &cp, const std::vector<double> &d) {
    synced_ = false;  // until the factor holds the new base
    // (base_ and log_ take turns: both hold the largest history's room)
    reserve_tangent_log(base_, static_cast<int64_t>(cp.size()));
    reserve_tangent_log(log_, static_cast<int64_t>(cp.size()));
    TangentLog &base = base_;
    base.i.assign(1, 0);
    base.x.clear();
    for (size_t q = 0; q < d.size(); ++q)
      if (d[q] != 0) base.i.push_back(static_cast<int64_t>(q)), base.x.push_back(d[q]);
    base.i[0] = static_cast<int64_t>(base.x.size());
    base_q_.assign(base.i.begin() + 1, base.i.end());
    columns(cp, base_q_, base.x, up_C_);
    const bool cheap = !factor_->has_costs() || factor_->modify_cost(up_C_) <= factorization_cost();
    bool updated = cheap && factor_->start_from(A_factor_);
    if (updated && factor_->modify_cost(up_C_) > factorization_cost()) updated = false;  // (costs known now)
    if (updated && up_C_.count() > 0) {
      count(counters_, &Counters::tangent_updates);
      updated = modify_counted(true, up_C_);  // false: a pivot lost to round-off, T factored instead
    }
    if (updated) {
      ++stats.restarts;
    } else {
      if (place_.empty()) {
        T_.val = A_.val;  // same size: no allocation
      } else {
        std::fill(T_.val.begin(), T_.val.end(), 0.0);
        for (size_t k = 0; k < place_.size(); ++k) T_.val[place_[k]] = A_.val[k];
      }
      for (size_t j = 0; j < base_q_.size(); ++j)
        add_point_tangent(cp, 1.0, static_cast<size_t>(base_q_[j]), base.x[j], T_, b_, p_);
      count(counters_, &Counters::tangent_updates);
      factor_->factor(T_);
      ++stats.refactorizations;
    }
    log_.i.swap(base.i);
    log_.x.swap(base.x);
    d_ = d;
    updates_ = 0;
    spent_ = 0;
    synced_ = true;
  }
  double factorization_cost() const { return factor_weight_ * factor_->factor_cost(); }
  // the columns sqrt(c_j) p_{q_j} of a rank update or downdate
  static void columns(const ContactPoints &cp, const std::vector<int64_t> &q, const std::vector<double> &c,
                      SparseColumns &C) {
    C.ptr.assign(1, 0);
    C.idx.clear();
    C.val.clear();
    for (size_t j = 0; j < q.size(); ++j) {
      append_p(cp, static_cast<size_t>(q[j]), std::sqrt(c[j]), C.idx, C.val);
      C.ptr.push_back(static_cast<int64_t>(C.idx.size()));
    }
  }
  bool modify(bool add, const SparseColumns &C) {
    count(counters_, &Counters::tangent_updates);
    updates_ += C.count();
    return modify_counted(add, C);
  }
  // the factor modified, its columns and their work counted (ND_STAT_FACTOR_*)
  bool modify_counted(bool add, const SparseColumns &C) {
    count(counters_, &Counters::factor_modifications, C.count());
    const int64_t before = factor_->modified_entries();
    const bool ok = factor_->modify(add, C);
    count(counters_, &Counters::factor_modified_entries, factor_->modified_entries() - before);
    return ok;
  }
  // from the factor's set to d: updates first (T stays further from
  // singular on the way), then downdates; each recorded. first (the step's
  // first solve, kLagSolves): where the factor holds an active set and the
  // changes cost more than kLagSolves solves, it is kept as it is (false)
  bool update_to(const ContactPoints &cp, const std::vector<double> &d, bool first = false) {
    up_q_.clear(), up_c_.clear(), down_q_.clear(), down_c_.clear();
    for (size_t q = 0; q < d.size(); ++q) {
      const double change = d[q] - d_[q];
      if (change > 0) up_q_.push_back(static_cast<int64_t>(q)), up_c_.push_back(change);
      if (change < 0) down_q_.push_back(static_cast<int64_t>(q)), down_c_.push_back(-change);
    }
    const int64_t changes = static_cast<int64_t>(up_q_.size() + down_q_.size());
    if (changes == 0) return true;
    columns(cp, up_q_, up_c_, up_C_);
    columns(cp, down_q_, down_c_, down_C_);
    const double up_cost = factor_->modify_cost(up_C_), down_cost = factor_->modify_cost(down_C_);
    const double cost = up_cost + down_cost, factorization = factorization_cost();
    if (first && cost > kLagSolves * factor_->solve_cost() &&
        std::any_of(d_.begin(), d_.end(), [](double v) { return v != 0; }))
      return false;
    if (cost > factorization || spent_ + cost > kReplayFactorizations * factorization ||
        updates_ + changes > updown_max_updates(static_cast<int64_t>(cp.size()))) {
      factor_at(cp, d);
      return true;
    }
    synced_ = false;  // until both succeed
    for (int pass = 0; pass < 2; ++pass) {
      const bool add = pass == 0;
      const std::vector<int64_t> &q = add ? up_q_ : down_q_;
      const std::vector<double> &c = add ? up_c_ : down_c_;
      if (q.empty()) continue;
      if (!modify(add, add ? up_C_ : down_C_)) {  // a pivot lost to round-off: factor anew
        factor_at(cp, d);
        return true;
      }
      log_.i.push_back(add ? static_cast<int64_t>(q.size()) : -static_cast<int64_t>(q.size()));
      log_.i.insert(log_.i.end(), q.begin(), q.end());
      log_.x.insert(log_.x.end(), c.begin(), c.end());
      spent_ += add ? up_cost : down_cost;  // as a replay adds them
    }
    d_ = d;
    synced_ = true;
    return true;
  }
  // the factor that log_ describes (checkpoint::decode_state checked its
  // form); with no history yet, the first factor (of `first`) starts one
  void replay(const ContactPoints &cp, const std::vector<double> &first) {
    if (log_.i.empty()) {
      factor_at(cp, first);
      return;
    }
    const TangentLog history = log_;
    std::vector<double> d(cp.size(), 0.0);
    const int64_t nb = history.i[0];
    for (int64_t j = 0; j < nb; ++j) d[history.i[1 + j]] = history.x[j];
    factor_at(cp, d);
    size_t at = 1 + static_cast<size_t>(nb), xat = static_cast<size_t>(nb);
    std::vector<int64_t> q;
    std::vector<double> c;
    while (at < history.i.size()) {
      const int64_t m = history.i[at++];
      const size_t count = static_cast<size_t>(m > 0 ? m : -m);
      q.assign(history.i.begin() + at, history.i.begin() + at + count);
      c.assign(history.x.begin() + xat, history.x.begin() + xat + count);
      at += count, xat += count;
      for (size_t j = 0; j < count; ++j) d[q[j]] += m > 0 ? c[j] : -c[j];
      columns(cp, q, c, up_C_);
      spent_ += factor_->modify_cost(up_C_);
      if (!modify(m > 0, up_C_)) {  // not the factor that was recorded (another A): start anew
        factor_at(cp, d);
        return;
      }
    }
    log_ = history;
    d_ = d;
    synced_ = true;
  }

  const Csr &A_;
  std::vector<int64_t> place_;  // pairs: A's entry k is T's place_[k] (empty: T has A's pattern)
  const Factorization &A_factor_;
  Counters *counters_;
  double factor_weight_;  // the price of a factorization, times the model's
  Csr T_;
  std::unique_ptr<UpdatableCholesky> factor_;
  TangentLog log_;          // the factor's history (or, !synced_, the one to replay)
  TangentLog base_;         // factor_at's new history, kept for its memory
  bool synced_ = false;     // the factor holds log_
  bool first_ = false;      // no solve yet since begin_step
  std::vector<double> d_;   // the coefficients the factor holds, per point
  int64_t updates_ = 0;     // columns updated since the factorization
  double spent_ = 0;        // their cost (UpdatableCholesky::modify_cost)
  std::vector<double> d_new_, up_c_, down_c_;
  std::vector<double> P_;  // P_q at the iterate (scratch)
  std::vector<double> b_, p_;  // add_point_tangent's (scratch)
  std::vector<int64_t> up_q_, down_q_, base_q_;
  SparseColumns up_C_, down_C_;
};

}  // namespace

std::unique_ptr<TangentSolver> make_updown_tangent(const Csr &A, const Factorization &A_factor, Counters *counters,
                                                   double factor_weight) {
  return std::make_unique<UpdownTangent>(A, A_factor, counters, factor_weight);
}

bool updown_tangent_applies(int solver, Structure structure) {
  return structure == Structure::SymmetricPositiveDefinite && (solver == ND_SOLVER_AUTO || solver == ND_SOLVER_CHOLMOD);
}

}  // namespace nd
