#include "assembly/redistribution.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "linalg/lapack.hpp"
#include "nitschedyn.h"

namespace nd {

std::vector<char> contact_nodes(const Space &s, const std::vector<ContactPlane> &planes) {
  std::vector<int> regions;
  for (const ContactPlane &pl : planes) regions.push_back(pl.region);
  return contact_nodes(s, regions);
}

std::vector<char> contact_nodes(const Space &s, const std::vector<int> &regions) {
  std::vector<char> on(static_cast<size_t>(s.n_nodes), 0);
  for (int region : regions)
    for (int64_t b : s.mesh->regions.at(region))
      for (int64_t node : s.facet_nodes(s.mesh->boundary[b])) on[node] = 1;
  return on;
}

namespace {

// A^T B C on small row-major matrices
std::vector<double> at_b_c(int m, int n, int p, const double *A, const double *B, const double *C) {
  // A: m x n, B: m x m, C: m x p -> n x p
  std::vector<double> BC(static_cast<size_t>(m * p), 0.0), out(static_cast<size_t>(n * p), 0.0);
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < p; ++j) BC[i * p + j] += B[i * m + k] * C[k * p + j];
  for (int i = 0; i < m; ++i)
    for (int a = 0; a < n; ++a)
      for (int j = 0; j < p; ++j) out[a * p + j] += A[i * n + a] * BC[i * p + j];
  return out;
}

}  // namespace

void redistribute_element_mass(const Space &s, int64_t cell, const std::vector<char> &on_contact, std::vector<double> &me) {
  const int nb = s.basis_of(cell).n, d = s.dim, m = d + 1;
  const int64_t *nodes = s.nodes_of(cell);
  std::vector<int> I;
  for (int i = 0; i < nb; ++i)
    if (!on_contact[nodes[i]]) I.push_back(i);
  const int k = static_cast<int>(I.size());
  if (k == nb) return;
  if (k == 0)
    fail(ND_ERR_VALUE, "mass redistribution: every node of cell " + std::to_string(cell) +
                           " lies on the contact boundary, so its mass has nowhere to go; refine the mesh");
  // affine functions at the nodes, centred on I's centroid and scaled by h
  // (the centring puts the constants in P_I's row space: the mass is kept)
  double c[3] = {0, 0, 0};
  for (int i : I)
    for (int a = 0; a < d; ++a) c[a] += s.node_x(nodes[i])[a] / k;
  const double h = s.mesh->cell_diameter(cell);
  std::vector<double> P(static_cast<size_t>(nb * m)), PI(static_cast<size_t>(k * m)), MII(static_cast<size_t>(k * k));
  for (int i = 0; i < nb; ++i) {
    P[i * m] = 1;
    for (int a = 0; a < d; ++a) P[i * m + 1 + a] = (s.node_x(nodes[i])[a] - c[a]) / h;
  }
  for (int r = 0; r < k; ++r) {
    std::copy(&P[I[r] * m], &P[I[r] * m] + m, &PI[r * m]);
    for (int q = 0; q < k; ++q) MII[r * k + q] = me[I[r] * nb + I[q]];
  }
  const std::vector<double> G = at_b_c(nb, m, m, P.data(), me.data(), P.data());
  const std::vector<double> H = at_b_c(k, m, m, PI.data(), MII.data(), PI.data());
  // row space of P_I: eigenvectors of P_I^T P_I with non-zero eigenvalues
  std::vector<double> V(static_cast<size_t>(m * m));
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      double x = 0;
      for (int r = 0; r < k; ++r) x += PI[r * m + a] * PI[r * m + b];
      V[a * m + b] = x;
    }
  std::vector<double> ev(static_cast<size_t>(m));
  if (lapack::dsyev_row_major('V', m, V.data(), ev.data()) != 0)
    fail(ND_ERR_INTERNAL, "mass redistribution: the eigenproblem of the nodes' moments failed");
  std::vector<int> kept;  // eigenpairs spanning the row space
  for (int a = 0; a < m; ++a)
    if (ev[a] > 1e-10 * ev[m - 1]) kept.push_back(a);
  const int r = static_cast<int>(kept.size());
  // L = pinv(P_I) = Q diag(1/ev) Q^T P_I^T (m x k);  G_r, H_r: G, H on the row space
  std::vector<double> L(static_cast<size_t>(m * k), 0.0), Gr(static_cast<size_t>(r * r), 0.0), Hr(Gr);
  for (int a = 0; a < m; ++a)
    for (int q = 0; q < k; ++q)
      for (int e = 0; e < r; ++e) {
        const int j = kept[e];
        double qp = 0;  // (Q^T P_I^T)_{e,q}
        for (int b = 0; b < m; ++b) qp += V[b * m + j] * PI[q * m + b];
        L[a * k + q] += V[a * m + j] / ev[j] * qp;
      }
  for (int e = 0; e < r; ++e)
    for (int f = 0; f < r; ++f)
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) {
          const double qq = V[a * m + kept[e]] * V[b * m + kept[f]];
          Gr[e * r + f] += qq * G[a * m + b];
          Hr[e * r + f] += qq * H[a * m + b];
        }
  // alpha = min(1, 1/lambda_max) with H_r x = lambda G_r x (G_r > 0: the mass is positive)
  std::vector<double> lam(static_cast<size_t>(r));
  if (lapack::dsygv_values_row_major(1, r, Hr.data(), Gr.data(), lam.data()) != 0)
    fail(ND_ERR_INTERNAL, "mass redistribution: the moments' eigenproblem failed");
  const double alpha = lam[r - 1] > 1 ? 1 / lam[r - 1] : 1.0;
  std::vector<double> D(static_cast<size_t>(m * m));
  for (int i = 0; i < m * m; ++i) D[i] = G[i] - alpha * H[i];
  // L^T D L: L is m x k, so it is L as "A" (rows m) in at_b_c
  const std::vector<double> C = at_b_c(m, k, k, L.data(), D.data(), L.data());
  std::fill(me.begin(), me.end(), 0.0);
  for (int p = 0; p < k; ++p)
    for (int q = 0; q < k; ++q)  // symmetrized: bitwise symmetric M
      me[I[p] * nb + I[q]] = alpha * 0.5 * (MII[p * k + q] + MII[q * k + p]) + 0.5 * (C[p * k + q] + C[q * k + p]);
}

}  // namespace nd
