// Conjugate gradients with the diagonal as preconditioner, for a matrix
// that the diagonal already conditions well: the mass matrix, whose
// condition number after diagonal scaling is bounded independently of the
// mesh size for Lagrange elements. One solve with it costs a few dozen
// products, against a factorization (and the memory of a second factor)
// when the mass matrix is solved once, for the initial acceleration.
#pragma once
#include <cmath>

#include "linalg/csr.hpp"

namespace nd {

struct PcgResult {
  bool converged = false;
  int iterations = 0;
  double residual = 0;  // ||b - A x|| / ||b|| at the end
};

// x = A^{-1} b for symmetric positive definite A (x: b on entry, the
// solution on return), until ||b - A x|| <= target ||b|| (target <= rtol;
// by default rtol), or until the residual stops decreasing or max_iter
// iterations are done: converged if then ||b - A x|| <= rtol ||b||. Not
// converged (x then unspecified), for the caller to fall back on a
// factorization.
PcgResult pcg_jacobi(const Csr &A, double *x, double rtol, int max_iter, double target = INFINITY);

}  // namespace nd
