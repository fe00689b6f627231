// The reference cells: the simplex with its affine map to a mesh cell, the
// P1/P2 Lagrange basis in barycentric coordinates and exact quadrature rules;
// the square and cube [0,1]^dim with their multilinear map and the Q1/Q2
// tensor-product basis (fem/cube.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nd {

struct Mesh;

// The map from the reference cell onto cell c; J = dx/dxi (dim x dim,
// row-major). A simplex's is affine, x = x0 + J xi; a quadrilateral's or
// hexahedron's multilinear, J, Jinv and det holding their values at the last
// point given to at() (at construction: the reference centre).
struct CellMap {
  int dim;
  bool affine;
  double x0[3];
  double J[9];
  double Jinv[9];
  double det;
  CellMap(const Mesh &m, int64_t c);
  // J, Jinv, det at xi (nothing to do for a simplex)
  void at(const double *xi) {
    if (!affine) multilinear_at(xi);
  }
  // grad_x = J^{-T} grad_xi
  void physical_gradient(const double *grad_xi, double *grad_x) const;
  void to_physical(const double *xi, double *x) const;

 private:
  const double *corners_[8];
  void multilinear_at(const double *xi);
  void invert();
};

// Lagrange basis of degree 1 or 2 on the reference cell of a cell type
// (ND_CELL_LIST). Simplex, local order: the dim+1 vertices, then (P2) the
// edges (i,j), i<j, lexicographically. Square and cube (Q1, Q2, tensor
// products): the 2^dim vertices, then (Q2) the edges in cube::kEdge's order,
// the faces of a cube (its facets' order) and the centre.
struct Lagrange {
  int dim, degree, n;  // n = number of local basis functions
  int cell_type = 0;
  Lagrange(int dim, int degree, int cell_type = 0);
  void values(const double *xi, double *phi) const;
  void gradients(const double *xi, double *dphi) const;  // n x dim, row-major
  // local vertices of local edge e (P2)
  static void edge_vertices(int dim, int e, int &a, int &b);
  static int n_edges(int dim) { return dim * (dim + 1) / 2; }
  // Q: node i's position along axis k: 0 at 0, 1 at 1, 2 at 1/2
  int tensor_index(int i, int k) const { return index_[i * 3 + k]; }

 private:
  signed char index_[27 * 3] = {};
  void cube_values(const double *xi, double *phi) const;
  void cube_gradients(const double *xi, double *dphi) const;
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
// A rule exact for polynomials of the given degree in each variable on
// [0,1]^dim: the tensor product of Gauss-Legendre rules.
QuadratureRule cube_rule(int dim, int degree);
// The Q1/Q2 nodes' positions on [0,1]^dim (Lagrange::tensor_index), 3 a node.
void cube_nodes(int dim, int degree, signed char *index);
// Gauss-Legendre on [0, 1] with n points.
void gauss_legendre01(int n, std::vector<double> &x, std::vector<double> &w);

}  // namespace nd
