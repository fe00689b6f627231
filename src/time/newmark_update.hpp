// The Newmark(beta, gamma) updates, shared by Newmark and generalized-alpha:
//   A^{n+1} = (U^{n+1} - U^n)/(beta tau^2) - V^n/(beta tau) - (1/(2 beta) - 1) A^n
//   V^{n+1} = V^n + tau ((1 - gamma) A^n + gamma A^{n+1})
#pragma once

#include "time/state.hpp"

namespace nd {

// V^{n+1} from A^n and A^{n+1} (the explicit scheme's, A^{n+1} solved)
void newmark_velocity(double gamma, double tau, const State &old, State &next);
// A^{n+1} and V^{n+1} from U^{n+1}: one pass, four rows per lane group
// with AVX2 (common/simd.hpp; the same bits: a division or product per
// lane is the scalar one; the division was most of the update's time)
void newmark_update(double beta, double gamma, double tau, const State &old, State &next);

}  // namespace nd
