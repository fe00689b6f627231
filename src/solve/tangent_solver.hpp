// The seam between Newton and the factorizations: solves with the Newton
// tangent T(U) = A + kappa N'(U), A = c M + K_Theta factored once per time
// step size. Today's implementation refactors T numerically (the symbolic
// analysis of A's pattern reused); a low-rank update of A's factor over the
// active points (DESIGN §4) slots in beside it.
#pragma once
#include <memory>

#include "linalg/factorization.hpp"
#include "solve/contact_law.hpp"

namespace nd {

class TangentSolver {
 public:
  virtual ~TangentSolver() = default;
  // x <- T(U)^{-1} x; with no active point T(U) = A
  virtual void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x) = 0;
  virtual const char *name() const = 0;
};

// A and its factor must outlive the solver. solver: ND_SOLVER_* for the
// tangent, structure: the tangent's (symmetric positive definite iff Theta = 1).
std::unique_ptr<TangentSolver> make_refactoring_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                        Structure structure);

}  // namespace nd
