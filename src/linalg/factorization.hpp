// One small interface over the direct solvers. A factorization is created
// for a pattern (the symbolic work: ordering, bandwidth) and then factors any
// matrix of that pattern numerically, as often as needed.
#pragma once
#include <memory>

#include "common/counters.hpp"
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
  virtual Definiteness definiteness() const = 0;
  virtual const char *name() const = 0;
};

// solver: an ND_SOLVER_* value; s: the structure of the matrices it will
// factor. AUTO picks by size and bandwidth, CHOLMOD falls back to UMFPACK
// for non-symmetric matrices. Any other id throws ND_ERR_KEY. With
// counters, the making (symbolic analysis), every factor() and every solve()
// are counted there.
std::unique_ptr<Factorization> make_factorization(int solver, const Csr &pattern, Structure s,
                                                  Counters *counters = nullptr);
// whether make_factorization accepts this id (AUTO or a registered backend)
bool linear_solver_known(int solver);

}  // namespace nd
