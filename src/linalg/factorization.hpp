// One small interface over the direct solvers. A factorization is created
// for a pattern (the symbolic work: ordering, bandwidth) and then factors any
// matrix of that pattern numerically, as often as needed.
#pragma once
#include <memory>

#include "linalg/csr.hpp"

namespace nd {

enum class Structure { SymmetricPositiveDefinite, General };
// What the last factor() learnt about the matrix (NotPositiveDefinite: it
// threw ND_ERR_INDEFINITE). Unknown: factored as General, the backend's
// pivoting hid the inertia, or factor() failed otherwise.
enum class Definiteness { PositiveDefinite, NotPositiveDefinite, Unknown };

class Factorization {
 public:
  virtual ~Factorization() = default;
  // Throws ND_ERR_INDEFINITE (SPD requested on a matrix that is certainly
  // not positive definite) or ND_ERR_SINGULAR.
  virtual void factor(const Csr &A, Structure s) = 0;
  virtual void solve(double *x) const = 0;  // in place, one right-hand side
  // in place, nrhs right-hand sides, column j at X + j n (the low-rank
  // tangent's columns A^{-1} b_q); one solve() each unless a backend does better
  virtual void solve_many(double *X, int64_t n, int64_t nrhs) const {
    for (int64_t j = 0; j < nrhs; ++j) solve(X + j * n);
  }
  virtual Definiteness definiteness() const = 0;
  virtual const char *name() const = 0;
};

// solver: an ND_SOLVER_* value; s: the structure of the matrices it will
// factor. AUTO picks by size and bandwidth, CHOLMOD falls back to UMFPACK
// for non-symmetric matrices. Any other id throws ND_ERR_KEY.
std::unique_ptr<Factorization> make_factorization(int solver, const Csr &pattern, Structure s);
// whether make_factorization accepts this id (AUTO or a registered backend)
bool linear_solver_known(int solver);

}  // namespace nd
