#include "fem/simplex.hpp"

#include <cmath>

#include "mesh/cell_shape.hpp"
#include "mesh/geometry.hpp"
#include "mesh/mesh.hpp"

namespace nd {

CellMap::CellMap(const Mesh &m, int64_t c) : dim(m.dim), affine(m.simplicial(c)) {
  for (int i = 0; i < dim; ++i) x0[i] = m.x(m.cell(c)[0])[i];
  if (!affine) {
    for (int v = 0; v < m.cell_vertices(c); ++v) corners_[v] = m.x(m.cell(c)[v]);
    const double centre[3] = {0.5, 0.5, 0.5};
    multilinear_at(centre);
    return;
  }
  m.cell_jacobian(c, J);
  invert();
}

void CellMap::multilinear_at(const double *xi) {
  cube::jacobian(dim, corners_, xi, J);
  invert();
}

void CellMap::invert() {
  det = determinant(dim, J);
  if (dim == 1) {
    Jinv[0] = 1.0 / det;
  } else if (dim == 2) {
    Jinv[0] = J[3] / det;
    Jinv[1] = -J[1] / det;
    Jinv[2] = -J[2] / det;
    Jinv[3] = J[0] / det;
  } else {
    const double *a = J;
    Jinv[0] = (a[4] * a[8] - a[5] * a[7]) / det;
    Jinv[1] = (a[2] * a[7] - a[1] * a[8]) / det;
    Jinv[2] = (a[1] * a[5] - a[2] * a[4]) / det;
    Jinv[3] = (a[5] * a[6] - a[3] * a[8]) / det;
    Jinv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
    Jinv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
    Jinv[6] = (a[3] * a[7] - a[4] * a[6]) / det;
    Jinv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
    Jinv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
  }
}

void CellMap::physical_gradient(const double *gxi, double *gx) const {
  for (int i = 0; i < dim; ++i) {
    double s = 0;
    for (int k = 0; k < dim; ++k) s += Jinv[k * dim + i] * gxi[k];
    gx[i] = s;
  }
}

void CellMap::to_physical(const double *xi, double *x) const {
  if (!affine) {
    cube::to_physical(dim, corners_, xi, x);
    return;
  }
  for (int i = 0; i < dim; ++i) {
    double s = x0[i];
    for (int k = 0; k < dim; ++k) s += J[i * dim + k] * xi[k];
    x[i] = s;
  }
}

Lagrange::Lagrange(int d, int p, int type)
    : dim(d), degree(p), n(type ? (p == 1 ? 1 << d : d == 2 ? 9 : 27) : p == 1 ? d + 1 : d + 1 + n_edges(d)),
      cell_type(type) {
  if (type) cube_nodes(d, p, index_);
}

void Lagrange::edge_vertices(int d, int e, int &a, int &b) {
  for (int i = 0, k = 0; i <= d; ++i)
    for (int j = i + 1; j <= d; ++j, ++k)
      if (k == e) {
        a = i;
        b = j;
        return;
      }
  a = b = -1;
}

namespace {
// barycentric coordinates and their (constant) xi-gradients
void barycentric(int dim, const double *xi, double *lam, double *dlam) {
  lam[0] = 1;
  for (int k = 0; k < dim; ++k) {
    lam[0] -= xi[k];
    lam[k + 1] = xi[k];
  }
  for (int i = 0; i <= dim; ++i)
    for (int k = 0; k < dim; ++k) dlam[i * dim + k] = i == 0 ? -1.0 : (i == k + 1 ? 1.0 : 0.0);
}
}  // namespace

void Lagrange::values(const double *xi, double *phi) const {
  if (cell_type) {
    cube_values(xi, phi);
    return;
  }
  double lam[4], dlam[12];
  barycentric(dim, xi, lam, dlam);
  if (degree == 1) {
    for (int i = 0; i <= dim; ++i) phi[i] = lam[i];
    return;
  }
  for (int i = 0; i <= dim; ++i) phi[i] = lam[i] * (2 * lam[i] - 1);
  for (int e = 0; e < n_edges(dim); ++e) {
    int a, b;
    edge_vertices(dim, e, a, b);
    phi[dim + 1 + e] = 4 * lam[a] * lam[b];
  }
}

void Lagrange::gradients(const double *xi, double *dphi) const {
  if (cell_type) {
    cube_gradients(xi, dphi);
    return;
  }
  double lam[4], dlam[12];
  barycentric(dim, xi, lam, dlam);
  for (int i = 0; i <= dim; ++i)
    for (int k = 0; k < dim; ++k)
      dphi[i * dim + k] = degree == 1 ? dlam[i * dim + k] : (4 * lam[i] - 1) * dlam[i * dim + k];
  if (degree == 1) return;
  for (int e = 0; e < n_edges(dim); ++e) {
    int a, b;
    edge_vertices(dim, e, a, b);
    for (int k = 0; k < dim; ++k)
      dphi[(dim + 1 + e) * dim + k] = 4 * (lam[a] * dlam[b * dim + k] + lam[b] * dlam[a * dim + k]);
  }
}

namespace {
// The Legendre polynomial P_n and its derivative at z (|z| < 1), by the
// three-term recurrence.
struct LegendreValue {
  double p, dp;
};
LegendreValue legendre(int n, double z) {
  double p0 = 1, p1 = z;
  for (int k = 2; k <= n; ++k) {
    const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  return {p1, n * (z * p1 - p0) / (z * z - 1)};
}
}  // namespace

void gauss_legendre01(int n, std::vector<double> &x, std::vector<double> &w) {
  // Newton's method on the Legendre polynomial P_n from Chebyshev guesses.
  x.assign(n, 0);
  w.assign(n, 0);
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    double z = std::cos(pi * (i + 0.75) / (n + 0.5));
    for (int it = 0; it < 100; ++it) {
      const LegendreValue l = legendre(n, z);
      const double dz = l.p / l.dp;
      z -= dz;
      if (std::fabs(dz) < 1e-16) break;
    }
    const double dp = legendre(n, z).dp;  // at the root found
    x[i] = 0.5 * (1 - z);
    w[i] = 1.0 / ((1 - z * z) * dp * dp);  // 2/((1-z^2)P'^2), halved for [0,1]
  }
}

QuadratureRule simplex_rule(int dim, int degree) {
  QuadratureRule r;
  r.dim = dim;
  if (dim == 0) {
    r.weights = {1.0};
    return r;
  }
  // Collapsed map: xi_1 = u1, xi_2 = u2 (1-u1), xi_3 = u3 (1-u1)(1-u2), with
  // Jacobian (1-u1)^{dim-1} (1-u2)^{dim-2}: one more degree per collapse.
  const int n = (degree + dim) / 2 + 1;
  std::vector<double> g, w;
  gauss_legendre01(n, g, w);
  const int total = dim == 1 ? n : dim == 2 ? n * n : n * n * n;
  for (int idx = 0; idx < total; ++idx) {
    int i1 = idx % n, i2 = (idx / n) % n, i3 = idx / (n * n);
    double u1 = g[i1], u2 = dim > 1 ? g[i2] : 0, u3 = dim > 2 ? g[i3] : 0;
    double xi[3] = {u1, u2 * (1 - u1), u3 * (1 - u1) * (1 - u2)};
    double weight = w[i1];
    if (dim > 1) weight *= w[i2] * (1 - u1);
    if (dim > 2) weight *= w[i3] * (1 - u1) * (1 - u2);
    for (int k = 0; k < dim; ++k) r.points.push_back(xi[k]);
    r.weights.push_back(weight);
  }
  return r;
}

}  // namespace nd
