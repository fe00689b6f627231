// The critical time step of the explicit schemes (docs/design.md §3b.4): they are
// stable for omega_max tau below a limit of the scheme (2 for the central
// difference), omega_max^2 the largest eigenvalue of
//   (K_Theta + T_c) x = lambda M x,   T_c = sum_q (w_q/gamma_q) sym(b_q p_q^T),
// T_c the contact tangent with every point active (its symmetric part when
// Theta != 1, where b_q != p_q). Estimated by Lanczos in the M inner product
// with full reorthogonalization, from a fixed start vector. The same for
// the free motion (no point active, T_c = 0): the set-up refuses a step
// above its limit, which no active set can make stable (docs/design.md §3b.4).
#pragma once
#include "solve/operators.hpp"

namespace nd {

struct CriticalStep {
  double omega_max;  // the estimate of sqrt(lambda_max): Ritz value plus its residual bound
  double omega_low;  // sqrt of the largest Ritz value: at most sqrt(lambda_max)
  int iterations;
};

// every_point_active: with T_c (the critical step's estimate), else K_Theta alone
CriticalStep estimate_omega_max(Discretization &d, int solver, bool every_point_active = true);

}  // namespace nd
