#include "linalg/gmres.hpp"

#include <algorithm>
#include <cmath>

namespace nd {

namespace {
double dot(int64_t n, const double *a, const double *b) {
  double s = 0;
  for (int64_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}
}  // namespace

GmresResult gmres(int64_t n, const std::function<void(const double *, double *)> &apply,
                  const std::function<void(double *)> &precondition, double *x, double rtol, int max_iterations,
                  GmresWork &work) {
  GmresResult res;
  const int k = std::max(max_iterations, 1);
  const size_t N = static_cast<size_t>(n);
  work.V.resize(N * static_cast<size_t>(k + 1));
  work.Z.resize(N * static_cast<size_t>(k));
  work.H.assign(static_cast<size_t>((k + 1) * k), 0.0);
  work.cs.assign(static_cast<size_t>(k), 0.0);
  work.sn.assign(static_cast<size_t>(k), 0.0);
  work.g.assign(static_cast<size_t>(k + 1), 0.0);
  work.w.resize(N);
  double *V = work.V.data(), *Z = work.Z.data(), *H = work.H.data(), *g = work.g.data();
  const double beta = std::sqrt(dot(n, x, x));
  if (beta == 0) {
    res.converged = true;
    return res;
  }
  std::copy(x, x + n, work.w.begin());  // b, kept for the final residual
  for (int64_t i = 0; i < n; ++i) V[i] = x[i] / beta;
  g[0] = beta;
  int j = 0;
  auto h = [&](int r, int c) -> double & { return H[static_cast<size_t>(c * (k + 1) + r)]; };
  for (; j < k; ++j) {
    double *z = Z + N * static_cast<size_t>(j), *v = V + N * static_cast<size_t>(j + 1);
    std::copy(V + N * static_cast<size_t>(j), V + N * static_cast<size_t>(j + 1), z);
    precondition(z);
    apply(z, v);
    for (int i = 0; i <= j; ++i) {  // modified Gram-Schmidt
      const double *vi = V + N * static_cast<size_t>(i);
      const double c = dot(n, v, vi);
      h(i, j) = c;
      for (int64_t r = 0; r < n; ++r) v[r] -= c * vi[r];
    }
    const double norm = std::sqrt(dot(n, v, v));
    h(j + 1, j) = norm;
    if (norm > 0)
      for (int64_t r = 0; r < n; ++r) v[r] /= norm;
    for (int i = 0; i < j; ++i) {  // the earlier rotations on the new column
      const double a = h(i, j), b = h(i + 1, j);
      h(i, j) = work.cs[i] * a + work.sn[i] * b;
      h(i + 1, j) = -work.sn[i] * a + work.cs[i] * b;
    }
    const double a = h(j, j), b = h(j + 1, j), r = std::hypot(a, b);
    work.cs[j] = r == 0 ? 1 : a / r;
    work.sn[j] = r == 0 ? 0 : b / r;
    h(j, j) = r;
    h(j + 1, j) = 0;
    g[j + 1] = -work.sn[j] * g[j];
    g[j] = work.cs[j] * g[j];
    if (std::fabs(g[j + 1]) <= 0.25 * rtol * beta || norm == 0) {  // (margin for the true residual)
      ++j;
      break;
    }
  }
  res.iterations = j;
  // y = H^{-1} g (upper triangular), x = Z y
  std::vector<double> y(g, g + j);
  for (int i = j - 1; i >= 0; --i) {
    for (int c = i + 1; c < j; ++c) y[i] -= h(i, c) * y[c];
    y[i] = h(i, i) != 0 ? y[i] / h(i, i) : 0;
  }
  std::fill(x, x + n, 0.0);
  for (int c = 0; c < j; ++c) {
    const double *z = Z + N * static_cast<size_t>(c);
    for (int64_t r = 0; r < n; ++r) x[r] += y[c] * z[r];
  }
  // the true residual: the recursion's can pass below what round-off allows
  double *t = V;  // (free now)
  apply(x, t);
  double rr = 0;
  for (int64_t r = 0; r < n; ++r) rr += (work.w[r] - t[r]) * (work.w[r] - t[r]);
  res.residual = std::sqrt(rr) / beta;
  res.converged = std::isfinite(res.residual) && res.residual <= rtol;
  return res;
}

}  // namespace nd
