#include "linalg/factorization.hpp"

#include "linalg/backends.hpp"
#include "linalg/ordering.hpp"
#include "nitschedyn.h"

namespace nd {

// AUTO, from bench/solver_crossover (bench/results/solver_crossover.csv, 2D
// P1, c M + K): a step pays one solve, a Newton iteration with active contact
// a factorization too. Dense factorization beats CHOLMOD up to ~130 unknowns
// but a dense solve is 3x slower than CHOLMOD's already at 56 (2.7 vs 0.8 us),
// so dense only below 40. Banded factors faster than CHOLMOD in 2D but solves
// 1.6x slower at 870 unknowns: it is kept for patterns that reverse
// Cuthill-McKee makes truly narrow (1D meshes: half-bandwidth 1-4).
constexpr int64_t kDenseMax = 40, kBandMax = 16;

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
