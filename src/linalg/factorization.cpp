#include "linalg/factorization.hpp"

#include "linalg/lapack_solvers.hpp"
#include "nitschedyn.h"

namespace nd {

std::unique_ptr<Factorization> make_factorization(int solver, const Csr &pattern) {
  switch (solver) {
    case ND_SOLVER_DENSE:
      return make_dense_factorization(pattern);
    case ND_SOLVER_BANDED:
      return make_banded_factorization(pattern);
    default:  // AUTO: below ~100 unknowns dense LU costs nothing and needs no ordering
      return pattern.n <= 100 ? make_dense_factorization(pattern) : make_banded_factorization(pattern);
  }
}

}  // namespace nd
