// The reference simplex: its affine map to a mesh cell, the P1/P2 Lagrange
// basis in barycentric coordinates, and exact quadrature rules.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nd {

struct Mesh;

// x = x0 + J xi on cell c; J = dx/dxi (dim x dim, row-major).
struct AffineMap {
  int dim;
  double x0[3];
  double J[9];
  double Jinv[9];
  double det;
  AffineMap(const Mesh &m, int64_t c);
  // grad_x = J^{-T} grad_xi
  void physical_gradient(const double *grad_xi, double *grad_x) const;
  void to_physical(const double *xi, double *x) const;
};

// Lagrange basis of degree 1 or 2 on the reference dim-simplex. Local order:
// the dim+1 vertices, then (P2) the edges (i,j), i<j, lexicographically.
struct Lagrange {
  int dim, degree, n;  // n = number of local basis functions
  Lagrange(int dim, int degree);
  void values(const double *xi, double *phi) const;
  void gradients(const double *xi, double *dphi) const;  // n x dim, row-major
  // local vertices of local edge e (P2)
  static void edge_vertices(int dim, int e, int &a, int &b);
  static int n_edges(int dim) { return dim * (dim + 1) / 2; }
};

// A rule exact for polynomials of the given degree on the reference simplex
// {xi_k >= 0, sum xi_k <= 1} of dimension 0..3 (dimension 0: one point,
// weight 1). Built from Gauss-Legendre rules through the collapsed (Duffy)
// map, so that any degree is available without tables.
struct QuadratureRule {
  int dim = 0;
  std::vector<double> points;  // n * dim
  std::vector<double> weights; // sum = 1/dim!
  size_t size() const { return weights.size(); }
};
QuadratureRule simplex_rule(int dim, int degree);
// Gauss-Legendre on [0, 1] with n points.
void gauss_legendre01(int n, std::vector<double> &x, std::vector<double> &w);

}  // namespace nd
