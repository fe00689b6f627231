// Quadrature on a boundary facet, expressed in the owning cell's reference
// coordinates so that basis values and gradients come from that cell.
#pragma once
#include <vector>

#include "fem/space.hpp"

namespace nd {

struct FacetPoint {
  double xi[3];  // reference coordinates in the owning cell
  double x[3];   // physical point
  double weight; // reference weight times the facet's measure factor
};

// A rule exact for polynomials of the given degree on the facet.
std::vector<FacetPoint> facet_quadrature(const Mesh &m, const Facet &f, int degree);

}  // namespace nd
