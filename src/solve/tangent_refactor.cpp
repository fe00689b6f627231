// The reference tangent solver: assemble A + kappa N'(U) on A's pattern and
// factor it numerically at every Newton iteration with an active point.
#include "solve/tangent_solver.hpp"

#include <utility>

namespace nd {
namespace {

class RefactoringTangent : public TangentSolver {
 public:
  RefactoringTangent(const Csr &A, const Factorization &A_factor, int solver, Structure s, Counters *c,
                     const DofGeometry *g, std::vector<int64_t> held, bool linear_held)
      : A_(A), A_factor_(A_factor), T_(A), structure_(s), T_factor_(make_factorization(solver, A, s, c, g)),
        held_(std::move(held)), linear_held_(linear_held && !held_.empty()) {}
  void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
             const double *guess, const std::vector<double> *P_U) override {
    ++stats.calls;
    if (!any_active) {  // Newton's linear step, which often ends it: every row, or the held ones
      if (linear_held_) return A_factor_.solve_at(x, A_.n, held_, guess);
      A_factor_.solve_from(x, guess);
      return;
    }
    T_.val = A_.val;  // same size: no allocation
    law.add_tangent(U, kappa, T_, P_U);
    // (GAMG keeps its preconditioner from tangent to tangent while it serves)
    if (T_factor_->refactor(T_, structure_)) ++stats.refactorizations;
    if (held_.empty()) return T_factor_->solve(x);
    T_factor_->solve_at(x, A_.n, held_);
  }
  const char *name() const override { return "refactor"; }
  const std::vector<int64_t> *held() const override { return held_.empty() ? nullptr : &held_; }

 private:
  const Csr &A_;
  const Factorization &A_factor_;
  Csr T_;
  Structure structure_;
  std::unique_ptr<Factorization> T_factor_;
  std::vector<int64_t> held_;
  bool linear_held_;
};

}  // namespace

std::unique_ptr<TangentSolver> make_refactoring_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                        Structure structure, Counters *counters,
                                                        const DofGeometry *geometry, std::vector<int64_t> held,
                                                        bool linear_held) {
  return std::make_unique<RefactoringTangent>(A, A_factor, solver, structure, counters, geometry, std::move(held),
                                              linear_held);
}

}  // namespace nd
