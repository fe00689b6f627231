#include "fem/facet.hpp"

#include <cmath>

namespace nd {

std::vector<FacetPoint> facet_quadrature(const Mesh &m, const Facet &f, int degree) {
  const int d = m.dim;
  const QuadratureRule rule = simplex_rule(d - 1, degree);
  // local vertices of the facet in the cell, and its edge vectors
  int local[3], k = 0;
  for (int i = 0; i <= d; ++i)
    if (i != f.opposite) local[k++] = i;
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
