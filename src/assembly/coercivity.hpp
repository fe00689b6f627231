// The coercivity limit of Nitsche's term (docs/design.md §3b.1). K_Theta is positive
// semi-definite if, on every cell K owning contact points,
//   K_e - Theta gamma0 h_K sum_{q in K} w_q s_q s_q^T >= 0
// (h_K E/E_K in a cell of another material than the default, §10.6),
// i.e. Theta gamma0 <= 1/lambda_K, lambda_K the largest eigenvalue of
// h_K sum_q w_q s_q s_q^T relative to K_e (on the complement of K_e's kernel:
// s_q vanishes on rigid motions). gamma0* = min_K 1/lambda_K is a sufficient
// bound, cheap (a dense eigenproblem of at most 30 unknowns per contact cell).
#pragma once
#include <string>

#include "assembly/contact.hpp"
#include "assembly/material.hpp"
#include "fem/space.hpp"

namespace nd {

// gamma0* for Theta = 1 (for Theta > 0 the limit is gamma0*/Theta); +infinity
// without contact points. The rows s_q and the weights w_q do not depend on
// gamma0, so this can be computed before gamma0 is chosen.
double gamma0_limit(const Space &s, const DofMap &dofs, const CellMaterials &mat, const ContactPoints &cp);

// What every refusal of a gamma0 too large says: "gamma0 <= X is safe
// (...)", X = gamma0*/Theta with 6 significant digits, the bound that
// nd_get_scalar(ND_GAMMA0_LIMIT) reports (or that no gamma0 > 0 is, when it
// is 0). Empty where gamma0 cannot make K_Theta indefinite (Theta <= 0) or
// there is no finite bound (no contact points).
std::string safe_gamma0(double theta, double limit_at_theta_1);

}  // namespace nd
