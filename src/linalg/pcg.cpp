#include "linalg/pcg.hpp"

#include <cmath>
#include <vector>

namespace nd {

PcgResult pcg_jacobi(const Csr &A, double *x, double rtol, int max_iter, double target) {
  if (!(target < rtol)) target = rtol;
  const int64_t n = A.n;
  PcgResult res;
  std::vector<double> b(x, x + n), inv_d(static_cast<size_t>(n)), r(b), z(inv_d.size()), p(inv_d.size()),
      q(inv_d.size()), X(inv_d.size(), 0.0);
  for (int64_t i = 0; i < n; ++i) {
    const int64_t k = A.find(i, i);
    const double d = k < 0 ? 0.0 : A.val[k];
    if (!(d > 0) || !std::isfinite(d)) return res;  // not positive definite: not for this method
    inv_d[i] = 1 / d;
  }
  const double b_norm = norm2(n, b.data());
  if (b_norm == 0) {
    for (int64_t i = 0; i < n; ++i) x[i] = 0;
    res.converged = true;
    return res;
  }
  // The recursive residual r drifts from b - A X by round-off; it is
  // replaced by the true one when it claims convergence, at most twice.
  bool stagnated = false;
  for (int replacement = 0; replacement < 3 && res.iterations < max_iter && !stagnated; ++replacement) {
    for (int64_t i = 0; i < n; ++i) z[i] = inv_d[i] * r[i], p[i] = z[i];
    double rz = dot(n, r.data(), z.data()), best = INFINITY;
    int since_best = 0;
    while (res.iterations < max_iter) {
      ++res.iterations;
      A.multiply(p.data(), q.data());
      const double pq = dot(n, p.data(), q.data());
      if (!(pq > 0)) return res;
      const double alpha = rz / pq;
      for (int64_t i = 0; i < n; ++i) X[i] += alpha * p[i], r[i] -= alpha * q[i];
      const double r_norm = norm2(n, r.data());
      if (r_norm <= target * b_norm) break;
      if (r_norm < best) best = r_norm, since_best = 0;
      if (++since_best > 20) {  // stagnates above target: rtol decides
        stagnated = true;
        break;
      }
      for (int64_t i = 0; i < n; ++i) z[i] = inv_d[i] * r[i];
      const double rz_next = dot(n, r.data(), z.data()), beta = rz_next / rz;
      rz = rz_next;
      for (int64_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    }
    A.multiply(X.data(), q.data());
    for (int64_t i = 0; i < n; ++i) r[i] = b[i] - q[i];
    res.residual = norm2(n, r.data()) / b_norm;
    if (res.residual <= target) break;
  }
  if (res.residual <= rtol && res.iterations > 0) {
    res.converged = true;
    for (int64_t i = 0; i < n; ++i) x[i] = X[i];
  }
  return res;
}

}  // namespace nd
