// The reference square and cube [0,1]^dim: the Q1 and Q2 Lagrange bases as
// tensor products of 1D Lagrange polynomials, and tensor Gauss rules.
#include <vector>

#include "fem/simplex.hpp"
#include "mesh/cell_shape.hpp"

namespace nd {
namespace {

// the 1D Lagrange polynomial with node index i (0 at 0, 1 at 1, 2 at 1/2) of
// degree p, and its derivative, at t
double lagrange1d(int p, int i, double t) {
  if (p == 1) return i == 0 ? 1 - t : t;
  return i == 0 ? (2 * t - 1) * (t - 1) : i == 1 ? t * (2 * t - 1) : 4 * t * (1 - t);
}
double lagrange1d_derivative(int p, int i, double t) {
  if (p == 1) return i == 0 ? -1.0 : 1.0;
  return i == 0 ? 4 * t - 3 : i == 1 ? 4 * t - 1 : 4 - 8 * t;
}

}  // namespace

void cube_nodes(int dim, int degree, signed char *index) {
  int n = 0;
  auto add = [&](const int *at) {
    for (int k = 0; k < 3; ++k) index[n * 3 + k] = static_cast<signed char>(k < dim ? at[k] : 0);
    ++n;
  };
  for (int v = 0; v < cube::n_vertices(dim); ++v) add(cube::kCorner[v]);
  if (degree == 1) return;
  for (int e = 0; e < cube::n_edges(dim); ++e) {  // 2 where the edge's vertices differ
    const int *a = cube::kCorner[cube::kEdge[e][0]], *b = cube::kCorner[cube::kEdge[e][1]];
    const int at[3] = {a[0] == b[0] ? a[0] : 2, a[1] == b[1] ? a[1] : 2, a[2] == b[2] ? a[2] : 2};
    add(at);
  }
  if (dim == 3)
    for (int f = 0; f < cube::n_facets(dim); ++f) {  // face xi_axis = side
      int at[3] = {2, 2, 2};
      at[f / 2] = f % 2;
      add(at);
    }
  const int centre[3] = {2, 2, 2};
  add(centre);
}

void Lagrange::cube_values(const double *xi, double *phi) const {
  for (int i = 0; i < n; ++i) {
    double v = 1;
    for (int k = 0; k < dim; ++k) v *= lagrange1d(degree, index_[i * 3 + k], xi[k]);
    phi[i] = v;
  }
}

void Lagrange::cube_gradients(const double *xi, double *dphi) const {
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) {
      double v = 1;
      for (int l = 0; l < dim; ++l)
        v *= l == k ? lagrange1d_derivative(degree, index_[i * 3 + l], xi[l]) : lagrange1d(degree, index_[i * 3 + l], xi[l]);
      dphi[i * dim + k] = v;
    }
}

QuadratureRule cube_rule(int dim, int degree) {
  QuadratureRule r;
  r.dim = dim;
  const int n = degree / 2 + 1;  // n Gauss points: exact to degree 2n - 1
  std::vector<double> g, w;
  gauss_legendre01(n, g, w);
  const int total = dim == 1 ? n : dim == 2 ? n * n : n * n * n;
  for (int idx = 0; idx < total; ++idx) {
    const int i[3] = {idx % n, (idx / n) % n, idx / (n * n)};
    double weight = 1;
    for (int k = 0; k < dim; ++k) {
      r.points.push_back(g[i[k]]);
      weight *= w[i[k]];
    }
    r.weights.push_back(weight);
  }
  return r;
}

}  // namespace nd
