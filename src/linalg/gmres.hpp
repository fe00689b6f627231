// GMRES with a right preconditioner (flexible form: the preconditioned
// vectors are kept, so the solution costs no extra preconditioner solve),
// without restarts: for operators that a factorization of a nearby matrix
// preconditions well, so that a few dozen iterations suffice or the caller
// falls back on factoring the operator itself.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

namespace nd {

struct GmresResult {
  bool converged = false;
  int iterations = 0;
  double residual = 0;  // ||b - T x|| / ||b|| at the end, computed (not the recursion's)
};

// The vectors GMRES keeps (n (2 k + 2) doubles for k iterations), reused
// from solve to solve.
struct GmresWork {
  std::vector<double> V, Z, H, cs, sn, g, w;
};

// x <- T^{-1} x (x: b on entry), with T applied by apply(v, Tv) and the
// preconditioner by precondition(v) (v <- M^{-1} v in place), from the guess
// 0, until ||b - T x|| <= rtol ||b|| or max_iterations. Not converged: x is
// unspecified, for the caller to fall back on another solver.
GmresResult gmres(int64_t n, const std::function<void(const double *, double *)> &apply,
                  const std::function<void(double *)> &precondition, double *x, double rtol, int max_iterations,
                  GmresWork &work);

}  // namespace nd
