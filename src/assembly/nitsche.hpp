// K_Theta = K - Theta sum_q w_q gamma_q s_q^T s_q (docs/design.md §2): the part of the
// Nitsche term that is present whether or not a point is in contact.
#pragma once
#include "assembly/contact.hpp"
#include "linalg/csr.hpp"

namespace nd {

// Theta = 0 drops the s_q^T s_q term entirely (K_Theta = K).
Csr assemble_k_theta(const Csr &K, const ContactPoints &cp, double theta);
// K <- K - Theta sum_q w_q gamma_q s_q^T s_q in place, over the points
// flagged in `points` (1 per contact point; null: all).
void add_nitsche_terms(Csr &K, const ContactPoints &cp, double theta, const std::vector<char> *points);

}  // namespace nd
