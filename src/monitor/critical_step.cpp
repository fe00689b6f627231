#include "monitor/critical_step.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/error.hpp"
#include "linalg/lapack.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"

namespace nd {
namespace {

// y = A x: the ranks' rows, gathered, when the operators are split over
// them (the estimate is collective then, as its mass solves are)
void multiply(const Discretization &d, const Csr &A, const std::vector<double> &x, std::vector<double> &y) {
  count(d.counters, &Counters::spmv);
  const Share *rows = own_rows_of(d, false);
  A.multiply(x.data(), y.data(), own_rows(rows));
  if (rows) gather(*rows, {y.data()});
}

// y = (K_Theta + T_c) x, or K_Theta x without the contact points
void apply(const Discretization &d, const std::vector<double> &x, std::vector<double> &y, bool with_points) {
  multiply(d, d.K_theta, x, y);
  if (!with_points) return;
  const ContactPoints &cp = d.contact;
  const double max_slope = d.contact_law->traits().max_slope;  // (every point active, as stiff as it gets)
  // (friction: a frictional point's tangential pairs too, sticking as stiff as the normal one)
  for (size_t q = 0; q < cp.size(); ++q)
    for (int v = 0; v < (cp.m > 1 && cp.friction[q] ? cp.m : 1); ++v) {
      const SparseRow &a = cp.a_row(q, v), &s = cp.s_row(q, v);
      double bx = 0, px = 0;
      for (size_t k = 0; k < a.idx.size(); ++k) {
        const double b = a.val[k] - d.theta * cp.gamma[q] * s.val[k], p = a.val[k] - cp.gamma[q] * s.val[k];
        bx += b * x[a.idx[k]];
        px += p * x[a.idx[k]];
      }
      // sym(b p^T) x = (b (p.x) + p (b.x))/2, at the law's steepest slope
      const double f = 0.5 * cp.w[q] / cp.gamma[q] * max_slope;
      for (size_t k = 0; k < a.idx.size(); ++k) {
        const double b = a.val[k] - d.theta * cp.gamma[q] * s.val[k], p = a.val[k] - cp.gamma[q] * s.val[k];
        y[a.idx[k]] += f * (b * px + p * bx);
      }
    }
}

double m_dot(const Discretization &d, const std::vector<double> &x, const std::vector<double> &y,
             std::vector<double> &tmp) {
  multiply(d, d.M, y, tmp);
  return dot(static_cast<int64_t>(x.size()), x.data(), tmp.data());
}

}  // namespace

CriticalStep estimate_omega_max(Discretization &d, int solver, bool every_point_active) {
  // (as the assembly refuses operators that overflow: ND_ERR_MATERIAL)
  static const char *const out_of_range =
      "the largest frequency squared, K/M, overflows: the density is too small for the stiffness on this mesh "
      "(or the stiffness too large): rescale the units";
  const size_t n = static_cast<size_t>(d.dofs.n_free);
  const int max_iter = static_cast<int>(std::min<size_t>(n, 80));
  std::vector<std::vector<double>> Q;  // M-orthonormal Lanczos vectors
  std::vector<double> alpha, beta, w(n), z(n), tmp(n), r(n);
  // a fixed start that excites every mode (no symmetry of the mesh cancels it)
  for (size_t i = 0; i < n; ++i) r[i] = 1.0 + 0.5 * std::sin(1.7 * static_cast<double>(i) + 0.3);
  // massless DOFs (mass redistribution) held fixed: M has no norm there, and
  // mass_solve keeps them at 0, so the iteration stays on the others
  for (size_t i = 0; i < d.massless.size(); ++i)
    if (d.massless[i]) r[i] = 0;
  double b = std::sqrt(m_dot(d, r, r, tmp)), theta_max = 0, bound = 0, previous = -1;
  int j = 0;
  for (; j < max_iter; ++j) {
    for (double &v : r) v /= b;
    Q.push_back(r);
    apply(d, Q[j], z, every_point_active);
    alpha.push_back(dot(static_cast<int64_t>(n), Q[j].data(), z.data()));
    if (!std::all_of(z.begin(), z.end(), [](double x) { return std::isfinite(x); }))
      fail(ND_ERR_MATERIAL, out_of_range);
    w = z;
    d.mass_solve(w.data(), solver);  // w = M^-1 (K + T) q_j
    // full reorthogonalization, classical Gram-Schmidt twice ("twice is
    // enough"): one product M w a pass, not one per Lanczos vector (that
    // made the estimate O(k^2) products: 18 s on ball_h2 P2, 90k DOFs)
    std::vector<double> c(Q.size());
    for (int pass = 0; pass < 2; ++pass) {
      multiply(d, d.M, w, tmp);
      for (size_t k = 0; k < Q.size(); ++k) c[k] = dot(static_cast<int64_t>(n), Q[k].data(), tmp.data());
      for (size_t k = 0; k < Q.size(); ++k)
        for (size_t i = 0; i < n; ++i) w[i] -= c[k] * Q[k][i];
    }
    b = std::sqrt(std::max(0.0, m_dot(d, w, w, tmp)));
    // (a mass so small, or a stiffness so large, against the other that
    // K/M leaves the doubles: no step is small enough to say)
    if (!std::isfinite(alpha.back()) || !std::isfinite(b)) fail(ND_ERR_MATERIAL, out_of_range);
    // the largest Ritz value and its residual bound b |s_last|
    const int m = j + 1;
    std::vector<double> diag(alpha), off(beta), vec(static_cast<size_t>(m * m));
    if (lapack::dstev('V', m, diag.data(), off.data(), vec.data(), m) != 0)
      fail(ND_ERR_INTERNAL, "the Lanczos tridiagonal eigenproblem failed");
    theta_max = diag[m - 1];
    bound = b * std::fabs(vec[static_cast<size_t>((m - 1) * m + (m - 1))]);
    // at least min(n, 30) steps: a start vector poor in the top mode can
    // make the Ritz value settle on the second one for a while, with a small
    // residual (seen on a 4 x 4 rectangle)
    const bool settled = j + 1 >= std::min<int>(max_iter, 30) && std::fabs(theta_max - previous) <= 1e-10 * theta_max &&
                         bound <= 1e-6 * theta_max;
    if (!(b > 1e-14 * std::fabs(theta_max)) || settled) break;
    previous = theta_max;
    beta.push_back(b);
    r = w;
  }
  if (!std::isfinite(theta_max)) fail(ND_ERR_MATERIAL, out_of_range);
  if (!(theta_max > 0))
    fail(ND_ERR_MATERIAL, "the largest frequency squared, K/M, is " + std::to_string(theta_max) +
                              ": the stiffness is too small for the density on this mesh: rescale the units");
  return CriticalStep{std::sqrt(theta_max + bound), std::sqrt(theta_max), j + 1};
}

}  // namespace nd
