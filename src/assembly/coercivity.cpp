#include "assembly/coercivity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "assembly/bulk.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "linalg/lapack.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// Largest lambda with S x = lambda K x, K symmetric positive semi-definite
// (m x m, row-major, destroyed). Infinity if S does not vanish on K's kernel.
double largest_relative_eigenvalue(int m, std::vector<double> &K, const std::vector<double> &S) {
  std::vector<double> w(static_cast<size_t>(m));
  if (lapack::dsyev_row_major('V', m, K.data(), w.data()) != 0)
    fail(ND_ERR_INTERNAL, "the element stiffness eigenproblem failed");
  const double kmax = w[m - 1], tol = 1e-10 * kmax;
  // S in K's eigenbasis: B = V^T S V (columns of V are K's eigenvectors)
  std::vector<double> SV(static_cast<size_t>(m * m), 0.0), B(static_cast<size_t>(m * m), 0.0);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) SV[i * m + j] += S[i * m + k] * K[k * m + j];
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) B[i * m + j] += K[k * m + i] * SV[k * m + j];
  double smax = 0;
  for (int i = 0; i < m; ++i) smax = std::max(smax, std::fabs(B[i * m + i]));
  // the kernel modes: S must vanish there, else no gamma0 > 0 keeps K_e - gamma0 S >= 0
  int r = 0;
  while (r < m && w[r] <= tol) ++r;
  for (int i = 0; i < r; ++i)
    if (std::fabs(B[i * m + i]) > 1e-8 * smax) return std::numeric_limits<double>::infinity();
  // scaled reduced problem: Lambda^{-1/2} B_rr Lambda^{-1/2}
  const int n = m - r;
  if (n == 0) return 0;
  // (sqrt(w_i) sqrt(w_j), not sqrt(w_i w_j): with a tiny stiffness, E =
  // 1e-300, the product underflowed to 0 and C became 0/0)
  std::vector<double> C(static_cast<size_t>(n * n)), e(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      C[i * n + j] = B[(r + i) * m + (r + j)] / (std::sqrt(w[r + i]) * std::sqrt(w[r + j]));
  for (double x : C)
    if (!std::isfinite(x))
      fail(ND_ERR_MATERIAL, "the check of the Nitsche terms' coercivity over- or underflows with this material on "
                            "this mesh: rescale the units");
  if (lapack::dsyev_row_major('N', n, C.data(), e.data()) != 0)
    fail(ND_ERR_INTERNAL, "the element coercivity eigenproblem failed");
  return std::max(e[n - 1], 0.0);
}

}  // namespace

double gamma0_limit(const Space &s, const DofMap &dofs, const CellMaterials &mat, const ContactPoints &cp) {
  // the contact points of each cell
  std::map<int64_t, std::vector<size_t>> by_cell;
  for (size_t q = 0; q < cp.size(); ++q) by_cell[s.mesh->boundary[cp.facet[q]].cell].push_back(q);
  double limit = std::numeric_limits<double>::infinity();
  ElementMatrices em(s, mat);
  const int d = s.dim;
  for (const auto &[cell, points] : by_cell) {
    em.compute(cell);
    const int nb = em.nb;
    // the cell's free DOFs: local position -> free index
    const int64_t *nodes = s.nodes_of(cell);
    std::vector<int> local;  // positions (i*d + a) that are free
    std::map<int64_t, int> where;
    for (int i = 0; i < nb * d; ++i) {
      const int64_t f = dofs.free[nodes[i / d] * d + i % d];
      if (f < 0) continue;
      where[f] = static_cast<int>(local.size());
      local.push_back(i);
    }
    const int m = static_cast<int>(local.size());
    if (m == 0) continue;
    std::vector<double> K(static_cast<size_t>(m * m)), S(static_cast<size_t>(m * m), 0.0);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) K[i * m + j] = em.ke[local[i] * nb * d + local[j]];
    for (size_t q : points) {  // (a frictional point: its tangential tractions' terms too, as K_Theta has them)
      const double h = cp.gamma_length[q];  // gamma_q / gamma0: h_K (E / E_K with several materials)
      for (int k = 0; k < (cp.m > 1 && cp.friction[q] ? cp.m : 1); ++k) {
        const SparseRow &row = cp.s_row(q, k);
        // (a pair's point: s_q is the slave cell's, zeros on the master's DOFs)
        for (size_t a = 0; a < row.idx.size(); ++a) {
          if (row.val[a] == 0 && !where.count(row.idx[a])) continue;
          for (size_t b = 0; b < row.idx.size(); ++b) {
            if (row.val[b] == 0 && !where.count(row.idx[b])) continue;
            S[where.at(row.idx[a]) * m + where.at(row.idx[b])] += h * cp.w[q] * row.val[a] * row.val[b];
          }
        }
      }
    }
    const double lambda = largest_relative_eigenvalue(m, K, S);
    if (lambda > 0) limit = std::min(limit, 1 / lambda);
    if (std::isinf(lambda)) limit = 0;
  }
  return limit;
}

std::string safe_gamma0(double theta, double limit_at_theta_1) {
  if (!(theta > 0)) return std::string();
  const double bound = limit_at_theta_1 / theta;
  if (!(bound >= 0) || !std::isfinite(bound)) return std::string();
  if (bound == 0)  // some contact row does not vanish on the element's rigid motions
    return "no gamma0 > 0 is safe (the coercivity bound of K_Theta, ND_GAMMA0_LIMIT, is 0): use Theta <= 0";
  return "gamma0 <= " + num(bound) + " is safe (the coercivity bound of K_Theta, ND_GAMMA0_LIMIT)";
}

}  // namespace nd
