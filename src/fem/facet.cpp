#include "fem/facet.hpp"

#include <cmath>

#include "mesh/cell_shape.hpp"

namespace nd {
namespace {

// Facet 2 axis + side of a quadrilateral or hexahedron: the face xi_axis =
// side, its other axes in increasing order taking the rule's coordinates; the
// measure factor |dx/du| (2D) or |dx/du x dx/dv| (3D) at each point, one more
// degree per variable for a hexahedron's bilinear face.
std::vector<FacetPoint> cube_facet_quadrature(const Mesh &m, const Facet &f, int degree) {
  const int d = m.dim, axis = f.local / 2;
  const QuadratureRule rule = cube_rule(d - 1, degree + d - 2);
  const double *corners[8];
  for (int v = 0; v < m.cell_vertices(f.cell); ++v) corners[v] = m.x(m.cell(f.cell)[v]);
  int free_axes[2] = {0, 0};
  for (int k = 0, j = 0; k < d; ++k)
    if (k != axis) free_axes[j++] = k;
  std::vector<FacetPoint> pts(rule.size());
  for (size_t q = 0; q < rule.size(); ++q) {
    FacetPoint &p = pts[q];
    for (int c = 0; c < 3; ++c) p.xi[c] = p.x[c] = 0;
    p.xi[axis] = f.local % 2;
    for (int j = 0; j + 1 < d; ++j) p.xi[free_axes[j]] = rule.points[q * (d - 1) + j];
    cube::to_physical(d, corners, p.xi, p.x);
    double J[9];
    cube::jacobian(d, corners, p.xi, J);
    double t[2][3] = {};  // the tangents dx/du, dx/dv: J's columns of the free axes
    for (int j = 0; j + 1 < d; ++j)
      for (int c = 0; c < d; ++c) t[j][c] = J[c * d + free_axes[j]];
    double scale;
    if (d == 2) {
      scale = std::sqrt(t[0][0] * t[0][0] + t[0][1] * t[0][1]);
    } else {
      const double cx = t[0][1] * t[1][2] - t[0][2] * t[1][1];
      const double cy = t[0][2] * t[1][0] - t[0][0] * t[1][2];
      const double cz = t[0][0] * t[1][1] - t[0][1] * t[1][0];
      scale = std::sqrt(cx * cx + cy * cy + cz * cz);
    }
    p.weight = rule.weights[q] * scale;
  }
  return pts;
}

}  // namespace

std::vector<FacetPoint> facet_quadrature(const Mesh &m, const Facet &f, int degree) {
  if (!m.simplicial(f.cell)) return cube_facet_quadrature(m, f, degree);
  const int d = m.dim;
  const QuadratureRule rule = simplex_rule(d - 1, degree);
  // local vertices of the facet in the cell, and its edge vectors
  int local[3], k = 0;
  for (int i = 0; i <= d; ++i)
    if (i != f.local) local[k++] = i;
  const int64_t *cv = m.cell(f.cell);
  double E[3][3] = {};  // E[j] = x(local[j+1]) - x(local[0])
  for (int j = 0; j + 1 < d; ++j)
    for (int c = 0; c < d; ++c) E[j][c] = m.x(cv[local[j + 1]])[c] - m.x(cv[local[0]])[c];
  // measure factor sqrt(det(E^T E)): 1 for a point, length, twice the area
  double scale = 1;
  if (d == 2) {
    scale = std::sqrt(E[0][0] * E[0][0] + E[0][1] * E[0][1]);
  } else if (d == 3) {
    const double cx = E[0][1] * E[1][2] - E[0][2] * E[1][1];
    const double cy = E[0][2] * E[1][0] - E[0][0] * E[1][2];
    const double cz = E[0][0] * E[1][1] - E[0][1] * E[1][0];
    scale = std::sqrt(cx * cx + cy * cy + cz * cz);
  }
  std::vector<FacetPoint> pts(rule.size());
  for (size_t q = 0; q < rule.size(); ++q) {
    // barycentric coordinates in the cell: zero at the opposite vertex
    double lam[4] = {0, 0, 0, 0}, rest = 1;
    for (int j = 0; j + 1 < d; ++j) {
      lam[local[j + 1]] = rule.points[q * (d - 1) + j];
      rest -= lam[local[j + 1]];
    }
    lam[local[0]] = rest;
    FacetPoint &p = pts[q];
    for (int c = 0; c < 3; ++c) p.xi[c] = c < d ? lam[c + 1] : 0.0;
    for (int c = 0; c < 3; ++c) {
      p.x[c] = 0;
      if (c < d)
        for (int i = 0; i <= d; ++i) p.x[c] += lam[i] * m.x(cv[i])[c];
    }
    p.weight = rule.weights[q] * scale;
  }
  return pts;
}

}  // namespace nd
