// Mass redistribution (Khenous-Laborde-Renard 2008): the FE nodes of the
// contact facets get no mass; each cell touching them moves its mass to its
// other nodes. Per cell, with I its other nodes and P the affine functions
// (1, x) at the nodes (x centred on I's centroid), the new element mass is
//   M'_II = alpha M_II + L^T (G - alpha H) L,   M'_C. = M'_.C = 0,
//   G = P^T M P,  H = P_I^T M_II P_I,  L = pinv(P_I),
// alpha in (0, 1] the largest value keeping G - alpha H >= 0 on the row space
// of P_I. Then p^T M' q = p^T M q for every pair of affine functions p, q whose
// coefficients lie in that row space: the constants always (mass), and the
// linear functions along the directions the nodes I span (all of them when I
// spans R^d affinely, e.g. every P2 cell with one contact facet): first and
// second moments. M' is symmetric positive definite on I (alpha M_II > 0).
#pragma once
#include <vector>

#include "assembly/contact.hpp"
#include "fem/space.hpp"

namespace nd {

// 1 for the FE nodes on the facets of the planes' regions, else 0 (n_nodes).
std::vector<char> contact_nodes(const Space &s, const std::vector<ContactPlane> &planes);
// the same for the facets of these regions
std::vector<char> contact_nodes(const Space &s, const std::vector<int> &regions);

// Replaces the element mass `me` (nb x nb, row-major) of `cell` by the
// redistributed one; unchanged when the cell has no contact node. Throws
// ND_ERR_VALUE when every node of the cell is a contact node.
void redistribute_element_mass(const Space &s, int64_t cell, const std::vector<char> &on_contact, std::vector<double> &me);

}  // namespace nd
