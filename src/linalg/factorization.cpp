#include "linalg/factorization.hpp"

#include "linalg/backends.hpp"
#include "nitschedyn.h"

namespace nd {

// AUTO: dense LU/Cholesky costs nothing below a few hundred unknowns; a
// pattern that reverse Cuthill-McKee makes narrow (1D meshes: half-bandwidth
// 1-4) is cheapest banded; anything else goes to the sparse direct solvers.
// The thresholds are measured by bench/solvers (see bench/README.md).
constexpr int64_t kDenseMax = 200, kBandMax = 16;

std::unique_ptr<Factorization> make_factorization(int solver, const Csr &pattern, Structure s) {
  const bool spd = s == Structure::SymmetricPositiveDefinite;
  switch (solver) {
    case ND_SOLVER_DENSE:
      return make_dense_factorization(pattern);
    case ND_SOLVER_BANDED:
      return make_banded_factorization(pattern);
    case ND_SOLVER_CHOLMOD:  // Cholesky needs symmetry: non-symmetric systems go to UMFPACK
      return spd ? make_cholmod_factorization(pattern) : make_umfpack_factorization(pattern);
    case ND_SOLVER_UMFPACK:
      return make_umfpack_factorization(pattern);
    case ND_SOLVER_KLU:
      return make_klu_factorization(pattern);
    default:
      if (pattern.n <= kDenseMax) return make_dense_factorization(pattern);
      if (bandwidth(pattern, reverse_cuthill_mckee(pattern)) <= kBandMax) return make_banded_factorization(pattern);
      return spd ? make_cholmod_factorization(pattern) : make_umfpack_factorization(pattern);
  }
}

}  // namespace nd
