// The reference tangent solver: assemble A + kappa N'(U) on A's pattern and
// factor it numerically at every Newton iteration with an active point.
#include "solve/tangent_solver.hpp"

#include <algorithm>
#include <utility>

#include "solve/contact_law.hpp"

namespace nd {
namespace {

class RefactoringTangent : public TangentSolver {
 public:
  RefactoringTangent(const Csr &A, const Factorization &A_factor, int solver, Structure s, Counters *c,
                     const DofGeometry *g, std::vector<int64_t> held, bool linear_held)
      : A_(A), A_factor_(A_factor), T_(A), structure_(s), T_factor_(make_factorization(solver, A, s, c, g)),
        held_(std::move(held)), linear_held_(linear_held && !held_.empty()), solver_(solver), counters_(c),
        geometry_(g) {}
  void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
             const double *guess, const std::vector<double> *P_U) override {
    ++stats.calls;
    if (!any_active) {  // Newton's linear step, which often ends it: every row, or the held ones
      if (linear_held_) return A_factor_.solve_at(x, A_.n, held_, guess);
      A_factor_.solve_from(x, guess);
      return;
    }
    if (!law.cp->pairing.empty() && widened_for_ != law.cp) widen(*law.cp);
    if (place_.empty()) {
      T_.val = A_.val;  // same size: no allocation
    } else {
      std::fill(T_.val.begin(), T_.val.end(), 0.0);
      for (size_t k = 0; k < place_.size(); ++k) T_.val[place_[k]] = A_.val[k];
    }
    law.add_tangent(U, kappa, T_, P_U);
    // (GAMG keeps its preconditioner from tangent to tangent while it serves)
    if (T_factor_->refactor(T_, structure_)) ++stats.refactorizations;
    if (held_.empty()) return T_factor_->solve(x);
    T_factor_->solve_at(x, A_.n, held_);
  }
  const char *name() const override { return "refactor"; }
  const std::vector<int64_t> *held() const override { return held_.empty() ? nullptr : &held_; }

 private:
  // Two bodies (contact/pairing.hpp): a pair's point couples its slave cell's
  // DOFs with its master cell's, which A's pattern (the cells') lacks: T's
  // pattern is A's and every point's a_q x a_q (s_q has a_q's index list),
  // A's entries scattered into it (place_), and T's factor analysed anew
  void widen(const ContactPoints &cp) {
    T_ = widened_pattern(A_, cp, place_);
    T_factor_ = make_factorization(solver_, T_, structure_, counters_, geometry_);
    widened_for_ = &cp;
  }
  const Csr &A_;
  const Factorization &A_factor_;
  Csr T_;
  Structure structure_;
  std::unique_ptr<Factorization> T_factor_;
  std::vector<int64_t> held_;
  bool linear_held_;
  int solver_;
  Counters *counters_;
  const DofGeometry *geometry_;
  std::vector<int64_t> place_;  // A's entry k is T's place_[k] (empty: T has A's pattern)
  const ContactPoints *widened_for_ = nullptr;
};

}  // namespace

Csr widened_pattern(const Csr &A, const ContactPoints &cp, std::vector<int64_t> &place) {
  std::vector<std::vector<int64_t>> rows(static_cast<size_t>(A.n));
  for (int64_t i = 0; i < A.n; ++i) rows[i].assign(A.col.begin() + A.ptr[i], A.col.begin() + A.ptr[i + 1]);
  for (size_t q = 0; q < cp.size(); ++q)
    for (int64_t i : cp.a[q].idx) rows[i].insert(rows[i].end(), cp.a[q].idx.begin(), cp.a[q].idx.end());
  Csr W = csr_from_rows(std::move(rows));
  place.resize(A.val.size());
  for (int64_t i = 0; i < A.n; ++i)
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k)
      place[k] = std::lower_bound(W.col.begin() + W.ptr[i], W.col.begin() + W.ptr[i + 1], A.col[k]) - W.col.begin();
  return W;
}

std::unique_ptr<TangentSolver> make_refactoring_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                        Structure structure, Counters *counters,
                                                        const DofGeometry *geometry, std::vector<int64_t> held,
                                                        bool linear_held) {
  return std::make_unique<RefactoringTangent>(A, A_factor, solver, structure, counters, geometry, std::move(held),
                                              linear_held);
}

}  // namespace nd
